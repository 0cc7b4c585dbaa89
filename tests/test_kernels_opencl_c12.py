"""The kernels are OpenCL C 1.2 (README, "OpenCL C 1.2 or later"), not PoCL's dialect.

PoCL takes more than OpenCL C 1.2 offers (the lanes used ctz, an OpenCL C 2.0
built-in), and a GPU's compiler need not. So every program is compiled here by
clang's OpenCL C 1.2 front end for SPIR, which knows only the standard's built-ins,
with the option sets the renderer builds (every traversal, each define off and
on), and must compile without an error or a warning. clang is a `make test`
dependency (the sanitizer build uses it).
"""

import itertools
import shutil
import subprocess

import pytest

from conftest import REPO

KERNELS = REPO / "kernels"
PROGRAMS = ["render.cl", "trace.cl", "hbao.cl"]
TRAVERSALS = range(5)  # MBAO_TRAVERSAL_RESTART .. MBAO_TRAVERSAL_LANES (kd_traversal.h)
SWITCHES = ["MBAO_COUNT_TRAVERSAL", "MBAO_ALPHA_MASKS", "MBAO_SHADING_NORMALS", "MBAO_UNLIMITED_DISTANCE",
            "MBAO_LOAD_BOTH_CHILDREN", "MBAO_ORIGIN_PATHS"]


def clang():
    path = shutil.which("clang")
    if path is None:
        pytest.fail("clang not found: install Debian's clang (make test does)")
    return path


@pytest.mark.parametrize("program, traversal, switched_on", itertools.product(PROGRAMS, TRAVERSALS, [0, 1]))
def test_program_compiles_as_opencl_c_1_2(program, traversal, switched_on):
    # The float fallbacks (MBAO_USE_FP64=0) with the switches on, the double ones with them off.
    defines = [f"-DMBAO_TRAVERSAL={traversal}", f"-DMBAO_USE_FP64={1 - switched_on}"]
    defines += [f"-D{name}={switched_on}" for name in SWITCHES]
    # __OPENCL_VERSION__ is the runtime's (the platform's version), which clang alone does not define.
    command = [clang(), "-x", "cl", "-cl-std=CL1.2", "-target", "spir64", "-Xclang", "-finclude-default-header",
               "-fsyntax-only", "-D__OPENCL_VERSION__=120", f"-I{KERNELS}", *defines, str(KERNELS / program)]
    result = subprocess.run(command, capture_output=True, text=True)
    assert result.returncode == 0 and not result.stderr, f"{' '.join(command)}\n{result.stderr}"
