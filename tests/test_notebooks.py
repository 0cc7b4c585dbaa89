"""The notebooks run headless on the kernel the two commands set up, with the command README.md gives,
at a small image size, so they cannot rot."""

import os
import json
import re
import shlex
import subprocess

import nbformat
import pytest

from conftest import REPO

NOTEBOOKS = sorted((REPO / "notebooks").glob("*.ipynb"))
README = (REPO / "README.md").read_text()
HEADLESS = re.findall(r"^    (\.venv/bin/python -m nbconvert .*)$", README, re.M)
KERNEL_INSTALL = ".venv/bin/python -m ipykernel install --user --name mbao"


def make(*arguments, env=None, timeout=300):
    return subprocess.run(
        ["make", "-s", "-C", str(REPO), *arguments], env=env, capture_output=True, text=True, timeout=timeout
    )


@pytest.fixture(scope="module")
def kernel_install(tmp_path_factory):
    """`make notebook-kernel` run with a scratch Jupyter data directory and temporary folder: those two."""
    data, temporary = tmp_path_factory.mktemp("jupyter"), tmp_path_factory.mktemp("tmp")
    done = make("notebook-kernel", env=dict(os.environ, JUPYTER_DATA_DIR=str(data), TMPDIR=str(temporary)))
    assert done.returncode == 0, done.stderr
    return data, temporary


@pytest.fixture(scope="module")
def jupyter_data_dir(kernel_install):
    """A scratch Jupyter data directory in which `make notebook-kernel` registered the kernel "mbao"."""
    return kernel_install[0]


def test_make_notebook_kernel_leaves_nothing_in_the_temporary_folder(kernel_install):
    """ipykernel leaves the folder it wrote the spec in; every `make build` runs it."""
    assert list(kernel_install[1].iterdir()) == []


def test_there_are_notebooks():
    assert NOTEBOOKS


def test_the_notebooks_name_the_kernel_mbao():
    for path in NOTEBOOKS:
        assert nbformat.read(path, as_version=4).metadata.kernelspec.name == "mbao", path.name


def test_notebooks_are_committed_without_outputs():
    for path in NOTEBOOKS:
        notebook = nbformat.read(path, as_version=4)
        assert all(not cell.get("outputs") for cell in notebook.cells if cell.cell_type == "code"), path.name


@pytest.mark.parametrize("target", ["demo", "test"])
def test_the_two_commands_register_the_kernel(target):
    """Their build step runs notebook-kernel (`make -n` lists the commands without running them)."""
    planned = make("-n", target)
    assert planned.returncode == 0, planned.stderr
    assert KERNEL_INSTALL in planned.stdout


def test_make_notebook_kernel_registers_the_venv_as_the_kernel_mbao(jupyter_data_dir):
    spec = json.loads((jupyter_data_dir / "kernels" / "mbao" / "kernel.json").read_text())
    assert spec["argv"][0] == str(REPO / ".venv" / "bin" / "python")


def test_the_readme_says_how_to_run_a_notebook_headless_and_at_what_size():
    assert len(HEADLESS) == 1, "one command line that runs a notebook with nbconvert"
    assert "--execute" in HEADLESS[0]
    assert "make notebook-kernel" in README
    assert "MBAO_NOTEBOOK_SIZE" in README


@pytest.mark.parametrize("path", NOTEBOOKS, ids=lambda p: p.name)
def test_the_readmes_command_runs_the_notebook_on_the_registered_kernel(path, jupyter_data_dir, tmp_path):
    """README's command, on this notebook and writing to a scratch folder, with only the kernel that
    `make notebook-kernel` registered (no JUPYTER_PATH to find another "mbao")."""
    command = readme_command(notebook=path.relative_to(REPO), output_dir=tmp_path)
    env = {k: v for k, v in os.environ.items() if k != "JUPYTER_PATH"}
    env.update(JUPYTER_DATA_DIR=str(jupyter_data_dir), MBAO_NOTEBOOK_SIZE="24")
    done = subprocess.run(command, cwd=REPO, env=env, capture_output=True, text=True, timeout=600)
    assert done.returncode == 0, done.stderr[-3000:]
    notebook = nbformat.read(tmp_path / path.name, as_version=4)
    outputs = [o for cell in notebook.cells if cell.cell_type == "code" for o in cell.outputs]
    assert not [o for o in outputs if o.output_type == "error"]
    assert [o for o in outputs if "image/png" in o.get("data", {})], "the notebook draws its figures"


def readme_command(notebook, output_dir):
    """README's headless command, with `notebook` and `output_dir` in place of its own."""
    words = shlex.split(HEADLESS[0])
    words[[word.endswith(".ipynb") for word in words].index(True)] = str(notebook)
    words[words.index("--output-dir") + 1] = str(output_dir)
    return words
