"""Kernels are built for what a scene and the settings need, once: cached in
memory for the process and as OpenCL binaries on disk for the next process."""

import os
import pathlib
import subprocess
import sys

import numpy as np

import mbao
from meshes import plane

RENDER_ONCE = """
import sys, mbao
result = mbao.render(mbao.cornell_box(), width=4, height=4, bounces=2)
print(result.stats["kernel_cache"], result.stats["kernel_build_ms"])
"""


def render_in_a_new_process(cache_dir):
    env = dict(os.environ, MBAO_CACHE_DIR=str(cache_dir))
    done = subprocess.run([sys.executable, "-c", RENDER_ONCE], env=env, capture_output=True, text=True, timeout=300)
    assert done.returncode == 0, done.stderr
    origin, build_ms = done.stdout.split()
    return origin, float(build_ms)


def cached_binaries(cache_dir):
    return sorted(p for p in pathlib.Path(cache_dir).iterdir())


def test_the_second_process_takes_the_program_from_disk(tmp_path):
    assert render_in_a_new_process(tmp_path)[0] == "compiled"
    files = cached_binaries(tmp_path)
    assert len(files) == 1 and files[0].suffix == ".bin"
    assert render_in_a_new_process(tmp_path)[0] == "disk"
    assert cached_binaries(tmp_path) == files


def test_a_cold_build_prints_nothing(tmp_path):
    """The compiler's log goes to the logger "mbao", never to stderr: here a
    first render and a denoised one with every cache empty (mbao's and PoCL's)."""
    code = RENDER_ONCE + "mbao.render(mbao.cornell_box(), width=4, height=4, bounces=2, denoise=True)\n"
    env = dict(
        os.environ,
        MBAO_CACHE_DIR=str(tmp_path / "mbao"),
        POCL_CACHE_DIR=str(tmp_path / "pocl"),
        XDG_CACHE_HOME=str(tmp_path),
    )
    done = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True, text=True, timeout=600)
    assert done.returncode == 0 and done.stdout.split()[0] == "compiled", done.stderr
    assert done.stderr == ""


def test_a_damaged_binary_is_rebuilt(tmp_path):
    render_in_a_new_process(tmp_path)
    [binary] = cached_binaries(tmp_path)
    for damage in (b"", b"garbage", binary.read_bytes()[:-7]):
        binary.write_bytes(damage)
        assert render_in_a_new_process(tmp_path)[0] == "compiled"
        assert render_in_a_new_process(tmp_path)[0] == "disk"


def test_concurrent_processes_share_the_store(tmp_path):
    env = dict(os.environ, MBAO_CACHE_DIR=str(tmp_path))
    runs = [subprocess.Popen([sys.executable, "-c", RENDER_ONCE], env=env, stdout=subprocess.PIPE, stderr=subprocess.PIPE)
            for _ in range(4)]  # fmt: skip
    for run in runs:
        assert run.wait(timeout=300) == 0, run.stderr.read()
    files = cached_binaries(tmp_path)
    assert len(files) == 1 and files[0].suffix == ".bin", files  # no temporary files left behind
    assert render_in_a_new_process(tmp_path)[0] == "disk"


def test_an_empty_cache_dir_setting_turns_the_store_off(tmp_path):
    env = dict(os.environ, MBAO_CACHE_DIR="", HOME=str(tmp_path), XDG_CACHE_HOME=str(tmp_path))
    done = subprocess.run([sys.executable, "-c", RENDER_ONCE], env=env, capture_output=True, text=True, timeout=300)
    assert done.returncode == 0 and done.stdout.split()[0] == "compiled"
    assert not list(tmp_path.rglob("mbao"))  # (the OpenCL driver may keep a cache of its own there)


def test_within_a_process_a_program_is_built_once():
    scene = mbao.cornell_box()
    mbao.render(scene, width=4, height=4, seed=1)
    again = mbao.render(scene, width=4, height=4, seed=2)
    assert again.stats["kernel_cache"] == "memory"


def test_kernels_compile_in_only_what_is_needed():
    """Mask lookups only for scenes with masks. A distance limit, shading
    normals and a variance are arguments of one program, not builds of their own."""
    cornell = mbao.cornell_box()  # no masks, no normals
    options = mbao.render(cornell, width=2, height=2).stats["kernel_options"]
    assert "-DMBAO_ALPHA_MASKS=0" in options
    assert mbao.render(cornell, width=2, height=2, max_distance=100.0).stats["kernel_options"] == options
    assert mbao.render(cornell, width=2, height=2, variance=True).stats["kernel_options"] == options

    vertices, indices = plane(2.0)
    with_normals = mbao.Mesh(vertices, indices, np.tile([0.0, 1.0, 0.0], (len(vertices), 1)))
    shading = mbao.render(with_normals, width=2, height=2).stats["kernel_options"]
    geometric = mbao.render(with_normals, width=2, height=2, normals="geometric").stats["kernel_options"]
    assert shading == geometric
