"""progress= has one meaning in every long call (issue 60): None, the
default, a bar where someone watches, for work that runs a while; False,
none; True, a bar; a callable progress(done, total)."""

import os
import pty
import subprocess
import sys

import numpy as np
import pytest

import mbao
from meshes import plane

SMALL = dict(width=16, height=16, samples=2)
TILED = mbao.Engine(tile_pixels=64)  # 16 x 16 pixels: 4 tiles


@pytest.fixture(scope="module")
def cornell():
    return mbao.cornell_box()


@pytest.fixture(scope="module")
def reference(cornell):
    return mbao.reference(
        cornell, target_error=0.5, width=8, height=8, samples=4, min_passes=2, max_distance=300.0, progress=False
    )


def floor():
    return mbao.Mesh(*plane(1.0, divisions=4))


# Each long call, run with progress=..., and the total its bar or callable counts to.
CALLS = {
    "render": (lambda scene, reference, progress: mbao.render(scene, engine=TILED, progress=progress, **SMALL), 4),
    "render_sequence": (
        lambda scene, reference, progress: list(
            mbao.render_sequence(scene, [None], engine=TILED, progress=progress, **SMALL)
        ),
        4,
    ),
    "bake": (lambda scene, reference, progress: mbao.bake(floor(), samples=2, progress=progress), 1),
    "render_many": (
        lambda scene, reference, progress: list(mbao.render_many([dict(scene=scene, **SMALL)] * 3, progress=progress)),
        3,
    ),
    "reference": (
        lambda scene, reference, progress: mbao.reference(
            scene, target_error=0.5, width=8, height=8, samples=4, min_passes=2, max_passes=8, progress=progress
        ),
        8,
    ),
    "convergence": (
        lambda scene, reference, progress: mbao.convergence(
            scene, ["b1", "b2 path"], reference, sample_counts=(1, 2), progress=progress, plot=False
        ),
        4,
    ),
}


@pytest.mark.parametrize("call", CALLS)
def test_a_callable_is_told_the_work_done_and_its_total(call, cornell, reference):
    run, total = CALLS[call]
    calls = []
    run(cornell, reference, lambda done, of: calls.append((done, of)))
    assert calls and calls[-1][0] == calls[-1][1]
    assert [done for done, _ in calls] == sorted(done for done, _ in calls)
    if call != "reference":  # the passes a reference needs are estimated as it goes
        assert calls[-1] == (total, total)


@pytest.mark.parametrize("call", CALLS)
def test_true_shows_a_bar_and_false_none(call, cornell, reference, capsys):
    run, _ = CALLS[call]
    capsys.readouterr()
    run(cornell, reference, True)
    assert "100%" in capsys.readouterr().err
    run(cornell, reference, False)
    assert capsys.readouterr().err == ""


@pytest.mark.parametrize("call", CALLS)
def test_none_shows_no_bar_where_nobody_watches(call, cornell, reference, capsys):
    """Under pytest stderr is captured, not a terminal."""
    run, _ = CALLS[call]
    capsys.readouterr()
    run(cornell, reference, None)
    assert capsys.readouterr().err == ""


@pytest.mark.parametrize("call", CALLS)
@pytest.mark.parametrize("value", ["yes", 1, [print]])
def test_anything_else_is_refused_with_the_meanings(call, cornell, reference, value):
    run, _ = CALLS[call]
    with pytest.raises(
        TypeError,
        match=r"progress must be None \(a bar on a terminal for long work\), False, True "
        r"or a callable progress\(done, total\)",
    ):
        run(cornell, reference, value)


def on_a_terminal(code):
    """What `python -c code` writes to its terminal: stderr and stdout are a pseudo-terminal's."""
    controller, terminal = pty.openpty()
    process = subprocess.Popen([sys.executable, "-c", code], stdin=subprocess.DEVNULL, stdout=terminal, stderr=terminal)
    os.close(terminal)
    written = b""
    while True:
        try:
            chunk = os.read(controller, 4096)
        except OSError:  # the terminal is closed once the process has exited
            break
        if not chunk:
            break
        written += chunk
    os.close(controller)
    assert process.wait(timeout=120) == 0, written.decode(errors="replace")
    return written.decode(errors="replace")


RENDER_TILES = (
    "import mbao\n"
    "mbao.render(mbao.cornell_box(), width=16, height=16, samples=2, "
    "engine=mbao.Engine(tile_pixels=64))\n"
)


def test_none_shows_a_bar_on_a_terminal_for_work_that_runs_a_while():
    """A render that takes longer than mbao's threshold (here set to 0 s)
    shows a bar; one that takes less shows nothing."""
    shown = on_a_terminal("import mbao._progress\nmbao._progress.SHOWN_AFTER_S = 0.0\n" + RENDER_TILES)
    assert "4/4" in shown
    assert "4/4" not in on_a_terminal(RENDER_TILES)


def test_a_bar_does_not_change_the_image(cornell):
    quiet = mbao.render(cornell, engine=TILED, progress=False, **SMALL)
    shown = mbao.render(cornell, engine=TILED, progress=True, **SMALL)
    np.testing.assert_array_equal(quiet.ao, shown.ao)


@pytest.mark.parametrize("quiet", [False, True])
def test_the_command_line_render_shows_a_bar_unless_quiet(quiet, tmp_path):
    argv = [
        "render",
        "--width",
        "16",
        "--height",
        "16",
        "--samples",
        "2",
        "--tile-pixels",
        "64",
        "-o",
        str(tmp_path / "ao.png"),
    ] + ["--quiet"] * quiet
    shown = on_a_terminal(
        "import mbao._progress\nmbao._progress.SHOWN_AFTER_S = 0.0\n"
        f"from mbao.cli import main\nraise SystemExit(main({argv!r}))\n"
    )
    assert ("4/4" in shown) != quiet
