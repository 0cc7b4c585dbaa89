"""`python -m mbao orbit`: a camera's turn about its target, rendered as a sequence into an animated GIF."""

import re

import numpy as np
import pytest

import mbao
from command_line import output_lines, run_mbao


def test_orbit_writes_the_sequence_as_a_looping_gif(tmp_path):
    """Each GIF frame is the sequence's frame in 8-bit greys; frames alike in a
    row may be merged by Pillow, but the loop's length is frames / fps."""
    from PIL import Image, ImageSequence

    proc = run_mbao(
        "orbit",
        "--frames",
        6,
        "--fps",
        20,
        "--width",
        24,
        "--height",
        16,
        "--bounces",
        2,
        "--temporal",
        "-o",
        "turn.gif",
        cwd=tmp_path,
    )
    assert proc.returncode == 0, proc.stderr
    assert output_lines(proc.stdout)["wrote"].startswith("turn.gif")
    gif = Image.open(tmp_path / "turn.gif")
    assert gif.size == (24, 16) and gif.info["loop"] == 0
    frames = [(np.asarray(frame.convert("L")), frame.info["duration"]) for frame in ImageSequence.Iterator(gif)]
    assert sum(duration for _, duration in frames) == 6 * 50
    first = mbao.cornell_box().default_camera(24, 16)
    expected = next(mbao.render_sequence(mbao.cornell_box(), [first], width=24, height=16, bounces=2))
    np.testing.assert_array_equal(frames[0][0], np.round(expected.ao * 255).astype(np.uint8))


def test_orbit_cameras_turn_the_eye_about_the_target():
    from mbao.orbit import orbit_cameras

    start = mbao.Camera((0.0, 1.0, 2.0), (0.0, 1.0, 0.0), vfov_deg=45.0, max_distance=3.0)
    quarter_turns = orbit_cameras(start, 4)
    np.testing.assert_allclose(
        [c.eye for c in quarter_turns], [(0, 1, 2), (2, 1, 0), (0, 1, -2), (-2, 1, 0)], atol=1e-6
    )
    assert all(c.target == start.target and c.vfov_deg == 45.0 and c.max_distance == 3.0 for c in quarter_turns)
    with pytest.raises(ValueError, match="frames must be an integer >= 1"):
        orbit_cameras(start, 0)


@pytest.mark.parametrize(
    "args, message",
    [
        (["--fps", "0"], r"fps must be in \(0, 100\]"),
        (["--temporal", "--samples", "1"], r"temporal accumulation .* samples >= 2"),
    ],
    ids=["0 fps", "temporal with r = 1"],
)
def test_a_bad_orbit_gives_a_one_line_message_and_no_gif(tmp_path, args, message):
    proc = run_mbao("orbit", *args, "--frames", 2, "--width", 4, "--height", 4, "-o", "x.gif", cwd=tmp_path)
    assert proc.returncode != 0 and "Traceback" not in proc.stderr
    assert re.fullmatch("mbao: " + message + r".*\n", proc.stderr), proc.stderr
    assert not (tmp_path / "x.gif").exists()
