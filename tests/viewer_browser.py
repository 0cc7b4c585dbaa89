"""Headless Chromium (Debian's chromium and chromium-driver) driven by
Selenium, for the viewer's tests: a page's state and image as a user's
browser has them."""

import base64
import contextlib
import io
import os
import tempfile
import time

import numpy as np
from PIL import Image
from selenium import webdriver
from selenium.webdriver.chrome.service import Service

from viewer_client import FRAME_TIMEOUT_S


@contextlib.contextmanager
def chromium():
    """The browser, quit on leaving. Its temporary files go in a folder of its
    own, removed after: Chromium leaves its singleton-lock folders behind."""
    with tempfile.TemporaryDirectory(prefix="mbao-chromium-") as folder:
        options = webdriver.ChromeOptions()
        options.binary_location = "/usr/bin/chromium"
        # No sandbox: tests run as root in CI, where Chromium's sandbox refuses to start.
        for argument in ("--headless=new", "--no-sandbox", "--disable-dev-shm-usage", "--window-size=1200,900"):
            options.add_argument(argument)
        options.set_capability("goog:loggingPrefs", {"browser": "ALL"})
        service = Service("/usr/bin/chromedriver", env={**os.environ, "TMPDIR": folder})
        driver = webdriver.Chrome(service=service, options=options)
        try:
            driver.set_script_timeout(FRAME_TIMEOUT_S)
            yield driver
        finally:
            driver.quit()


def state(driver):
    return driver.execute_script("return window.mbaoView ? window.mbaoView.state() : null")


def wait_for(driver, condition, what):
    """The page's state once condition(state) holds; fails after FRAME_TIMEOUT_S."""
    deadline = time.monotonic() + FRAME_TIMEOUT_S
    while time.monotonic() < deadline:
        current = state(driver)
        if current is not None and condition(current):
            return current
        time.sleep(0.05)
    raise AssertionError(f"the page did not reach {what} within {FRAME_TIMEOUT_S} s; its state: {state(driver)}")


def wait_still(driver):
    """The state once the page shows the final frame of its view."""
    return wait_for(driver, lambda s: s["final"], "a final frame")


def image(driver):
    """The bytes of the image the page shows (its element "view"), decoded: (H, W) uint8."""
    encoded = driver.execute_async_script(
        """
        const done = arguments[arguments.length - 1];
        fetch(document.getElementById("view").src).then((r) => r.arrayBuffer()).then((buffer) => {
          let text = "";
          for (const byte of new Uint8Array(buffer)) text += String.fromCharCode(byte);
          done(btoa(text));
        });"""
    )
    return np.asarray(Image.open(io.BytesIO(base64.b64decode(encoded))))


def set_view(driver, camera=None, settings=None):
    driver.execute_script(
        "window.mbaoView.set(arguments[0])",
        {k: v for k, v in dict(camera=camera, settings=settings).items() if v is not None},
    )


def console_errors(driver):
    return [entry for entry in driver.get_log("browser") if entry["level"] == "SEVERE"]
