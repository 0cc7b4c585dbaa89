"""Takes docs/viewer.png: the live viewer's page on Sponza, still at b = 2 with a radius of 200
after 16 frames, in headless Chromium. Run from the repository root:
.venv/bin/python docs/viewer_screenshot.py"""

import pathlib
import sys

here = pathlib.Path(__file__).resolve().parent
sys.path.insert(0, str(here.parent / "tests"))  # the tests' browser and server helpers

from viewer_browser import chromium, wait_still  # noqa: E402
from viewer_client import served  # noqa: E402

sponza = here.parent.parent / "shared" / "scenes" / "sponza"

with served(
    str(sponza / "scene.glb"),
    camera=str(sponza / "camera.json"),
    width=640,
    height=400,
    bounces=2,
    samples=4,
    max_distance=200.0,
    denoise=True,
    frames=16,
) as viewer:
    with chromium() as browser:
        browser.set_window_size(960, 740)
        browser.get(viewer.url)
        wait_still(browser)
        browser.save_screenshot(str(here / "viewer.png"))
