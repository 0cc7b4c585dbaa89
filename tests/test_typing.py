"""Type information ships with the package (issue 60): the Python layer's
annotations, a stub for the C++ core that matches the built module, and
py.typed, so that mypy and IDEs check a script that uses mbao."""

import pathlib
import subprocess
import sys

REPO = pathlib.Path(__file__).resolve().parents[1]
TYPING = REPO / "tests" / "typing"


def mypy(*arguments):
    return subprocess.run([sys.executable, "-m", *arguments], capture_output=True, text=True, timeout=600, cwd=REPO)


def test_mypy_strict_passes_a_script_that_uses_the_api_and_names_the_misuses_of_another(tmp_path):
    """--strict refuses a call to any function without annotations, so every
    function the example calls must have them, and they must fit its use; a
    script that misuses the API fails, with each misuse named. One run of mypy
    checks both, as its start-up (numpy's stubs) is most of its time."""
    misuse = tmp_path / "misuse.py"
    misuse.write_text("import mbao\n" "result: mbao.Bake = mbao.render(mbao.cornell_box())\n" "mbao.load(42)\n")
    run = mypy("mypy", "--strict", "--no-incremental", str(TYPING / "example.py"), str(misuse))
    assert run.returncode == 1, run.stdout + run.stderr
    errors = [line for line in run.stdout.splitlines() if ": error:" in line]
    assert errors and all(line.startswith(str(misuse)) for line in errors), run.stdout
    assert 'Incompatible types in assignment (expression has type "Result", variable has type "Bake")' in run.stdout
    assert 'Argument 1 to "load" has incompatible type "int"' in run.stdout


def test_the_cores_stub_matches_the_built_module():
    """mypy's stubtest imports mbao._core and compares each name, signature and
    type in python/mbao/_core.pyi with it."""
    run = mypy("mypy.stubtest", "mbao._core", "--allowlist", str(TYPING / "stubtest_allowlist.txt"))
    assert run.returncode == 0, run.stdout + run.stderr
