"""mbao.load: glTF 2.0 files (.gltf and .glb) into world-space triangles (SPEC 3.2):
containers, primitive modes and the default scene (transforms: test_gltf_transforms.py;
indices, buffer layouts and sparse accessors: test_gltf_accessors.py; normals:
test_gltf_normals.py).

Every file here is written by tests/gltf_writer.py, so each test states its
whole input. Expected positions and normals are computed with numpy
(tests/gltf_expected.py).
"""

import json
import re
import warnings

import numpy as np
import pytest

import mbao
from gltf_expected import (
    QUAD,
    QUAD_INDICES,
    TRIANGLE,
    build_reference_scene,
    load_clean,
    single_mesh_file,
    two_scene_file,
)
from gltf_writer import (
    CONTAINERS,
    LINE_LOOP,
    LINE_STRIP,
    LINES,
    POINTS,
    TRIANGLE_FAN,
    TRIANGLE_STRIP,
    TRIANGLES,
    UNSIGNED_BYTE,
    GltfBuilder,
    file_name,
)


# == containers =====================================================================


def test_gltf_with_data_uri_with_external_bin_and_glb_load_identically(tmp_path):
    b = build_reference_scene()
    scenes = [load_clean(b.write(tmp_path / file_name(f"ref{i}", c), c)) for i, c in enumerate(CONTAINERS)]
    first = scenes[0]
    assert first.triangle_count == 2 * (2 + 1)
    for other in scenes[1:]:
        np.testing.assert_array_equal(other.vertices, first.vertices)
        np.testing.assert_array_equal(other.indices, first.indices)
        np.testing.assert_array_equal(other.normals, first.normals)
        assert other.bounds == first.bounds
        assert other.camera.eye == first.camera.eye
        assert other.camera.target == first.camera.target
        assert other.camera.up == first.camera.up
        assert other.camera.vfov_deg == first.camera.vfov_deg


@pytest.mark.parametrize("media_type, payload", [
    ("application/octet-stream", "@" * 12000),  # not base64
    ("text/plain", "QUJD" * 3000),  # base64, but not a buffer's media type
], ids=["not-base64", "not-a-buffer-media-type"])  # fmt: skip
def test_an_undecodable_data_uri_is_named_not_quoted_in_full(tmp_path, media_type, payload):
    b = GltfBuilder()
    b.add_scene([b.add_node(mesh=b.add_mesh([b.primitive(TRIANGLE, [0, 1, 2])]))])
    path = b.write(tmp_path / "scene.gltf", "gltf")
    doc = json.loads(path.read_text())
    uri = f"data:{media_type};base64,{payload}"
    doc["buffers"][0]["uri"] = uri
    path.write_text(json.dumps(doc))
    with pytest.raises(mbao.LoadError) as raised:
        mbao.load(path)
    message = str(raised.value)
    assert re.search(rf"data:{media_type};base64,{re.escape(payload[:16])}\.\.\. \({len(uri)} characters\)", message)
    assert len(message) < 200 + len(str(path)), message
    assert not message.endswith("\n")


@pytest.mark.parametrize("name_length", [1, 2, 3, 4])
def test_glb_json_chunk_padded_with_spaces_loads(tmp_path, name_length):
    # Different node name lengths give each of the four JSON paddings.
    b = GltfBuilder()
    mesh = b.add_mesh([b.primitive(TRIANGLE, [0, 1, 2])])
    b.add_scene([b.add_node(mesh=mesh, name="n" * name_length)])
    scene = load_clean(b.write_glb(tmp_path / "padded.glb"))
    np.testing.assert_array_equal(scene.vertices, TRIANGLE)


def test_glb_bin_chunk_padded_with_zeros_loads(tmp_path):
    # One UNSIGNED_BYTE index triple leaves the buffer at a length that needs padding.
    b = GltfBuilder()
    mesh = b.add_mesh([b.primitive(TRIANGLE, [2, 1, 0], index_type=UNSIGNED_BYTE)])
    b.add_scene([b.add_node(mesh=mesh)])
    assert len(b.bin) % 4 != 0
    scene = load_clean(b.write_glb(tmp_path / "bin_padded.glb"))
    np.testing.assert_array_equal(scene.indices, [[2, 1, 0]])


def test_path_may_be_str_or_pathlib(tmp_path):
    path = single_mesh_file(tmp_path / "tri.gltf", lambda b: [b.primitive(TRIANGLE)])
    np.testing.assert_array_equal(load_clean(str(path)).vertices, load_clean(path).vertices)


def test_external_bin_file_is_read_from_next_to_the_gltf(tmp_path):
    b = GltfBuilder()
    mesh = b.add_mesh([b.primitive(QUAD, QUAD_INDICES)])
    b.add_scene([b.add_node(mesh=mesh)])
    path = b.write_gltf_external(tmp_path / "scene.gltf", bin_name="data_elsewhere.bin")
    assert (tmp_path / "data_elsewhere.bin").exists()
    scene = load_clean(path)
    np.testing.assert_array_equal(scene.vertices, QUAD)
    np.testing.assert_array_equal(scene.indices, QUAD_INDICES)


# == primitive modes ================================================================


@pytest.mark.parametrize("mode", [POINTS, LINES, LINE_LOOP, LINE_STRIP])
def test_points_and_lines_are_skipped_with_a_warning(tmp_path, mode):
    b = GltfBuilder()
    kept = b.primitive(TRIANGLE, [0, 1, 2])
    skipped = b.primitive(QUAD + np.float32([0, 0, 9]), [0, 1, 2, 3, 0, 2], mode=mode)
    mesh = b.add_mesh([kept, skipped])
    b.add_scene([b.add_node(mesh=mesh)])
    path = b.write(tmp_path / "modes.gltf")
    with pytest.warns(UserWarning, match=r"mesh 0 primitive 1\b") as caught:
        scene = mbao.load(path)
    np.testing.assert_array_equal(scene.vertices, TRIANGLE)  # nothing of the skipped primitive
    np.testing.assert_array_equal(scene.indices, [[0, 1, 2]])
    assert len(scene.warnings) == 1
    assert "mesh 0 primitive 1" in scene.warnings[0] and str(path) in scene.warnings[0]
    assert [str(w.message) for w in caught] == scene.warnings


@pytest.mark.parametrize(
    "mode, expected",
    [
        (TRIANGLE_STRIP, [[0, 1, 2], [1, 3, 2], [2, 3, 4]]),  # glTF 2.0 3.7.2.1: p_i = v_i, v_i+(1+i%2), v_i+(2-i%2)
        (TRIANGLE_FAN, [[1, 2, 0], [2, 3, 0], [3, 4, 0]]),  # p_i = v_i+1, v_i+2, v_0
    ],
    ids=["strip", "fan"],
)
@pytest.mark.parametrize("indexed", [True, False], ids=["indexed", "not indexed"])
def test_strips_and_fans_are_the_triangles_glTF_defines(tmp_path, mode, expected, indexed):
    """Their corners in glTF's order (`expected` counts in the primitive's
    corners), so that every triangle faces as the file means; the fan's last
    triangle comes back to vertex 0, a degenerate one as in the file."""
    corners = [0, 1, 2, 3, 0]
    vertices = QUAD[corners] if not indexed else QUAD
    b = GltfBuilder()
    b.add_scene([b.add_node(mesh=b.add_mesh([b.primitive(vertices, corners if indexed else None, mode=mode)]))])
    scene = load_clean(b.write(tmp_path / "strip.glb"))
    np.testing.assert_array_equal(scene.vertices[scene.indices], QUAD[np.array(corners)[np.array(expected)]])


def test_explicit_triangles_mode_is_loaded_without_warning(tmp_path):
    path = single_mesh_file(tmp_path / "m4.gltf", lambda b: [b.primitive(QUAD, QUAD_INDICES, mode=TRIANGLES)])
    assert load_clean(path).triangle_count == 2


def test_each_skipped_primitive_gets_its_own_warning(tmp_path):
    b = GltfBuilder()
    lines = b.add_mesh([b.primitive(QUAD, [0, 1, 1, 2], mode=LINES)])
    mixed = b.add_mesh([b.primitive(TRIANGLE), b.primitive(QUAD, [0, 1, 2, 3], mode=LINE_STRIP)])
    b.add_scene([b.add_node(mesh=lines), b.add_node(mesh=mixed)])
    with pytest.warns(UserWarning):
        scene = mbao.load(b.write(tmp_path / "two_skips.glb"))
    assert scene.triangle_count == 1
    assert len(scene.warnings) == 2
    assert "mesh 0 primitive 0" in scene.warnings[0]
    assert "mesh 1 primitive 1" in scene.warnings[1]


# == scenes =========================================================================


def test_default_scene_is_the_one_named_by_scene(tmp_path):
    scene = load_clean(two_scene_file(tmp_path / "s1.gltf", default=1))
    np.testing.assert_array_equal(scene.vertices, TRIANGLE + np.float32([0, 0, 1]))


def test_default_scene_0_when_named(tmp_path):
    scene = load_clean(two_scene_file(tmp_path / "s0.gltf", default=0))
    np.testing.assert_array_equal(scene.vertices, TRIANGLE)


def test_scene_0_when_no_default_scene_is_set(tmp_path):
    with warnings.catch_warnings():  # whether this is worth a warning is the loader's call
        warnings.simplefilter("ignore")
        scene = mbao.load(two_scene_file(tmp_path / "none.gltf"))
    np.testing.assert_array_equal(scene.vertices, TRIANGLE)
