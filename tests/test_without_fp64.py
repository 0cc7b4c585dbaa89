"""The float paths of devices without fp64 (kernels/geometry.h, MBAO_USE_FP64).

PoCL adds POCL_EXTRA_BUILD_FLAGS to every program it builds, so a process
started with -DMBAO_USE_FP64=0 there (and an empty kernel cache) runs mbao's
kernels as a device without doubles would. Other devices have no such hook:
there the tests skip.
"""

import os
import pathlib
import subprocess
import sys

import numpy as np
import pytest

TESTS = pathlib.Path(__file__).resolve().parent

# What the float-only process computes; the parent computes the same with fp64.
WORKLOAD = r"""
import numpy as np
import mbao
from meshes import t_junction_box

def cornell_ao():
    return mbao.render(mbao.cornell_box(), width=48, height=48, bounces=2, samples=4, seed=3).ao

def t_junction_rays():
    # Rays from inside the closed box at its T-vertices (test_degenerate_geometry).
    vertices, indices, t_vertices, _ = t_junction_box()
    rng = np.random.default_rng(11)
    origins = (vertices[:8].mean(axis=0) + rng.uniform(-1.0, 1.0, (4000, 3))).astype(np.float32)
    targets = vertices[rng.choice(t_vertices, 4000)].astype(np.float32)
    return mbao.trace(mbao.Mesh(vertices, indices), origins, targets - origins)[1]
"""

CHILD = (
    WORKLOAD
    + r"""
import sys
np.savez(sys.argv[1], cornell_ao=cornell_ao(), t_junction_hits=t_junction_rays())
"""
)


@pytest.fixture(scope="module")
def without_fp64(tmp_path_factory, device):
    """The workload's results from a process whose kernels take the float paths."""
    if "Portable Computing Language" not in device.platform:
        pytest.skip("only PoCL can add a define to every build (POCL_EXTRA_BUILD_FLAGS)")
    folder = tmp_path_factory.mktemp("without_fp64")
    env = dict(
        os.environ,
        POCL_EXTRA_BUILD_FLAGS="-DMBAO_USE_FP64=0",
        POCL_KERNEL_CACHE="0",
        MBAO_CACHE_DIR=str(folder / "kernels"),
        PYTHONPATH=os.pathsep.join(filter(None, [str(TESTS), os.environ.get("PYTHONPATH")])),
    )
    output = folder / "results.npz"
    subprocess.run([sys.executable, "-c", CHILD, str(output)], env=env, check=True, timeout=600)
    return np.load(output)


@pytest.fixture(scope="module")
def with_fp64():
    namespace = {}
    exec(WORKLOAD, namespace)
    return {"cornell_ao": namespace["cornell_ao"](), "t_junction_hits": namespace["t_junction_rays"]()}


def test_the_float_paths_are_taken(without_fp64, with_fp64):
    """With doubles every ray at a T-vertex hits; the float edge functions let
    some through the junction (test_degenerate_geometry's docstring: 1-2%), which
    shows the define reached the kernels."""
    assert np.all(with_fp64["t_junction_hits"] >= 0)
    escaped = np.mean(without_fp64["t_junction_hits"] < 0)
    assert 0.0 < escaped < 0.05, escaped


def test_without_fp64_the_cornell_box_renders_the_same_ao(without_fp64, with_fp64):
    """The same seed, so the images differ only where a normal or an edge function
    rounds differently. Their paired difference has no bias: its mean lies within
    4 standard errors of zero."""
    float_ao, double_ao = without_fp64["cornell_ao"], with_fp64["cornell_ao"]
    assert np.all(np.isfinite(float_ao)) and np.all((float_ao >= 0.0) & (float_ao <= 1.0))
    difference = (float_ao - double_ao).ravel()
    standard_error = difference.std(ddof=1) / np.sqrt(difference.size)
    assert abs(difference.mean()) <= 4.0 * standard_error, (difference.mean(), standard_error)
