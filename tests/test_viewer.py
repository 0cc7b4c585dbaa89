"""The live viewer's server, as a page talks to it (docs/viewer.md): what a
still view shows and how it refuses bad input (who may connect:
test_viewer_safety.py)."""

import asyncio
import json
import math
import pathlib
import re
import signal
import subprocess
import sys
import urllib.error
import urllib.request

import numpy as np
import pytest

import mbao
from mbao.viewer.session import to_8bit
from viewer_client import FRAME_TIMEOUT_S, connected, decode, run, served

SMALL = dict(width=48, height=40)


def test_a_still_view_after_k_frames_shows_render_sequences_last_image():
    settings = dict(SMALL, bounces=2, samples=4, frames=3)
    with served(**settings, denoise=True) as viewer:

        async def still():
            async with connected(viewer) as page:
                await page.send(type="set", camera=page.hello["home"])
                return await page.still_frame(3)

        header, payload = run(still())
        camera = viewer.home_camera
    *_, last = mbao.render_sequence(
        mbao.cornell_box(), [camera] * 3, denoise=True, **{k: v for k, v in settings.items() if k != "frames"}
    )
    assert header["final"] and header["format"] == "png"
    np.testing.assert_array_equal(decode(payload), to_8bit(last.ao))


def test_the_page_gets_the_8_bits_save_image_writes(tmp_path, rng):
    ao = rng.uniform(-0.1, 1.1, size=(7, 9)).astype(np.float32)
    ao[0, :3] = [0.5 / 255, 1.5 / 255, 254.5 / 255]  # halves: how they round matters
    mbao.save_image(tmp_path / "ao.png", ao)
    from PIL import Image

    np.testing.assert_array_equal(to_8bit(ao), np.asarray(Image.open(tmp_path / "ao.png")))


def test_a_moving_camera_gets_smaller_frames_until_it_stops():
    with served(width=256, height=256, bounces=1, samples=1, temporal=False) as viewer:

        async def frames():
            async with connected(viewer) as page:
                await page.send(type="set", camera=page.hello["home"], interactive=True)
                moving, _ = await page.until(lambda m, p: m["type"] == "frame")
                await page.send(type="set", interactive=False)
                still, _ = await page.until(lambda m, p: m["type"] == "frame" and not m["moving"])
                return moving, still

        moving, still = run(frames())
    assert moving["moving"] and moving["format"] == "jpeg" and moving["width"] < 256
    assert moving["height"] == pytest.approx(moving["width"], abs=1)
    assert (still["width"], still["height"]) == (256, 256) and still["final"]


BAD_MESSAGES = {
    "not JSON": ("{bad", "not JSON"),
    "not an object": ("[1, 2]", "JSON object"),
    "unknown type": (json.dumps({"type": "launch"}), "message type"),
    "unknown field": (json.dumps({"type": "set", "colour": 1}), "'colour'"),
    "short vector": (
        json.dumps({"type": "set", "camera": {"eye": [0, 0], "target": [0, 0, 1], "up": [0, 1, 0], "vfov_deg": 40}}),
        "camera eye",
    ),
    "NaN eye": (
        '{"type": "set", "camera": {"eye": [NaN, 0, 0], "target": [0, 0, 1], "up": [0, 1, 0], ' '"vfov_deg": 40}}',
        "finite",
    ),
    "degenerate camera": (
        json.dumps({"type": "set", "camera": {"eye": [0, 0, 0], "target": [0, 0, 0], "up": [0, 1, 0], "vfov_deg": 40}}),
        "eye",
    ),
    "unknown setting": (json.dumps({"type": "set", "settings": {"brightness": 2}}), "'brightness'"),
    "wrong type": (json.dumps({"type": "set", "settings": {"bounces": "two"}}), "bounces must be an integer"),
    "unknown method": (json.dumps({"type": "set", "settings": {"method": "baked"}}), "method must be one of"),
    "pick outside": (json.dumps({"type": "pick", "x": 2, "y": 0.5}), "pick x"),
    "save what": (json.dumps({"type": "save", "what": "gif"}), "what must be one of"),
}


@pytest.mark.parametrize("text, expected", BAD_MESSAGES.values(), ids=BAD_MESSAGES.keys())
def test_a_bad_message_gets_an_error_naming_it_and_the_view_goes_on(text, expected):
    with served(**SMALL, samples=2, frames=1) as viewer:

        async def exchange():
            async with connected(viewer) as page:
                await page.socket.send_str(text)
                error = await page.error()
                await page.send(type="set", camera=page.hello["home"])
                frame, _ = await page.until(lambda m, p: m["type"] == "frame")
                return error, frame

        error, frame = run(exchange())
    assert expected in error
    assert frame["final"]


def test_binary_input_gets_an_error():
    with served(**SMALL) as viewer:

        async def exchange():
            async with connected(viewer) as page:
                await page.socket.send_bytes(b"\x00\x01")
                return await page.error()

        assert "JSON text" in run(exchange())


def test_a_setting_the_core_refuses_is_shown_as_render_refuses_it():
    with pytest.raises(ValueError) as refused:
        mbao.render(mbao.cornell_box(), **SMALL, max_rays=1000)
    with served(**SMALL) as viewer:

        async def exchange():
            async with connected(viewer) as page:
                await page.send(type="set", settings={"max_rays": 1000})
                return await page.error()

        assert run(exchange()) == str(refused.value)


def test_two_clients_each_have_their_own_view():
    with served(**SMALL, samples=2, frames=1) as viewer:

        async def both():
            async with connected(viewer) as first, connected(viewer) as second:
                home = first.hello["home"]
                turned = dict(home, eye=[home["target"][0] + 700, home["target"][1], home["target"][2]])
                await first.send(type="set", camera=home)
                await second.send(type="set", camera=turned)
                return (await first.still_frame(1), await second.still_frame(1), home, turned)

        (first, first_image), (second, second_image), home, turned = run(both())
    assert first["camera"]["eye"] == pytest.approx(home["eye"])
    assert second["camera"]["eye"] == pytest.approx(turned["eye"])
    assert np.abs(decode(first_image).astype(int) - decode(second_image)).mean() > 5


def test_a_script_sets_every_pages_view():
    with served(**SMALL, samples=2, frames=1) as viewer:

        async def follow():
            async with connected(viewer) as page:
                await page.send(type="set", camera=page.hello["home"])
                await page.still_frame(1)
                await __import__("asyncio").to_thread(viewer.broadcast, settings={"bounces": 3})
                state, _ = await page.until(lambda m, p: m["type"] == "state")
                frame, _ = await page.still_frame(1)
                return state, frame

        state, frame = run(follow())
    assert state["settings"]["bounces"] == 3 and frame["final"]


def test_save_gives_the_image_with_coverage_and_the_camera(tmp_path):
    from PIL import Image

    with served(**SMALL, samples=2, frames=1, max_distance=math.inf) as viewer:

        async def save():
            async with connected(viewer) as page:
                await page.send(type="set", camera=page.hello["home"])
                _, image = await page.still_frame(1)
                await page.send(type="save", what="png")
                png = await page.until(lambda m, p: m["type"] == "file")
                await page.send(type="save", what="exr")
                exr = await page.until(lambda m, p: m["type"] == "file")
                await page.send(type="save", what="camera")
                camera = await page.until(lambda m, p: m["type"] == "file")
                return image, png, exr, camera

        image, (png_header, png), (exr_header, exr), (_, camera) = run(save())
    (tmp_path / png_header["name"]).write_bytes(png)
    saved = np.asarray(Image.open(tmp_path / "ao.png"))
    assert saved.shape == (40, 48, 2)  # grey and alpha
    np.testing.assert_array_equal(saved[..., 0], decode(image))
    assert (saved[..., 1] == 0).any() and (saved[..., 1] == 255).any()  # the box's front is open
    import OpenImageIO as oiio

    (tmp_path / exr_header["name"]).write_bytes(exr)
    floats = oiio.ImageBuf(str(tmp_path / "ao.exr"))
    assert floats.spec().channelnames == ("Y", "coverage")
    values = floats.get_pixels(oiio.FLOAT)
    np.testing.assert_array_equal(to_8bit(values[..., 0]), decode(image))
    np.testing.assert_array_equal(values[..., 1] > 0, saved[..., 1] > 0)
    (tmp_path / "camera.json").write_bytes(camera)
    loaded = mbao.Camera.load(str(tmp_path / "camera.json"))
    assert loaded.eye == pytest.approx(viewer.home_camera.eye) and "max_distance" not in json.loads(camera)


def test_a_pick_finds_the_point_under_the_cursor():
    """The point is the camera hit through that point of the image, as the G-buffer has it."""
    with served(**SMALL) as viewer:

        async def pick(points):
            async with connected(viewer) as page:
                picked = []
                for x, y in points:
                    await page.send(type="pick", x=x, y=y)
                    message, _ = await page.until(lambda m, p: m["type"] == "picked")
                    picked.append(message["point"])
                return picked

        pixels = [(0, 0), (20, 13), (30, 37), (10, 24)]
        picked = run(pick([((column + 0.5) / 48, (row + 0.5) / 40) for row, column in pixels]))
        hits = mbao.gbuffer(viewer.scene, camera=viewer.home_camera, **SMALL)
    assert hits.mask[[p[0] for p in pixels], [p[1] for p in pixels]].sum() >= 3
    for (row, column), point in zip(pixels, picked):
        if hits.mask[row, column]:
            np.testing.assert_allclose(point, hits.position[row, column], rtol=1e-4, atol=1e-2)
        else:
            assert point is None


def test_a_client_that_goes_stops_its_work():
    """Its frame, minutes of work, stops at its next tile: the next client's
    frame comes within the time limit, which the whole frame would exceed."""
    heavy = dict(width=1024, height=1024, bounces=3, samples=16)  # 4.6e9 rays: ten minutes on two cores
    with served(**heavy, frames=1) as viewer:

        async def leave():
            async with connected(viewer) as page:
                await page.send(type="set", camera=page.hello["home"])
                await asyncio.sleep(1)  # the frame is in flight

        async def next_client():
            async with connected(viewer) as page:
                await page.send(type="set", camera=page.hello["home"], settings={"width": 8, "height": 8})
                return await page.still_frame(1)

        run(leave())
        header, _ = run(next_client())
    assert header["width"] == 8 and not viewer.sessions


def test_the_command_prints_its_url_serves_the_page_and_stops_on_ctrl_c():
    repo = pathlib.Path(__file__).resolve().parents[1]
    process = subprocess.Popen(
        [sys.executable, "-m", "mbao", "view", "--no-browser", "--port", "0", "--width", "32", "--height", "32"],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
        cwd=repo,
    )
    try:
        url = None
        for line in process.stdout:
            if re.fullmatch(r"http://127\.0\.0\.1:\d+/\n", line):
                url = line.strip()
                break
        assert url, process.stderr.read()
        with urllib.request.urlopen(url, timeout=FRAME_TIMEOUT_S) as page:
            assert b'id="view"' in page.read()
    finally:
        process.send_signal(signal.SIGINT)
        _, stderr = process.communicate(timeout=FRAME_TIMEOUT_S)
    assert process.returncode == 0, stderr
    assert "Traceback" not in stderr


def test_a_busy_port_is_named():
    with served(**SMALL) as viewer:
        done = subprocess.run(
            [sys.executable, "-m", "mbao", "view", "--no-browser", "--port", str(viewer.port)],
            capture_output=True,
            text=True,
            timeout=FRAME_TIMEOUT_S,
        )
    assert done.returncode == 2
    assert f"127.0.0.1:{viewer.port}" in done.stderr and "Traceback" not in done.stderr


def test_hbao_with_the_gtao_fit_shows_the_fit_of_hbaos_image():
    with served(**SMALL, method="hbao+gtao", rho=0.6, max_distance=200.0) as viewer:

        async def still():
            async with connected(viewer) as page:
                await page.send(type="set", camera=page.hello["home"])
                return await page.still_frame(1)

        header, payload = run(still())
        hbao = mbao.render(viewer.scene, camera=viewer.home_camera, method="hbao", max_distance=200.0, **SMALL)
    fitted = np.where(hbao.mask, mbao.gtao_multibounce(np.clip(hbao.ao, 0, 1), 0.6), hbao.ao)
    assert header["final"] and (fitted > hbao.ao + 0.02).any()
    np.testing.assert_array_equal(decode(payload), to_8bit(fitted))


def test_a_views_handle_reads_sets_and_snapshots_outside_a_notebook():
    view = mbao.view(port=0, **SMALL, samples=2, frames=1)
    try:
        assert view.settings["samples"] == 2 and re.fullmatch(r"http://127\.0\.0\.1:\d+/", view.url)
        view.settings = {"bounces": 2}
        assert view.settings["bounces"] == 2
        with pytest.raises(ValueError, match="brightness"):
            view.settings = {"brightness": 1}
        with pytest.raises(TypeError, match="camera"):
            view.camera = 3
        snapshot = view.snapshot()  # no page yet: the view's first frame
        first = next(mbao.render_sequence(mbao.cornell_box(), [view.camera], **SMALL, samples=2, bounces=2))
        np.testing.assert_array_equal(snapshot.ao, first.ao)
    finally:
        view.close()


def test_an_unset_radius_is_the_home_cameras_suggestion(tmp_path):
    """A camera from the page carries the home camera's max_distance, as render's default radius (SPEC 1)."""
    home = mbao.cornell_box().default_camera(48, 40)
    path = tmp_path / "camera.json"
    path.write_text(
        json.dumps(
            dict(
                eye=list(home.eye),
                target=list(home.target),
                up=list(home.up),
                vfov_deg=home.vfov_deg,
                max_distance=120.0,
            )
        )
    )
    with served(camera=str(path), **SMALL, samples=2, temporal=False) as viewer:

        async def still():
            async with connected(viewer) as page:
                assert page.hello["scene"]["default_radius"] == 120.0
                await page.send(type="set", camera=page.hello["home"])
                frame = await page.still_frame(1)
                await page.send(type="save", what="camera")
                return frame, await page.until(lambda m, p: m["type"] == "file")

        (_, payload), (_, saved) = run(still())
    expected = mbao.render(mbao.cornell_box(), camera=mbao.Camera.load(str(path)), **SMALL, samples=2)
    assert expected.stats["max_distance"] == 120.0
    np.testing.assert_array_equal(decode(payload), to_8bit(expected.ao))
    assert json.loads(saved)["max_distance"] == 120.0


def test_a_fault_in_a_frame_is_shown_and_the_server_serves_on(monkeypatch):
    import mbao.viewer.session as session

    class Faulty(session.StillView):
        def next_frame(self, cancelled):
            if self.settings["bounces"] == 3:
                raise RuntimeError("a fault")
            return super().next_frame(cancelled)

    monkeypatch.setattr(session, "StillView", Faulty)
    with served(**SMALL, samples=2, frames=1) as viewer:

        async def exchange():
            async with connected(viewer) as page:
                await page.send(type="set", settings={"bounces": 3})
                error = await page.error()
                await page.send(type="set", settings={"bounces": 2})
                return error, await page.still_frame(1)

        error, (frame, _) = run(exchange())
    assert "internal error" in error and "a fault" in error and frame["final"]
