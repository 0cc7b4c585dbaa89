"""mbao.view in a notebook, as a user has it: Jupyter's notebook server (the
one `make notebook` starts), opened in headless Chromium, runs a cell that
calls mbao.view; the view shows in the cell's output, and the page and the
kernel's handle follow each other."""

import json
import secrets
import socket
import subprocess
import sys
import time
import urllib.request

import nbformat
import pytest
from selenium.webdriver.common.by import By

from viewer_browser import chromium, set_view, state, wait_for, wait_still
from viewer_client import FRAME_TIMEOUT_S


def free_port():
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


@pytest.fixture
def notebook_server(tmp_path):
    """Jupyter's notebook server on 127.0.0.1, its kernel "mbao-tests" this
    interpreter (the venv's), serving tmp_path; (url, token)."""
    kernels = tmp_path / "jupyter" / "kernels" / "mbao-tests"
    kernels.mkdir(parents=True)
    argv = [sys.executable, "-m", "ipykernel_launcher", "-f", "{connection_file}"]
    (kernels / "kernel.json").write_text(json.dumps({"argv": argv, "display_name": "mbao tests", "language": "python"}))
    port, token = free_port(), secrets.token_hex(16)
    env = dict(
        __import__("os").environ, JUPYTER_PATH=str(tmp_path / "jupyter"), JUPYTER_RUNTIME_DIR=str(tmp_path / "runtime")
    )
    # Debian's /usr/bin/python3 has Jupyter's notebook server; --allow-root: CI runs as root.
    server = subprocess.Popen(
        [
            "/usr/bin/python3",
            "-m",
            "notebook",
            "--no-browser",
            "--allow-root",
            "--ip=127.0.0.1",
            f"--port={port}",
            f"--NotebookApp.token={token}",
            f"--notebook-dir={tmp_path}",
            "--NotebookApp.port_retries=0",
        ],
        env=env,
        stdout=subprocess.DEVNULL,
        stderr=subprocess.PIPE,
    )
    url = f"http://127.0.0.1:{port}"
    try:
        _wait_until_serving(f"{url}/api/status?token={token}", server)
        yield url, token
    finally:
        server.terminate()
        server.wait(timeout=FRAME_TIMEOUT_S)


def _wait_until_serving(url, server):
    deadline = time.monotonic() + FRAME_TIMEOUT_S
    while time.monotonic() < deadline:
        if server.poll() is not None:
            raise AssertionError(f"the notebook server stopped: {server.stderr.read().decode()[-2000:]}")
        try:
            urllib.request.urlopen(url, timeout=5).close()
            return
        except OSError:
            time.sleep(0.2)
    raise AssertionError("the notebook server did not start")


@pytest.fixture
def browser():
    with chromium() as driver:
        yield driver


def run_cell(driver, source):
    """Appends a code cell, runs it, and returns its text output once all of it has arrived.

    The execute reply (which sets the prompt number) and the outputs come on
    different channels, so the prompt can change before the last output is
    in; the cell's finished_execute event comes after both."""
    index = driver.execute_script(
        """
        const cell = Jupyter.notebook.insert_cell_at_bottom("code");
        cell.set_text(arguments[0]);
        Jupyter.notebook.events.on("finished_execute.CodeCell", (event, data) => {
            if (data.cell === cell) cell.mbao_test_finished = true;
        });
        cell.execute();
        return Jupyter.notebook.find_cell_index(cell);""",
        source,
    )
    deadline = time.monotonic() + FRAME_TIMEOUT_S
    while time.monotonic() < deadline:
        done = driver.execute_script(
            """
            const cell = Jupyter.notebook.get_cell(arguments[0]);
            return cell.mbao_test_finished ? cell.output_area.outputs : null;""",
            index,
        )
        if done is not None:
            errors = [o for o in done if o["output_type"] == "error"]
            assert not errors, "\n".join(errors[0]["traceback"])
            return "".join(o.get("text", "") + o.get("data", {}).get("text/plain", "") for o in done)
        time.sleep(0.1)
    raise AssertionError(f"the cell did not finish: {source}")


def test_mbao_view_shows_and_reacts_in_a_notebook(notebook_server, browser, tmp_path):
    url, token = notebook_server
    notebook = nbformat.v4.new_notebook(
        metadata={"kernelspec": {"name": "mbao-tests", "display_name": "mbao tests", "language": "python"}}
    )
    nbformat.write(notebook, tmp_path / "view.ipynb")
    browser.get(f"{url}/notebooks/view.ipynb?token={token}")
    deadline = time.monotonic() + FRAME_TIMEOUT_S
    while not browser.execute_script(
        "return window.Jupyter && Jupyter.notebook && Jupyter.notebook.kernel && Jupyter.notebook.kernel.is_connected()"
    ):
        assert time.monotonic() < deadline, "the notebook's kernel did not start"
        time.sleep(0.2)

    run_cell(browser, "import mbao\nv = mbao.view(width=64, height=48, samples=2, frames=2)")
    frame = browser.find_element(By.CSS_SELECTOR, ".output_area iframe")
    browser.switch_to.frame(frame)
    shown = wait_still(browser)
    assert (shown["width"], shown["height"]) == (64, 48) and shown["error"] is None

    # The kernel sets, the page follows.
    browser.switch_to.default_content()
    run_cell(browser, "v.settings = {'bounces': 3}")
    browser.switch_to.frame(frame)
    assert wait_for(browser, lambda s: s["settings"]["bounces"] == 3 and s["final"], "the kernel's bounces")

    # The page sets, the kernel's handle reads it.
    home = state(browser)["camera"]
    moved = dict(home, eye=[home["eye"][0] + 150, home["eye"][1], home["eye"][2]])
    set_view(browser, camera=moved)
    wait_still(browser)
    browser.switch_to.default_content()
    eye = run_cell(browser, "print(list(v.camera.eye))")
    assert json.loads(eye) == pytest.approx(moved["eye"])
    shape = run_cell(browser, "s = v.snapshot(); print(s.ao.shape, v.settings['bounces'])")
    assert shape.strip() == "(48, 64) 3"
    run_cell(browser, "v.close()")
