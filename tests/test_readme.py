"""Every example in README.md and docs/ runs as pasted, within a minute on 2 cores.

Each ```python block is a whole script. It runs as a user runs it: written to `example.py` in an empty
folder and run as `python example.py` in a fresh process, with matplotlib drawing off screen. So a
block needs its own imports, and the processes it starts (Dask's spawned workers) import it again, as
they do a user's script: a block without an `if __name__ == "__main__":` guard hangs or fails here too.
README's command lines (`.venv/bin/python -m mbao ...`) run in an empty folder as well.
"""

import dataclasses
import os
import pathlib
import re
import signal
import subprocess
import sys
import time

import pytest

import mbao
from conftest import REPO

BLOCK = re.compile(r"```python\n(.*?)```", re.S)
TIMEOUT_S = 60
PACKAGE_ROOT = str(pathlib.Path(mbao.__file__).resolve().parents[1])


@dataclasses.dataclass
class Example:
    document: pathlib.Path
    line: int  # of the opening ```python
    code: str

    def __str__(self):
        return f"{self.document.name}:{self.line}"


def examples(document):
    text = document.read_text()
    return [Example(document, text.count("\n", 0, match.start()) + 1, match.group(1)) for match in BLOCK.finditer(text)]


EXAMPLES = [
    example for path in [REPO / "README.md", *sorted((REPO / "docs").glob("*.md"))] for example in examples(path)
]


@dataclasses.dataclass
class Finished:
    returncode: int | None  # None: still running at the timeout, and killed
    stdout: str
    stderr: str

    def report(self):
        status = f"still running after {TIMEOUT_S} s" if self.returncode is None else f"exit status {self.returncode}"
        return f"{status}:\n{self.stderr[-3000:]}"


def run(command, cwd, timeout_s=TIMEOUT_S):
    """Runs `command` in a session of its own, so that at the timeout every process it started (Dask's
    workers too) is killed with it and none outlives the test."""
    env = dict(os.environ, MPLBACKEND="Agg", PYTHONPATH=PACKAGE_ROOT + os.pathsep + os.environ.get("PYTHONPATH", ""))
    with subprocess.Popen(
        command, cwd=cwd, env=env, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, start_new_session=True
    ) as process:
        try:
            stdout, stderr = process.communicate(timeout=timeout_s)
            return Finished(process.returncode, stdout, stderr)
        except subprocess.TimeoutExpired:
            os.killpg(process.pid, signal.SIGKILL)
            stdout, stderr = process.communicate()
            return Finished(None, stdout, stderr)


def run_as_a_script(code, folder, timeout_s=TIMEOUT_S):
    (folder / "example.py").write_text(code)
    return run([sys.executable, "example.py"], folder, timeout_s)


def test_the_readme_has_examples():
    assert any(example.document.name == "README.md" for example in EXAMPLES)


def test_the_readme_stays_a_first_page():
    """README.md is at most 300 lines: the rest goes to docs/, which its last table lists."""
    readme = (REPO / "README.md").read_text()
    assert len(readme.splitlines()) <= 300
    for page in sorted((REPO / "docs").glob("*.md")):
        assert f"](docs/{page.name})" in readme, f"docs/{page.name} is not linked from README.md"


@pytest.mark.parametrize("example", EXAMPLES, ids=str)
def test_each_example_runs_as_a_script_of_its_own(tmp_path, example):
    finished = run_as_a_script(example.code, tmp_path)
    assert finished.returncode == 0, f"the example at {example}: {finished.report()}"


COMMANDS = re.findall(r"^    \.venv/bin/python -m mbao(.*?)$", (REPO / "README.md").read_text(), re.M)


@pytest.mark.parametrize("arguments", COMMANDS)
def test_the_readmes_command_lines_run_as_written(tmp_path, arguments):
    command = [sys.executable, "-m", "mbao", *arguments.split()]
    finished = run(command, tmp_path)
    assert finished.returncode == 0, f"{' '.join(command)}: {finished.report()}"


# The harness itself: an example sees what a user's script sees, and one that hangs fails.


def test_an_example_runs_as_the_main_script_in_an_empty_folder(tmp_path):
    code = 'import os, sys\nassert __name__ == "__main__" and sys.argv == ["example.py"]\nprint(os.listdir("."))\n'
    finished = run_as_a_script(code, tmp_path)
    assert finished.returncode == 0, finished.report()
    assert finished.stdout.strip() == "['example.py']"


def test_an_example_that_hangs_is_killed_with_its_processes(tmp_path):
    code = (
        "import subprocess, sys, time\n"
        "child = subprocess.Popen([sys.executable, '-c', 'import time; time.sleep(600)'])\n"
        "print(child.pid, flush=True)\n"
        "time.sleep(600)\n"
    )
    finished = run_as_a_script(code, tmp_path, timeout_s=5)
    assert finished.returncode is None
    assert ends_within(int(finished.stdout), seconds=5)


def ends_within(pid, seconds):
    """Whether process `pid` ends within `seconds` (a zombie, killed but not yet reaped, has ended)."""
    deadline = time.monotonic() + seconds
    while time.monotonic() < deadline:
        try:
            state = pathlib.Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()[0]
        except FileNotFoundError:
            return True
        if state in ("Z", "X"):
            return True
        time.sleep(0.05)
    return False
