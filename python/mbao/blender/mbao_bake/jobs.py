"""A bake running beside Blender's UI: in a thread of Blender's process where
its Python imports mbao, else in mbao's Python as a child process. Either way
it reports its progress, can be cancelled, and hands back arrays or a message."""

import importlib
import importlib.util
import json
import os
import subprocess
import sys
import tempfile
import threading
import warnings
from pathlib import Path

import numpy as np

# Written by the installer (`python -m mbao blender --install`): where mbao's
# package lies, and the Python that runs it.
LOCATION_FILE = Path(__file__).with_name("location.json")


def location():
    """{"package": the folder holding the mbao package, "python": its interpreter}."""
    try:
        return json.loads(LOCATION_FILE.read_text())
    except (OSError, ValueError) as error:
        raise RuntimeError(
            f"the add-on does not know where mbao is ({LOCATION_FILE}: {error}); install it with "
            f"`python -m mbao blender --install`"
        ) from None


def request_module(place):
    """mbao.blender.request, loaded from its file without mbao's package: enough to write a request."""
    path = Path(place["package"]) / "mbao" / "blender" / "request.py"
    spec = importlib.util.spec_from_file_location("mbao_blender_request", path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def imports_mbao(place):
    """Whether Blender's Python imports mbao (its compiled core included)."""
    if place["package"] not in sys.path:
        sys.path.append(place["package"])
    try:
        importlib.import_module("mbao")
    except ImportError:
        return False
    return True


class Cancelled(Exception):
    """Raised in the bake's progress callback to stop it between tiles."""


class BakeJob:
    """One bake, started at once. fraction: how far it is; done once finished,
    failed or cancelled; then result ({"values", "standard_error"}), error (a
    message) and warnings (messages)."""

    def __init__(self, arrays, settings, run_in="AUTO"):
        place = location()
        if run_in == "AUTO":
            run_in = "BLENDER" if imports_mbao(place) else "CHILD"
        elif run_in == "BLENDER" and not imports_mbao(place):
            raise RuntimeError(
                f"Blender's Python {sys.version.split()[0]} cannot import mbao from "
                f"{place['package']}; run it as a child process (the add-on's preferences)"
            )
        self.run_in = run_in
        self.fraction, self.result, self.error, self.warnings = 0.0, None, None, []
        self._cancel = threading.Event()
        self._finished = threading.Event()
        self._child = None
        # The module itself where it runs here; else its file, for the request it writes.
        self._request = (
            importlib.import_module("mbao.blender.request") if run_in == "BLENDER" else request_module(place)
        )
        run = self._run_here if run_in == "BLENDER" else self._run_child
        threading.Thread(target=self._finishing(run), args=(arrays, settings, place), daemon=True).start()

    @property
    def done(self):
        return self._finished.is_set()

    @property
    def cancelled(self):
        return self._cancel.is_set()

    def cancel(self):
        """Stops the bake between tiles (a child process at once); it then has no result."""
        self._cancel.set()
        child = self._child
        if child is not None and child.poll() is None:
            child.terminate()

    def wait(self):
        self._finished.wait()

    def _finishing(self, run):
        def finishing(*arguments):
            try:
                run(*arguments)
            except Exception as error:  # the thread's end: the operator reports it
                self.error = self._request.message_of(error)
            finally:
                if self.cancelled:
                    self.result = None
                self._finished.set()

        return finishing

    def _progress(self, done, total):
        if self.cancelled:
            raise Cancelled()
        self.fraction = done / total

    def _run_here(self, arrays, settings, place):
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            try:
                self.result = self._request.bake(arrays, settings, self._progress)
            except Cancelled:
                pass
        self.warnings = [" ".join(str(w.message).split()) for w in caught]

    def _run_child(self, arrays, settings, place):
        with tempfile.TemporaryDirectory(prefix="mbao-blender-") as folder:
            request, result = os.path.join(folder, "request.npz"), os.path.join(folder, "result.npz")
            self._request.write_request(request, arrays, settings)
            environment = dict(
                os.environ,
                PYTHONPATH=os.pathsep.join(
                    [place["package"]] + [p for p in os.environ.get("PYTHONPATH", "").split(os.pathsep) if p]
                ),
            )
            self._child = subprocess.Popen(
                [place["python"], "-m", "mbao.blender.request", request, result],
                stdout=subprocess.PIPE,
                stderr=subprocess.PIPE,
                text=True,
                env=environment,
            )
            if self.cancelled:  # cancelled while it started
                self._child.terminate()
            errors = []
            reading = threading.Thread(target=lambda: errors.extend(self._child.stderr), daemon=True)
            reading.start()
            for line in self._child.stdout:
                self._read_line(line)
            self._child.wait()
            reading.join()
            if self.cancelled:
                return
            if self._child.returncode != 0:
                self.error = errors[-1].strip() if errors else f"mbao's process ended with {self._child.returncode}"
                return
            with np.load(result) as arrays_back:
                self.result = {name: arrays_back[name] for name in arrays_back.files}

    def _read_line(self, line):
        kind, _, rest = line.rstrip("\n").partition(" ")
        if kind == "progress":
            done, total = map(int, rest.split())
            self.fraction = done / total
        elif kind == "warning":
            self.warnings.append(rest)
