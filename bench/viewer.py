"""The live viewer in a real browser: frames per second while dragging, input to frame, a still view's error.

From the repository root, after `make build` (Debian's chromium and chromium-driver installed):
    .venv/bin/python bench/viewer.py --json bench/results/pocl-viewer.json
then `.venv/bin/python bench/report.py` puts its table into docs/performance.md.

Each scene is served by `mbao.viewer` on 127.0.0.1 (a thread of this process) and shown in headless
Chromium, driven through Selenium. bench/viewer_probe.js, loaded into the page, moves the camera with
pointer and key events dispatched to the page's own handlers, and logs each frame as it reaches the
image element with the state the page then gives (the frame's header: camera, size, frame_ms).

* Dragging (the built-in Cornell box, and Sponza from its camera.json at the radius it suggests; b = 1,
  one sample, no temporal accumulation, the moving frames' size the server's): after a 1 s warm-up drag,
  a 5 s drag in circles of 24 px (0.19 rad of orbit; a turn in 1.25 s, 120 px/s) with a pointer move
  every 1/60 s. The views stay near the home view: a long drag would orbit Sponza's camera out of the
  building.
  Frames per second are the frames the page received while the button was down. From the same drag,
  each move's latency: to the first frame showing it or a later move (the page sends only the latest).
* Input to frame (same settings): with the button held, 40 single moves of 6 px, right and back in turn,
  each after a pause of 0.15-0.45 s (seeded) and waiting for the frame whose camera is the move's: the
  time from the move's event to that frame's arrival (its decoding and paint not included).
* A still view (the Cornell box, b = 2, 4 samples of the default branching estimator, denoise and temporal
  accumulation on): a drag away, released, then the H key takes the camera home; each PNG the page shows
  in the next 10 s is decoded (/ 255) and compared, over the pixels that hit, with a converged reference
  of the home camera: mbao.reference, 64 paths a pass through the pixel centres, no denoising, until
  every covered pixel's standard error is at most --target-error (bench/denoise.py's, and its cache).
"""

import argparse
import base64
import contextlib
import datetime
import io
import json
import os
import pathlib
import random
import sys
import tempfile

import numpy as np
from PIL import Image

import mbao
from mbao.viewer import open_viewer
from mbao.viewer.server import BackgroundServer

from denoise import reference  # bench/denoise.py's: run as bench/viewer.py, bench/ is on the path

REPO = pathlib.Path(__file__).resolve().parent.parent
PROBE = pathlib.Path(__file__).with_name("viewer_probe.js")

SIZE = 512  # the view's width and height, as Table 1's frames
CORNELL = "cornell_box (built-in)"
MOTION = dict(bounces=1, samples=1, temporal=False)
STILL = dict(bounces=2, samples=4, denoise=True, temporal=True)
# Small circles about the home view, so that the frames are of the scene as its camera shows it.
DRAG = dict(seconds=5.0, hz=60, radius=24, period=1.25, after=1.0)
INPUTS, STEP_PX, PAUSES_S = 40, 6, (0.15, 0.45)
STILL_SECONDS = 10.0
TARGETS = {"drag_fps": 10, "input_to_frame_ms": 150, "rmse": 0.05, "rmse_within_s": 10}
# Every wait is bounded: for the page and its first frame, and for a drag's frames.
FRAME_TIMEOUT_S = 60
# A single move's frame that has not come by then counts as missing.
INPUT_TIMEOUT_S = 5


@contextlib.contextmanager
def chromium():
    """Headless Chromium, without its sandbox (which refuses to start as root), quit on leaving. Its
    temporary files go in a folder of its own, removed after: Chromium leaves its singleton-lock folders."""
    from selenium import webdriver
    from selenium.webdriver.chrome.service import Service

    with tempfile.TemporaryDirectory(prefix="mbao-chromium-") as folder:
        options = webdriver.ChromeOptions()
        options.binary_location = "/usr/bin/chromium"
        for argument in ("--headless=new", "--no-sandbox", "--disable-dev-shm-usage", "--window-size=1200,900"):
            options.add_argument(argument)
        driver = webdriver.Chrome(
            service=Service("/usr/bin/chromedriver", env={**os.environ, "TMPDIR": folder}), options=options
        )
        try:
            yield driver
        finally:
            driver.quit()


@contextlib.contextmanager
def page(driver, scene, **options):
    """The scene's view served on 127.0.0.1 and shown in the browser, its first frame come, the probe loaded."""
    viewer = open_viewer(scene, host="127.0.0.1", port=0, width=SIZE, height=SIZE, **options)
    server = BackgroundServer(viewer)
    try:
        driver.get(viewer.url)
        call(
            driver,
            "new Promise((resolve) => { const wait = () => (window.mbaoView && "
            "window.mbaoView.state().received > 0 ? resolve() : setTimeout(wait, 20)); wait(); })",
            FRAME_TIMEOUT_S,
        )
        driver.execute_script(PROBE.read_text())
        yield viewer
    finally:
        server.close()


def call(driver, expression, timeout_s):
    """The value of a JavaScript promise in the page, waited for at most timeout_s."""
    driver.set_script_timeout(timeout_s)
    return driver.execute_async_script(f"const done = arguments[arguments.length - 1]; ({expression}).then(done);")


def percentile(values, q):
    """The q-th percentile, interpolated; None where nothing was measured."""
    return float(np.percentile(values, q)) if values else None


def dragged(driver, values):
    """The probe's drag with these DRAG values."""
    arguments = ", ".join(str(values[k]) for k in ("seconds", "hz", "radius", "period", "after"))
    return call(driver, f"viewerProbe.drag({arguments})", values["seconds"] + values["after"] + FRAME_TIMEOUT_S)


def drag(driver):
    """Frames per second while dragging, their sizes and times, and each move's latency."""
    dragged(driver, dict(DRAG, seconds=1.0))  # a warm-up: the server sizes a moving frame from the last one's time
    result = dragged(driver, DRAG)
    frames, latencies = result["frames"], [ms for ms in result["latencies"] if ms is not None]
    return {
        "seconds": result["seconds"],
        "moves": result["moves"],
        "moves_per_s": result["moves"] / result["seconds"],
        "frames": result["received"],
        "fps": result["received"] / result["seconds"],
        "sizes": [[f["width"], f["height"]] for f in frames],
        "frame_ms": [f["frame_ms"] for f in frames],
        "median_width": percentile([f["width"] for f in frames], 50),
        "median_frame_ms": percentile([f["frame_ms"] for f in frames], 50),
        "latencies_ms": latencies,
        "latency_median_ms": percentile(latencies, 50),
        "latency_p90_ms": percentile(latencies, 90),
        "moves_without_frame": len(result["latencies"]) - len(latencies),
    }


def inputs(driver):
    """Single moves with the button held, each waited for: the median and 90th percentile of input to frame."""
    generator = random.Random(1)
    pauses = [round(generator.uniform(*PAUSES_S) * 1000) for _ in range(INPUTS)]
    results = call(
        driver,
        f"viewerProbe.inputs({pauses}, {STEP_PX}, {INPUT_TIMEOUT_S * 1000})",
        sum(pauses) / 1000 + INPUTS * INPUT_TIMEOUT_S + FRAME_TIMEOUT_S,
    )
    shown = [r for r in results if r is not None]
    latencies = [r["ms"] for r in shown]
    return {
        "inputs": INPUTS,
        "missing": INPUTS - len(shown),
        "latencies_ms": latencies,
        "median_ms": percentile(latencies, 50),
        "p90_ms": percentile(latencies, 90),
        "median_width": percentile([r["width"] for r in shown], 50),
        "median_frame_ms": percentile([r["frame_ms"] for r in shown], 50),
    }


def motion(driver, name, scene, camera, settings):
    """Dragging and single inputs on one scene."""
    with page(driver, scene, camera=camera, **settings):
        return {"scene": name, "settings": settings, "drag": drag(driver), "input_to_frame": inputs(driver)}


def decoded(data_url):
    """A frame's PNG as the page holds it (a data: URL), as values in [0, 1]."""
    payload = base64.b64decode(data_url.split(",", 1)[1])
    return np.asarray(Image.open(io.BytesIO(payload)), dtype=np.float64) / 255.0


def still(driver, converged):
    """The RMSE against the reference of each frame shown in the STILL_SECONDS after the camera stopped."""
    with page(driver, None, **STILL):
        result = call(driver, f"viewerProbe.stop({STILL_SECONDS})", STILL_SECONDS + FRAME_TIMEOUT_S)
    home = result["home"]
    reference_camera = converged.settings["camera"]
    if any(not np.allclose(home[key], reference_camera[key], rtol=1e-6) for key in ("eye", "target", "up")):
        raise SystemExit(f"viewer: the view's home camera {home} is not the reference's {reference_camera}")
    mask = converged.mask
    rows = []
    for frame in result["frames"]:
        if frame["camera"] != home:
            continue  # a frame of the drag away, sent before the key press reached the server
        error = decoded(frame["png"])[mask] - converged.ao[mask]
        rows.append({"t_s": frame["t"] / 1000, "frames": frame["frames"], "rmse": float(np.sqrt(np.mean(error**2)))})
    reached = next((row["t_s"] for row in rows if row["rmse"] <= TARGETS["rmse"]), None)
    return {
        "scene": CORNELL,
        "settings": STILL,
        "frames": rows,
        "seconds_to_target": reached,
        "rmse_at_end": rows[-1]["rmse"] if rows else None,
        "seconds": STILL_SECONDS,
        "covered": float(mask.mean()),
        "reference": converged.settings,
        "reference_noise": float(np.sqrt(np.mean(converged.standard_error[mask] ** 2))),
    }


def cpu_model():
    with open("/proc/cpuinfo") as file:
        return next(line.split(":", 1)[1].strip() for line in file if line.startswith("model name"))


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--json", required=True, help="where to write the results")
    parser.add_argument("--scenes", default=str(REPO.parent / "shared" / "scenes"), help="holds sponza/")
    parser.add_argument("--cache", default="out/references", help="where the reference is kept (bench/denoise.py's)")
    parser.add_argument("--target-error", type=float, default=0.01, help="the reference's standard error per pixel")
    args = parser.parse_args()
    sponza = pathlib.Path(args.scenes) / "sponza"
    # First, so that rendering it, once, is not measured with the browser.
    converged = reference(
        "cornell_box", mbao.cornell_box(), None, STILL["bounces"], None, args.target_error, args.cache
    )
    with chromium() as driver:
        scenes = [
            motion(driver, CORNELL, None, None, MOTION),
            motion(driver, "sponza", str(sponza / "scene.glb"), str(sponza / "camera.json"), MOTION),
        ]
        settled = still(driver, converged)
        browser = f"Chromium {driver.capabilities['browserVersion']}, headless"
    device = mbao.render(mbao.cornell_box(), width=1, height=1).stats["device"]  # as mbao_bench names it
    version = next(d.version for d in mbao.devices() if device.endswith(d.name))
    protocol = dict(drag=DRAG, inputs=INPUTS, step_px=STEP_PX, pauses_s=PAUSES_S, still_seconds=STILL_SECONDS)
    run = {
        "command": "bench/viewer.py " + " ".join(sys.argv[1:]),
        "device": device,
        "device_version": version,
        "date": datetime.date.today().isoformat(),
        "cpu": cpu_model(),
        "cores": os.cpu_count(),
        "browser": browser,
        "size": SIZE,
        "targets": TARGETS,
        "protocol": protocol,
        "viewer": {"motion": scenes, "still": settled},
    }
    pathlib.Path(args.json).write_text(json.dumps(run, indent=1) + "\n")
    for scene in scenes:
        d, i = scene["drag"], scene["input_to_frame"]
        print(
            f"{scene['scene']}: dragging {d['fps']:.1f} frames/s (median {d['median_width']:.0f} px wide, "
            f"{d['median_frame_ms']:.0f} ms), input to frame {i['median_ms']:.0f} ms median, {i['p90_ms']:.0f} ms "
            f"90th percentile ({d['latency_median_ms']:.0f} and {d['latency_p90_ms']:.0f} ms while dragging)"
        )
    print(
        f"still Cornell box: RMSE <= {TARGETS['rmse']} after {settled['seconds_to_target']:.2f} s, "
        f"{settled['rmse_at_end']:.4f} at {STILL_SECONDS:g} s"
    )
    print(f"wrote {os.path.relpath(args.json)}")


if __name__ == "__main__":
    main()
