"""python -m mbao check FILE (issue 60): the Khronos glTF-Validator's verdict
on a glTF file, and the ambient occlusion the file stores, as mbao.load_bake
reads it."""

import os
import subprocess
import sys

import pytest

from command_line import run_mbao
from gltf_writer import GltfBuilder
from meshes import plane
from test_bake_gltf import floor_and_wall


def check(path, **environment):
    return subprocess.run(
        [sys.executable, "-m", "mbao", "check", str(path)],
        capture_output=True,
        text=True,
        env=dict(os.environ, **environment),
        timeout=300,
    )


def baked(tmp_path, *arguments):
    output = tmp_path / "baked.glb"
    run = run_mbao("bake", floor_and_wall(tmp_path), "-o", output, "--samples", 2, "--quiet", *arguments, cwd=tmp_path)
    assert run.returncode == 0, run.stderr
    return output


def test_a_vertex_bake_is_valid_and_its_values_are_summed_up(tmp_path):
    run = check(baked(tmp_path))
    assert run.returncode == 0, run.stderr
    assert "glTF         valid: 0 errors" in run.stdout
    assert "occlusion    _OCCLUSION on " in run.stdout and " vertices: min " in run.stdout


def test_a_texture_bake_names_its_materials_textures(tmp_path):
    run = check(baked(tmp_path, "--target", "texture", "--resolution", "16"))
    assert run.returncode == 0, run.stderr
    assert "occlusion texture 16x16 through TEXCOORD_" in run.stdout


def test_a_file_without_occlusion_says_so(tmp_path):
    b = GltfBuilder()
    b.add_scene([b.add_node(mesh=b.add_mesh([b.primitive(*plane(1.0))]))], default=True)
    run = check(b.write(tmp_path / "plain.glb"))
    assert run.returncode == 0, run.stderr
    assert "occlusion    none: no _OCCLUSION attribute and no occlusion texture" in run.stdout


def test_an_invalid_file_is_named_invalid_with_its_errors(tmp_path):
    b = GltfBuilder()
    b.add_scene([b.add_node(mesh=b.add_mesh([b.primitive(*plane(1.0))]))], default=True)
    b.doc["accessors"][0]["count"] += 1000  # past the end of its bufferView
    run = check(b.write(tmp_path / "broken.gltf"))
    assert run.returncode == 1
    assert "glTF         INVALID: " in run.stdout and "  error ACCESSOR_" in run.stdout


@pytest.mark.parametrize("name, message", [("scene.obj", "check reads glTF files"), ("missing.glb", "no such file")])
def test_what_it_cannot_check_is_named(tmp_path, name, message):
    run = check(tmp_path / name)
    assert run.returncode == 2 and run.stderr.startswith(f"mbao: {tmp_path / name}: {message}")


def test_a_missing_validator_says_how_to_install_it(tmp_path):
    run = check(baked(tmp_path), MBAO_GLTF_VALIDATOR=str(tmp_path / "nowhere"))
    assert run.returncode == 2
    assert "the Khronos glTF-Validator is not installed" in run.stderr and "make gltf-validator" in run.stderr
