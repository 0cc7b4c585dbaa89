"""The sources keep one format: clang-format's (.clang-format) for the C++ and OpenCL C, black's
(pyproject.toml's [tool.black]) for the Python. Each check names the files it would change; running
the formatter on them (`clang-format -i FILE`, `black FILE`) mends them."""

import subprocess

from conftest import REPO


def tracked(*patterns):
    listed = subprocess.run(["git", "ls-files", *patterns], cwd=REPO, capture_output=True, text=True, check=True)
    files = listed.stdout.split()
    assert files, f"no tracked files match {patterns}"
    return files


def test_the_cpp_and_opencl_sources_are_as_clang_format_writes_them():
    run = subprocess.run(
        ["clang-format", "--dry-run", "--Werror", *tracked("*.cpp", "*.h", "*.cl")],
        cwd=REPO,
        capture_output=True,
        text=True,
    )
    assert run.returncode == 0, run.stderr[-3000:]


def test_the_python_sources_are_as_black_writes_them():
    run = subprocess.run(["black", "--check", *tracked("*.py")], cwd=REPO, capture_output=True, text=True)
    assert run.returncode == 0, run.stderr[-3000:]
