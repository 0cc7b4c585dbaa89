"""The kernels are OpenCL C 1.2 (docs/limits.md, "OpenCL C 1.2 or later"), not PoCL's dialect.

PoCL takes more than OpenCL C 1.2 offers (the lanes used ctz, an OpenCL C 2.0
built-in), and a GPU's compiler need not. So every program variant a render plan
can ask for (render/render_plan.h's all_program_variants) is compiled here by
clang's OpenCL C 1.2 front end for SPIR, which knows only the standard's
built-ins, with the double-precision geometry and with its float fallback, and
must compile without an error or a warning. clang is a `make test` dependency
(the sanitizer build uses it).
"""

import collections
import concurrent.futures
import os
import shutil
import subprocess

import pytest

from conftest import REPO
from mbao import _core

KERNELS = REPO / "kernels"
VARIANTS = collections.defaultdict(list)
for _file, _options in _core.kernel_variants():
    VARIANTS[_file].append(_options)


def clang():
    path = shutil.which("clang")
    if path is None:
        pytest.fail("clang not found: install Debian's clang (make test does)")
    return path


def compile_errors(program, options, use_fp64):
    # __OPENCL_VERSION__ is the runtime's (the platform's version), which clang alone does not define.
    command = [
        clang(),
        "-x",
        "cl",
        "-cl-std=CL1.2",
        "-target",
        "spir64",
        "-Xclang",
        "-finclude-default-header",
        "-fsyntax-only",
        "-D__OPENCL_VERSION__=120",
        f"-I{KERNELS}",
        *options.split(),
        f"-DMBAO_USE_FP64={use_fp64}",
        str(KERNELS / program),
    ]
    result = subprocess.run(command, capture_output=True, text=True)
    if result.returncode == 0 and not result.stderr:
        return None
    return f"{' '.join(command)}\n{result.stderr}"


def test_the_plan_lists_every_program():
    assert sorted(VARIANTS) == ["denoise.cl", "hbao.cl", "render.cl", "temporal.cl", "trace.cl"]
    # The lanes' walk and each of the four walks of one ray, in the programs that trace rays in streams.
    for program in ("render.cl", "trace.cl"):
        walks = {options.split()[0] for options in VARIANTS[program]}
        assert walks == {f"-DMBAO_TRAVERSAL={w}" for w in range(5)}


def test_docs_count_the_variants_listed():
    text = (REPO / "docs" / "kernel-variants.md").read_text()
    for program in ("render.cl", "trace.cl"):
        assert f"{len(VARIANTS[program])} of `{program}`" in " ".join(text.split())


@pytest.mark.parametrize("program", ["render.cl", "trace.cl", "hbao.cl", "denoise.cl", "temporal.cl"])
def test_every_variant_compiles_as_opencl_c_1_2(program):
    jobs = [(options, fp64) for options in VARIANTS[program] for fp64 in (0, 1)]
    with concurrent.futures.ThreadPoolExecutor(os.cpu_count()) as pool:
        errors = [e for e in pool.map(lambda job: compile_errors(program, *job), jobs) if e]
    assert not errors, f"{len(errors)} of {len(jobs)} builds failed; the first:\n{errors[0]}"
