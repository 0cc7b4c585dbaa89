"""The notebooks run, top to bottom, at a small image size, so they cannot rot."""

import json
import os
import pathlib
import subprocess
import sys

import nbformat
import pytest
from nbclient import NotebookClient

NOTEBOOKS = sorted((pathlib.Path(__file__).resolve().parents[1] / "notebooks").glob("*.ipynb"))


@pytest.fixture
def kernel_of_this_python(tmp_path, monkeypatch):
    """A Jupyter kernel on the interpreter running the tests (the venv's), not
    whatever "python3" kernel the system has."""
    spec = tmp_path / "kernels" / "mbao-tests"
    spec.mkdir(parents=True)
    argv = [sys.executable, "-m", "ipykernel_launcher", "-f", "{connection_file}"]
    (spec / "kernel.json").write_text(json.dumps({"argv": argv, "display_name": "mbao tests", "language": "python"}))
    monkeypatch.setenv("JUPYTER_PATH", str(tmp_path))
    return "mbao-tests"


@pytest.mark.parametrize("path", NOTEBOOKS, ids=lambda p: p.name)
def test_notebook_runs(path, kernel_of_this_python, monkeypatch):
    monkeypatch.setenv("MBAO_NOTEBOOK_SIZE", "24")
    notebook = nbformat.read(path, as_version=4)
    client = NotebookClient(
        notebook, timeout=600, kernel_name=kernel_of_this_python, resources={"metadata": {"path": str(path.parent)}}
    )
    # Where Debian's ipywidgets 6 is installed (python3-notebook, which `make
    # notebook` installs, brings it), the progress bars are widgets, whose comms
    # lack the state nbclient 0.7 reads; a run without a browser ignores them.
    client.comm_open_handlers.pop("jupyter.widget", None)
    client.execute()
    outputs = [o for cell in notebook.cells if cell.cell_type == "code" for o in cell.outputs]
    assert not [o for o in outputs if o.output_type == "error"]
    figures = [o for o in outputs if "image/png" in o.get("data", {})]
    assert figures, "the notebook draws its figures"


def test_notebooks_are_committed_without_outputs():
    for path in NOTEBOOKS:
        notebook = nbformat.read(path, as_version=4)
        assert all(not cell.get("outputs") for cell in notebook.cells if cell.cell_type == "code"), path.name


def test_there_are_notebooks():
    assert NOTEBOOKS


def test_make_notebook_kernel_installs_the_kernel_the_notebooks_name(tmp_path):
    """`make notebook` registers the venv as the Jupyter kernel "mbao"
    (its notebook-kernel step, here into a scratch Jupyter data directory)."""
    repo = pathlib.Path(__file__).resolve().parents[1]
    env = dict(os.environ, JUPYTER_DATA_DIR=str(tmp_path))
    done = subprocess.run(["make", "-s", "-C", str(repo), "notebook-kernel"], env=env, capture_output=True,
                          text=True, timeout=300)
    assert done.returncode == 0, done.stderr
    spec = json.loads((tmp_path / "kernels" / "mbao" / "kernel.json").read_text())
    assert pathlib.Path(spec["argv"][0]) == repo / ".venv" / "bin" / "python"
    for path in NOTEBOOKS:
        assert nbformat.read(path, as_version=4).metadata.kernelspec.name == "mbao", path.name
