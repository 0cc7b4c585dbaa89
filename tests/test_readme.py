"""Every example in README.md and docs/ runs as written, within a minute on 2 cores.

A document's ```python blocks run in order as one script (a later block may use
an earlier one's names), in an empty folder, with matplotlib drawing off screen.
README's command lines (`.venv/bin/python -m mbao ...`) run there too.
"""

import os
import pathlib
import re
import subprocess
import sys

import pytest

import mbao
from conftest import REPO

BLOCK = re.compile(r"```python\n(.*?)```", re.S)
DOCUMENTS = [path for path in [REPO / "README.md", *sorted((REPO / "docs").glob("*.md"))]
             if BLOCK.search(path.read_text())]
PACKAGE_ROOT = str(pathlib.Path(mbao.__file__).resolve().parents[1])


def run(command, cwd):
    env = dict(os.environ, MPLBACKEND="Agg", PYTHONPATH=PACKAGE_ROOT + os.pathsep + os.environ.get("PYTHONPATH", ""))
    return subprocess.run(command, cwd=cwd, env=env, capture_output=True, text=True, timeout=60)


def test_the_readme_has_examples():
    assert REPO / "README.md" in DOCUMENTS


@pytest.mark.parametrize("document", DOCUMENTS, ids=[path.name for path in DOCUMENTS])
def test_the_examples_run_as_written(tmp_path, document):
    proc = run([sys.executable, "-c", "\n".join(BLOCK.findall(document.read_text()))], tmp_path)
    assert proc.returncode == 0, f"{document.name}'s examples failed:\n{proc.stderr[-3000:]}"


COMMANDS = re.findall(r"^    \.venv/bin/python -m mbao(.*?)$", (REPO / "README.md").read_text(), re.M)


@pytest.mark.parametrize("arguments", COMMANDS)
def test_the_readmes_command_lines_run_as_written(tmp_path, arguments):
    command = [sys.executable, "-m", "mbao", *arguments.split()]
    proc = run(command, tmp_path)
    assert proc.returncode == 0, f"{' '.join(command)}:\n{proc.stderr[-3000:]}"
