"""mbao.load: glTF 2.0 files (.gltf and .glb) into world-space triangles (SPEC 3.2).

Every file here is written by tests/gltf_writer.py, so each test states its
whole input. Expected positions and normals are computed with numpy.
"""

import base64
import json
import math
import os
import re
import struct
import subprocess
import sys
import warnings

import numpy as np
import pytest

import mbao
from gltf_writer import (
    BYTE,
    CONTAINERS,
    FLOAT,
    LINE_LOOP,
    LINE_STRIP,
    LINES,
    POINTS,
    SHORT,
    TRIANGLE_FAN,
    TRIANGLE_STRIP,
    TRIANGLES,
    UNSIGNED_BYTE,
    UNSIGNED_INT,
    UNSIGNED_SHORT,
    GltfBuilder,
    file_name,
)

# -- geometry and transforms, computed independently of the loader ------------

TRIANGLE = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0]], np.float32)
QUAD = np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]], np.float32)
QUAD_INDICES = np.array([[0, 1, 2], [0, 2, 3]])
QUAD_NORMALS = np.tile(np.float32([0, 0, 1]), (4, 1))


def quaternion(axis, degrees):
    """Unit quaternion (x, y, z, w) for a rotation about `axis`."""
    axis = np.asarray(axis, float) / np.linalg.norm(axis)
    half = math.radians(degrees) / 2
    return (*(axis * math.sin(half)), math.cos(half))


def rotation_matrix(q):
    x, y, z, w = q
    m = np.eye(4)
    m[:3, :3] = [
        [1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
        [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
        [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)],
    ]
    return m


def trs_matrix(translation=(0, 0, 0), rotation=(0, 0, 0, 1), scale=(1, 1, 1)):
    """glTF's local transform: T * R * S."""
    t = np.eye(4)
    t[:3, 3] = translation
    return t @ rotation_matrix(rotation) @ np.diag([*scale, 1.0])


def transform_points(matrix, points):
    points = np.asarray(points, np.float64)
    return (points @ matrix[:3, :3].T + matrix[:3, 3]).astype(np.float32)


def transform_normals(matrix, normals):
    """Inverse-transpose of the 3x3 part, then normalised."""
    n = np.asarray(normals, np.float64) @ np.linalg.inv(matrix[:3, :3])  # == (inv(M).T @ n.T).T
    return (n / np.linalg.norm(n, axis=1, keepdims=True)).astype(np.float32)


def random_trs(rng):
    axis = rng.normal(size=3)
    scale = rng.uniform(0.3, 3.0, size=3) * rng.choice([-1, 1], size=3)
    return {
        "translation": rng.uniform(-10, 10, size=3),
        "rotation": quaternion(axis, rng.uniform(0, 360)),
        "scale": scale,
    }


@pytest.fixture
def rng():
    return np.random.default_rng(20240611)


def assert_close(actual, expected, scale=1.0):
    """float32 agreement: 1e-5 relative, with an absolute floor for values near 0."""
    np.testing.assert_allclose(actual, expected, rtol=1e-5, atol=1e-6 * scale)


# -- loading helpers ---------------------------------------------------------------


def load_clean(path):
    """mbao.load, asserting that a well-formed file loads without any warning."""
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        scene = mbao.load(path)
    assert [str(w.message) for w in caught] == []
    assert scene.warnings == []
    return scene


def assert_load_error(path, *elements):
    """mbao.load(path) raises mbao.LoadError naming the file and every element given."""
    with pytest.raises(mbao.LoadError) as raised:
        mbao.load(path)
    message = str(raised.value)
    assert str(path) in message
    for element in elements:
        assert re.search(rf"\b{re.escape(element)}\b", message), f"{element!r} not named in: {message}"
    return message


def single_mesh_file(path, primitives_of, container=None, **node):
    """A file with one mesh (primitives_of(builder) gives its primitives) on one root node."""
    b = GltfBuilder()
    mesh = b.add_mesh(primitives_of(b))
    b.add_scene([b.add_node(mesh=mesh, **node)])
    return b.write(path, container)


@pytest.fixture(params=CONTAINERS)
def container(request):
    """Each of: .gltf with a data URI, .gltf with an external .bin, .glb."""
    return request.param


# == containers =====================================================================


def build_reference_scene():
    """A bit of everything: a hierarchy, TRS and matrix nodes, indexed and
    non-indexed primitives, normals on some primitives only, and a camera."""
    b = GltfBuilder()
    with_normals = b.primitive(QUAD, QUAD_INDICES, normals=QUAD_NORMALS, index_type=UNSIGNED_SHORT)
    plain = b.primitive(TRIANGLE)
    mesh = b.add_mesh([with_normals, plain])
    camera = b.add_perspective_camera(yfov=0.7)
    child = b.add_node(mesh=mesh, matrix=trs_matrix((0, 1, 0), quaternion((1, 0, 0), 30), (1, 2, 1)))
    eye = b.add_node(camera=camera, translation=(0, 0, 10))
    root = b.add_node(mesh=mesh, translation=(1, 2, 3), rotation=quaternion((0, 1, 0), 45), children=[child])
    b.add_scene([root, eye], default=True)
    return b


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


# == geometry in world space ======================================================


def test_mesh_without_transform_is_loaded_verbatim(tmp_path, container):
    path = single_mesh_file(tmp_path / file_name("quad", container),
                            lambda b: [b.primitive(QUAD, QUAD_INDICES)], container)
    scene = load_clean(path)
    np.testing.assert_array_equal(scene.vertices, QUAD)
    np.testing.assert_array_equal(scene.indices, QUAD_INDICES)
    assert scene.triangle_count == 2


# Hand-computed: where the local point (1, 0, 0) ends up.
@pytest.mark.parametrize(
    "node, expected",
    [
        ({"translation": (1, 2, 3)}, (2, 2, 3)),
        ({"rotation": quaternion((0, 0, 1), 90)}, (0, 1, 0)),
        ({"rotation": quaternion((0, 1, 0), 90)}, (0, 0, -1)),
        ({"scale": (2, 3, 4)}, (2, 0, 0)),
        # T * R * S: scaled first, then rotated, then translated.
        ({"translation": (10, 0, 0), "rotation": quaternion((0, 0, 1), 90), "scale": (2, 1, 1)}, (10, 2, 0)),
        ({"matrix": [[0, -2, 0, 10], [2, 0, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]]}, (10, 2, 0)),
    ],
    ids=["translation", "rotation_z", "rotation_y", "scale", "trs_order", "matrix"],
)
def test_node_transform_moves_vertices(tmp_path, node, expected):
    points = np.float32([[1, 0, 0], [0, 0, 0], [0, 1, 0]])
    path = single_mesh_file(tmp_path / "t.gltf", lambda b: [b.primitive(points)], **node)
    scene = load_clean(path)
    assert_close(scene.vertices[0], expected, scale=10)


def test_trs_nodes_match_numpy(tmp_path, rng):
    points = rng.uniform(-2, 2, size=(30, 3)).astype(np.float32)
    for i in range(5):
        node = random_trs(rng)
        path = single_mesh_file(tmp_path / f"trs{i}.gltf", lambda b: [b.primitive(points)], **node)
        assert_close(load_clean(path).vertices, transform_points(trs_matrix(**node), points), scale=30)


def test_matrix_is_read_column_major(tmp_path):
    # A translation lives in the last column; read row-major it would be a projective term.
    matrix = np.array([[1, 0, 0, 5], [0, 1, 0, 6], [0, 0, 1, 7], [0, 0, 0, 1]], float)
    path = single_mesh_file(tmp_path / "m.gltf", lambda b: [b.primitive(TRIANGLE)], matrix=matrix)
    assert_close(load_clean(path).vertices, TRIANGLE + np.float32([5, 6, 7]))


def test_general_affine_matrix_matches_numpy(tmp_path, rng):
    points = rng.uniform(-1, 1, size=(12, 3)).astype(np.float32)
    matrix = np.eye(4)
    matrix[:3, :] = rng.uniform(-3, 3, size=(3, 4))  # rotation, scale and shear
    path = single_mesh_file(tmp_path / "affine.gltf", lambda b: [b.primitive(points)], matrix=matrix)
    assert_close(load_clean(path).vertices, transform_points(matrix, points), scale=10)


def test_hierarchy_composes_parent_times_child(tmp_path, rng, container):
    # root (TRS) -> middle (matrix) -> leaf (TRS), a mesh on every level.
    root_trs, leaf_trs = random_trs(rng), random_trs(rng)
    middle_matrix = trs_matrix(**random_trs(rng))
    b = GltfBuilder()
    mesh = b.add_mesh([b.primitive(TRIANGLE, [0, 1, 2])])
    leaf = b.add_node(mesh=mesh, **leaf_trs)
    middle = b.add_node(mesh=mesh, matrix=middle_matrix, children=[leaf])
    root = b.add_node(mesh=mesh, children=[middle], **root_trs)
    b.add_scene([root])
    scene = load_clean(b.write(tmp_path / file_name("tree", container), container))

    world_root = trs_matrix(**root_trs)
    world_middle = world_root @ middle_matrix
    world_leaf = world_middle @ trs_matrix(**leaf_trs)
    expected = np.concatenate([transform_points(m, TRIANGLE) for m in (world_root, world_middle, world_leaf)])
    assert_close(scene.vertices, expected, scale=100)
    np.testing.assert_array_equal(scene.indices, [[0, 1, 2], [3, 4, 5], [6, 7, 8]])


def test_traversal_order_is_scene_roots_in_order_then_depth_first(tmp_path):
    # Each node has its own one-triangle mesh, told apart by its x offset.
    b = GltfBuilder()

    def node_with_triangle(x, children=()):
        mesh = b.add_mesh([b.primitive(TRIANGLE + np.float32([x, 0, 0]))])
        return b.add_node(mesh=mesh, children=list(children))

    grandchild = node_with_triangle(3)
    child_a = node_with_triangle(2, [grandchild])
    child_b = node_with_triangle(4)
    second_root = node_with_triangle(5)
    first_root = node_with_triangle(1, [child_a, child_b])
    b.add_scene([first_root, second_root])
    scene = load_clean(b.write(tmp_path / "order.gltf"))
    # Node indices are 0..4 in creation order; traversal must not follow them.
    np.testing.assert_array_equal(scene.vertices[::3, 0], [1, 2, 3, 4, 5])


def test_primitives_are_concatenated_with_their_indices_offset(tmp_path):
    b = GltfBuilder()
    first = b.primitive(QUAD, QUAD_INDICES)
    second = b.primitive(TRIANGLE + np.float32([0, 0, 1]), [2, 1, 0])
    mesh = b.add_mesh([first, second])
    b.add_scene([b.add_node(mesh=mesh)])
    scene = load_clean(b.write(tmp_path / "two.gltf"))
    np.testing.assert_array_equal(scene.vertices, np.concatenate([QUAD, TRIANGLE + np.float32([0, 0, 1])]))
    np.testing.assert_array_equal(scene.indices, [[0, 1, 2], [0, 2, 3], [6, 5, 4]])


def test_mesh_used_by_two_nodes_is_loaded_twice(tmp_path):
    b = GltfBuilder()
    mesh = b.add_mesh([b.primitive(TRIANGLE)])
    b.add_scene([b.add_node(mesh=mesh), b.add_node(mesh=mesh, translation=(0, 0, -2))])
    scene = load_clean(b.write(tmp_path / "instanced.gltf"))
    np.testing.assert_array_equal(scene.vertices, np.concatenate([TRIANGLE, TRIANGLE - np.float32([0, 0, 2])]))
    assert scene.triangle_count == 2


def test_nodes_outside_the_default_scene_are_not_loaded(tmp_path):
    b = GltfBuilder()
    mesh = b.add_mesh([b.primitive(TRIANGLE)])
    b.add_node(mesh=mesh, translation=(100, 0, 0))  # in no scene
    b.add_scene([b.add_node(mesh=mesh)])
    scene = load_clean(b.write(tmp_path / "orphan.gltf"))
    np.testing.assert_array_equal(scene.vertices, TRIANGLE)


# == indices ========================================================================


@pytest.mark.parametrize("index_type", [UNSIGNED_BYTE, UNSIGNED_SHORT, UNSIGNED_INT])
def test_8_16_and_32_bit_indices(tmp_path, index_type, container):
    indices = [[0, 1, 2], [2, 3, 0], [3, 2, 1]]
    path = single_mesh_file(tmp_path / file_name("idx", container),
                            lambda b: [b.primitive(QUAD, indices, index_type=index_type)], container)
    scene = load_clean(path)
    assert scene.indices.dtype == np.uint32
    np.testing.assert_array_equal(scene.indices, indices)


def test_16_bit_indices_above_255(tmp_path):
    vertices = np.zeros((300, 3), np.float32)
    vertices[:, 0] = np.arange(300)
    vertices[1::2, 1] = 1
    indices = [[0, 257, 299], [299, 1, 256]]
    path = single_mesh_file(tmp_path / "i16.gltf",
                            lambda b: [b.primitive(vertices, indices, index_type=UNSIGNED_SHORT)])
    np.testing.assert_array_equal(load_clean(path).indices, indices)


def test_32_bit_indices_above_65535(tmp_path):
    vertices = np.zeros((70_000, 3), np.float32)
    vertices[:, 0] = np.arange(70_000)
    vertices[1::2, 1] = 1
    indices = [[0, 65_537, 69_999]]
    path = single_mesh_file(tmp_path / "i32.glb",
                            lambda b: [b.primitive(vertices, indices, index_type=UNSIGNED_INT)])
    scene = load_clean(path)
    np.testing.assert_array_equal(scene.indices, indices)
    np.testing.assert_array_equal(scene.vertices[scene.indices[0], 0], [0, 65_537, 69_999])


def test_non_indexed_primitive_uses_consecutive_vertex_triples(tmp_path, container):
    vertices = np.concatenate([TRIANGLE, TRIANGLE + np.float32([0, 0, 1]), TRIANGLE + np.float32([0, 0, 2])])
    path = single_mesh_file(tmp_path / file_name("soup", container), lambda b: [b.primitive(vertices)], container)
    scene = load_clean(path)
    np.testing.assert_array_equal(scene.vertices, vertices)
    np.testing.assert_array_equal(scene.indices, [[0, 1, 2], [3, 4, 5], [6, 7, 8]])


def test_indexed_and_non_indexed_primitives_mix(tmp_path):
    b = GltfBuilder()
    mesh = b.add_mesh([b.primitive(TRIANGLE), b.primitive(QUAD, QUAD_INDICES, index_type=UNSIGNED_BYTE)])
    b.add_scene([b.add_node(mesh=mesh)])
    scene = load_clean(b.write(tmp_path / "mix.glb"))
    np.testing.assert_array_equal(scene.indices, [[0, 1, 2], [3, 4, 5], [3, 5, 6]])


# == normals (SPEC 3.3: vertex normals where the mesh has them) ====================


def test_normals_is_none_when_no_primitive_has_normals(tmp_path):
    b = GltfBuilder()
    mesh = b.add_mesh([b.primitive(QUAD, QUAD_INDICES), b.primitive(TRIANGLE)])
    b.add_scene([b.add_node(mesh=mesh)])
    assert load_clean(b.write(tmp_path / "flat.gltf")).normals is None


def test_normals_are_loaded_as_float32_rows(tmp_path, container):
    path = single_mesh_file(tmp_path / file_name("n", container),
                            lambda b: [b.primitive(QUAD, QUAD_INDICES, normals=QUAD_NORMALS)], container)
    normals = load_clean(path).normals
    assert normals.dtype == np.float32 and normals.shape == (4, 3)
    np.testing.assert_array_equal(normals, QUAD_NORMALS)


def test_normals_use_the_inverse_transpose_and_are_normalised(tmp_path, rng):
    normals = rng.normal(size=(4, 3)).astype(np.float32)
    normals /= np.linalg.norm(normals, axis=1, keepdims=True)
    # Non-uniform scale: the plain 3x3 would give wrong directions and lengths.
    node = {"translation": (3, 4, 5), "rotation": quaternion((1, 2, 3), 70), "scale": (4, 0.5, -2)}
    path = single_mesh_file(tmp_path / "n.gltf", lambda b: [b.primitive(QUAD, QUAD_INDICES, normals=normals)],
                            **node)
    loaded = load_clean(path).normals
    assert_close(loaded, transform_normals(trs_matrix(**node), normals))
    assert_close(np.linalg.norm(loaded, axis=1), np.ones(4))


def test_normals_follow_the_whole_hierarchy(tmp_path):
    parent = {"rotation": quaternion((0, 0, 1), 90), "scale": (1, 3, 1)}
    child = {"rotation": quaternion((1, 0, 0), -45), "scale": (2, 1, 1)}
    b = GltfBuilder()
    mesh = b.add_mesh([b.primitive(QUAD, QUAD_INDICES, normals=QUAD_NORMALS)])
    b.add_scene([b.add_node(children=[b.add_node(mesh=mesh, **child)], **parent)])
    world = trs_matrix(**parent) @ trs_matrix(**child)
    assert_close(load_clean(b.write(tmp_path / "h.gltf")).normals, transform_normals(world, QUAD_NORMALS))


@pytest.mark.parametrize("normals_first", [True, False], ids=["normals_first", "normals_second"])
def test_vertices_of_primitives_without_normals_get_zero_normals(tmp_path, normals_first):
    b = GltfBuilder()
    with_normals = b.primitive(QUAD, QUAD_INDICES, normals=QUAD_NORMALS)
    without = b.primitive(TRIANGLE)
    mesh = b.add_mesh([with_normals, without] if normals_first else [without, with_normals])
    b.add_scene([b.add_node(mesh=mesh)])
    scene = load_clean(b.write(tmp_path / "mixed.gltf"))
    blocks = [QUAD_NORMALS, np.zeros((3, 3))]
    expected = np.concatenate(blocks if normals_first else blocks[::-1])
    assert scene.normals.shape == scene.vertices.shape == (7, 3)
    np.testing.assert_array_equal(scene.normals, expected)


def test_zero_normals_also_between_meshes_of_different_nodes(tmp_path):
    b = GltfBuilder()
    plain = b.add_mesh([b.primitive(TRIANGLE)])
    smooth = b.add_mesh([b.primitive(QUAD, QUAD_INDICES, normals=QUAD_NORMALS)])
    b.add_scene([b.add_node(mesh=plain), b.add_node(mesh=smooth), b.add_node(mesh=plain)])
    normals = load_clean(b.write(tmp_path / "nodes.gltf")).normals
    np.testing.assert_array_equal(normals, np.concatenate([np.zeros((3, 3)), QUAD_NORMALS, np.zeros((3, 3))]))


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


@pytest.mark.parametrize("mode, expected", [
    (TRIANGLE_STRIP, [[0, 1, 2], [1, 3, 2], [2, 3, 4]]),  # glTF 2.0 3.7.2.1: p_i = v_i, v_i+(1+i%2), v_i+(2-i%2)
    (TRIANGLE_FAN, [[1, 2, 0], [2, 3, 0], [3, 4, 0]]),  # p_i = v_i+1, v_i+2, v_0
], ids=["strip", "fan"])
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


# == buffer layouts ================================================================


@pytest.mark.parametrize("byte_stride", [None, 32, 40], ids=["packed_24", "stride_32", "stride_40"])
def test_interleaved_positions_and_normals_with_byte_stride(tmp_path, container, byte_stride):
    normals = np.float32([[0, 0, 1], [0, 1, 0], [1, 0, 0], [0.6, 0.8, 0]])

    def primitives(b):
        position, normal = b.add_interleaved([QUAD, normals], byte_stride=byte_stride)
        return [b.primitive(position_accessor=position, normal_accessor=normal, indices=QUAD_INDICES)]

    scene = load_clean(single_mesh_file(tmp_path / file_name("inter", container), primitives, container))
    np.testing.assert_array_equal(scene.vertices, QUAD)
    assert_close(scene.normals, normals)


def test_accessor_byte_offset_inside_a_buffer_view(tmp_path):
    # Two vertices of padding in front of the triangle, skipped by byteOffset.
    data = np.concatenate([np.full((2, 3), 99, np.float32), TRIANGLE])

    def primitives(b):
        view = b.add_buffer_view(data.tobytes())
        return [b.primitive(position_accessor=b.add_accessor(view, FLOAT, 3, 3, byte_offset=24))]

    np.testing.assert_array_equal(load_clean(single_mesh_file(tmp_path / "off.gltf", primitives)).vertices, TRIANGLE)


# == sparse accessors ================================================================


@pytest.mark.parametrize("index_type", [UNSIGNED_BYTE, UNSIGNED_SHORT, UNSIGNED_INT])
def test_sparse_positions_replace_elements_of_the_base(tmp_path, container, index_type):
    moved = np.float32([[5, 5, 5], [7, 7, 7]])

    def primitives(b):
        position = b.add_sparse(4, indices=[1, 3], values=moved, base=QUAD, index_type=index_type)
        return [b.primitive(position_accessor=position, indices=QUAD_INDICES)]

    scene = load_clean(single_mesh_file(tmp_path / file_name("sparse", container), primitives, container))
    expected = QUAD.copy()
    expected[[1, 3]] = moved
    np.testing.assert_array_equal(scene.vertices, expected)


def test_sparse_accessor_without_buffer_view_starts_from_zeros(tmp_path):
    def primitives(b):
        position = b.add_sparse(3, indices=[1, 2], values=[[1, 0, 0], [0, 1, 0]], base=None)
        return [b.primitive(position_accessor=position)]

    scene = load_clean(single_mesh_file(tmp_path / "zeros.gltf", primitives, translation=(0, 0, 3)))
    assert_close(scene.vertices, TRIANGLE + np.float32([0, 0, 3]))


def test_sparse_normals(tmp_path):
    def primitives(b):
        normal = b.add_sparse(4, indices=[2], values=[[0, 0, -3]], base=QUAD_NORMALS)
        return [b.primitive(QUAD, QUAD_INDICES, normal_accessor=normal)]

    normals = load_clean(single_mesh_file(tmp_path / "sn.gltf", primitives)).normals
    np.testing.assert_array_equal(normals, [[0, 0, 1], [0, 0, 1], [0, 0, -1], [0, 0, 1]])


# == scenes =========================================================================


def two_scene_file(path, default=None):
    """Scene 0 holds a triangle at z = 0, scene 1 one at z = 1."""
    b = GltfBuilder()
    mesh = b.add_mesh([b.primitive(TRIANGLE)])
    b.add_scene([b.add_node(mesh=mesh)])
    b.add_scene([b.add_node(mesh=mesh, translation=(0, 0, 1))])
    if default is not None:
        b.doc["scene"] = default
    return b.write(path)


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


# == camera ===========================================================================


def camera_file(path, camera_node, parent=None, yfov=0.9):
    """A quad at the origin and one perspective camera on a node (under `parent` if given)."""
    b = GltfBuilder()
    mesh = b.add_mesh([b.primitive(QUAD, QUAD_INDICES)])
    camera = b.add_node(camera=b.add_perspective_camera(yfov), **camera_node)
    roots = [b.add_node(mesh=mesh)]
    roots.append(b.add_node(children=[camera], **parent) if parent else camera)
    b.add_scene(roots)
    return b.write(path)


def assert_camera(camera, world, yfov):
    """eye at the node's origin, looking down its -Z, up its +Y, vfov = yfov in degrees."""
    forward = world[:3, :3] @ [0, 0, -1]
    up = world[:3, :3] @ [0, 1, 0]
    eye = np.array(camera.eye)
    assert_close(eye, world[:3, 3], scale=10)
    direction = np.array(camera.target) - eye
    assert_close(direction / np.linalg.norm(direction), forward / np.linalg.norm(forward))
    assert_close(np.array(camera.up) / np.linalg.norm(camera.up), up / np.linalg.norm(up))
    assert camera.vfov_deg == pytest.approx(math.degrees(yfov), rel=1e-6)


def test_camera_at_a_translated_node_looks_down_minus_z(tmp_path, container):
    node = {"translation": (1, 2, 8)}
    scene = load_clean(camera_file(tmp_path / file_name("cam", container), node, yfov=0.9))
    assert isinstance(scene.camera, mbao.Camera)
    assert_camera(scene.camera, trs_matrix(**node), 0.9)
    assert_close(scene.camera.eye, (1, 2, 8))


def test_camera_orientation_follows_node_rotation_and_parents(tmp_path):
    node = {"translation": (0, 1, 4), "rotation": quaternion((1, 0.5, 0), -25)}
    parent = {"translation": (3, 0, 0), "rotation": quaternion((0, 1, 0), 120), "scale": (2, 2, 2)}
    scene = load_clean(camera_file(tmp_path / "rot.gltf", node, parent=parent, yfov=1.2))
    assert_camera(scene.camera, trs_matrix(**parent) @ trs_matrix(**node), 1.2)


def test_camera_is_the_first_perspective_one_of_the_default_scene(tmp_path):
    b = GltfBuilder()
    mesh = b.add_mesh([b.primitive(QUAD, QUAD_INDICES)])
    ortho = b.add_orthographic_camera()
    wide, narrow = b.add_perspective_camera(1.5), b.add_perspective_camera(0.3)
    outside = b.add_node(camera=narrow, translation=(0, 0, 99))  # not in the scene
    b.add_scene([
        b.add_node(mesh=mesh),
        b.add_node(camera=ortho, translation=(0, 0, 7)),
        b.add_node(children=[b.add_node(camera=wide, translation=(0, 0, 5))]),
        b.add_node(camera=narrow, translation=(0, 0, 3)),
    ])
    assert outside not in b.doc["scenes"][0]["nodes"]
    camera = load_clean(b.write(tmp_path / "cams.gltf")).camera
    np.testing.assert_array_equal(camera.eye, [0, 0, 5])
    assert camera.vfov_deg == pytest.approx(math.degrees(1.5), rel=1e-6)


@pytest.mark.parametrize("extras, radius", [({"max_distance": 2.5}, 2.5), ({"max_distance": 0}, None),
                                            ({"max_distance": "far"}, None), ({"other": 1}, None), (None, None)])
def test_a_cameras_extras_may_suggest_the_radius(tmp_path, extras, radius):
    b = GltfBuilder()
    mesh = b.add_mesh([b.primitive(QUAD, QUAD_INDICES)])
    b.add_scene([b.add_node(mesh=mesh), b.add_node(camera=b.add_perspective_camera(0.9, extras=extras),
                                                   translation=(0, 0, 3))])
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        scene = mbao.load(b.write(tmp_path / "radius.gltf"))
    assert scene.camera.max_distance == radius
    bad = extras is not None and "max_distance" in extras and radius is None
    assert any("extras.max_distance ignored" in str(w.message) for w in caught) == bad
    if radius is not None:  # render takes it as it takes camera.json's (SPEC 1)
        result = mbao.render(scene, width=4, height=4)
        assert (result.stats["max_distance"], result.stats["max_distance_source"]) == (radius, "camera")


def test_no_camera_when_the_default_scene_has_none(tmp_path):
    b = GltfBuilder()
    mesh = b.add_mesh([b.primitive(TRIANGLE)])
    b.add_node(camera=b.add_perspective_camera(0.5))  # a perspective camera, but in no scene
    b.add_scene([b.add_node(mesh=mesh, camera=b.add_orthographic_camera())])  # orthographic only
    assert load_clean(b.write(tmp_path / "nocam.gltf")).camera is None


# == the Scene API on a loaded file ===============================================


@pytest.fixture
def loaded(tmp_path):
    b = build_reference_scene()
    return load_clean(b.write(tmp_path / "reference.glb"))


def test_vertices_are_read_only_float32_rows(loaded):
    vertices = loaded.vertices
    assert vertices.dtype == np.float32 and vertices.ndim == 2 and vertices.shape[1] == 3
    assert not vertices.flags.writeable
    with pytest.raises(ValueError):
        vertices[0, 0] = 1.0


def test_indices_are_uint32_rows_into_vertices(loaded):
    indices = loaded.indices
    assert indices.dtype == np.uint32 and indices.shape == (loaded.triangle_count, 3)
    assert indices.max() < len(loaded.vertices)
    assert not indices.flags.writeable


def test_normals_have_one_row_per_vertex(loaded):
    assert loaded.normals.dtype == np.float32 and loaded.normals.shape == loaded.vertices.shape
    assert not loaded.normals.flags.writeable


def test_bounds_are_the_box_around_the_triangles(tmp_path, loaded):
    lo, hi = loaded.bounds
    assert_close(lo, loaded.vertices.min(axis=0), scale=10)
    assert_close(hi, loaded.vertices.max(axis=0), scale=10)

    # A vertex that no triangle uses does not count.
    points = np.concatenate([TRIANGLE, np.float32([[50, 50, 50]])])
    path = single_mesh_file(tmp_path / "unused.gltf", lambda b: [b.primitive(points, [0, 1, 2])])
    lo, hi = load_clean(path).bounds
    np.testing.assert_array_equal(lo, [0, 0, 0])
    np.testing.assert_array_equal(hi, [1, 1, 0])


def test_triangle_count_and_name(loaded):
    assert loaded.triangle_count == len(loaded.indices) == 6
    assert isinstance(loaded.name, str) and "reference.glb" in loaded.name


def test_render_uses_the_file_camera(tmp_path):
    # The camera looks down -Z (up +Y) at a big quad covering only x < 0, y > 0:
    # the top-left quarter of the image (row 0 is the top).
    b = GltfBuilder()
    quad = np.float32([[-100, 0, 0], [0, 0, 0], [0, 100, 0], [-100, 100, 0]])
    mesh = b.add_mesh([b.primitive(quad, QUAD_INDICES)])
    b.add_scene([b.add_node(mesh=mesh), b.add_node(camera=b.add_perspective_camera(1.0), translation=(0, 0, 5))])
    result = mbao.render(load_clean(b.write(tmp_path / "quarter.glb")), width=8, height=8, samples=1)
    expected = np.zeros((8, 8), bool)
    expected[:4, :4] = True
    np.testing.assert_array_equal(result.mask, expected)


def test_render_a_loaded_file_without_camera(tmp_path):
    scene = load_clean(single_mesh_file(tmp_path / "plain.gltf", lambda b: [b.primitive(QUAD, QUAD_INDICES)]))
    assert scene.camera is None
    result = mbao.render(scene, width=8, height=8, samples=1)
    assert result.mask.any()
    assert np.isfinite(result.ao).all()


# == errors ======================================================================


def test_load_error_is_an_mbao_error_is_a_runtime_error():
    assert issubclass(mbao.LoadError, mbao.Error)
    assert issubclass(mbao.Error, RuntimeError)


@pytest.mark.parametrize("suffix", [".gltf", ".glb"])
def test_missing_file(tmp_path, suffix):
    assert_load_error(tmp_path / f"does_not_exist{suffix}")


@pytest.mark.parametrize(
    "name, content, element",
    [
        ("garbage.gltf", b"\x00\x01\x02 this is not json {{{", "GLB"),
        ("garbage.glb", bytes(range(256)) * 4, "GLB"),
        ("empty.gltf", b"", "empty"),
        ("array.gltf", b"[1, 2, 3]", "JSON"),
        ("fake_magic.glb", b"glTF" + b"\xff" * 40, "version"),
        ("wrong_magic.glb", b"glTf" + bytes(40), "GLB"),
    ],
    ids=lambda value: value if isinstance(value, str) and "." in value else "",
)
def test_garbage_bytes(tmp_path, name, content, element):
    path = tmp_path / name
    path.write_bytes(content)
    assert_load_error(path, element)


def quad_glb():
    b = GltfBuilder()
    mesh = b.add_mesh([b.primitive(QUAD, QUAD_INDICES)])
    b.add_scene([b.add_node(mesh=mesh)])
    return b.glb_bytes()


@pytest.mark.parametrize("keep", [4, 11, 12, 20, -1, -13])
def test_truncated_glb(tmp_path, keep):
    path = tmp_path / "cut.glb"
    path.write_bytes(quad_glb()[:keep])
    assert_load_error(path, "GLB")


def test_truncated_gltf_json(tmp_path):
    b = GltfBuilder()
    b.add_scene([b.add_node(mesh=b.add_mesh([b.primitive(TRIANGLE)]))])
    path = tmp_path / "cut.gltf"
    path.write_text(b.gltf_text()[:-40])
    assert_load_error(path, "parse error")


def patched_glb(path, offset, value):
    """The quad's .glb with the uint32 at byte `offset` replaced."""
    data = bytearray(quad_glb())
    struct.pack_into("<I", data, offset, value)
    path.write_bytes(data)
    return path


@pytest.mark.parametrize("version", [0, 1, 3])
def test_glb_version_other_than_2(tmp_path, version):
    assert_load_error(patched_glb(tmp_path / "v.glb", 4, version), f"version {version}")


@pytest.mark.parametrize(
    "offset, part",
    [(8, "GLB header"), (12, "GLB JSON chunk"), (-1, "GLB BIN chunk")],
    ids=["total_length", "json_chunk", "bin_chunk"],
)
@pytest.mark.parametrize("length", [2**31, 2**32 - 1])
def test_glb_lengths_past_the_end_of_the_file(tmp_path, offset, part, length):
    if offset == -1:  # the BIN chunk's header follows the JSON chunk
        offset = 20 + struct.unpack_from("<I", quad_glb(), 12)[0]
    message = assert_load_error(patched_glb(tmp_path / "long.glb", offset, length), part)
    assert str(length) in message


@pytest.mark.parametrize(
    "asset, element",
    [({"version": "2.0", "minVersion": "2.1"}, "minVersion"), ({"version": "3.0"}, "asset.version")],
    ids=["min_version_2_1", "gltf_3"],
)
def test_gltf_other_than_1_and_2_0(tmp_path, asset, element):
    b = GltfBuilder()
    b.add_scene([b.add_node(mesh=b.add_mesh([b.primitive(TRIANGLE)]))])
    b.doc["asset"] = asset
    assert_load_error(b.write(tmp_path / "version.gltf"), element)


def gltf_1(positions, indices):
    """A glTF 1.0 document (objects keyed by id, not arrays) of one mesh, its buffer a data URI."""
    data = np.asarray(positions, "<f4").tobytes() + np.asarray(indices, "<u2").tobytes()
    position_bytes = 12 * len(positions)
    return {
        "asset": {"version": "1.0"}, "scene": "scene", "scenes": {"scene": {"nodes": ["node"]}},
        "nodes": {"node": {"meshes": ["mesh"], "children": []}},
        "meshes": {"mesh": {"primitives": [{"attributes": {"POSITION": "positions"}, "indices": "indices",
                                            "mode": 4, "material": "material"}]}},
        "materials": {"material": {"values": {}}},
        "accessors": {
            "positions": {"bufferView": "vertices", "byteOffset": 0, "byteStride": 12, "componentType": 5126,
                          "count": len(positions), "type": "VEC3"},
            "indices": {"bufferView": "triangles", "byteOffset": 0, "componentType": 5123, "count": len(indices),
                        "type": "SCALAR"}},
        "bufferViews": {"vertices": {"buffer": "data", "byteOffset": 0, "byteLength": position_bytes, "target": 34962},
                        "triangles": {"buffer": "data", "byteOffset": position_bytes,
                                      "byteLength": len(data) - position_bytes, "target": 34963}},
        "buffers": {"data": {"uri": "data:application/octet-stream;base64," + base64.b64encode(data).decode(),
                             "byteLength": len(data), "type": "arraybuffer"}},
    }


@pytest.mark.parametrize("version", ["1.0", 1], ids=["string", "number"])  # collada2gltf wrote the number 1
def test_gltf_1_loads_through_assimp(tmp_path, version):
    """SPEC 3.2: Assimp's importer reads glTF 1.0; the same triangles as its 2.0 form."""
    path = tmp_path / "one.gltf"
    path.write_text(json.dumps(dict(gltf_1(QUAD, QUAD_INDICES.ravel()), asset={"version": version})))
    scene = load_clean(path)
    b = GltfBuilder()
    b.add_scene([b.add_node(mesh=b.add_mesh([b.primitive(QUAD, QUAD_INDICES)]))])
    two = load_clean(b.write(tmp_path / "two.gltf"))
    np.testing.assert_array_equal(scene.vertices[scene.indices], two.vertices[two.indices])
    camera = mbao.Camera((0.3, 0.4, 3.0), (0.0, 0.0, 0.0))
    np.testing.assert_array_equal(mbao.render(scene, camera=camera, width=8, height=8).mask,
                                  mbao.render(two, camera=camera, width=8, height=8).mask)


def test_a_2_0_document_that_says_1_0_is_a_load_error_naming_it(tmp_path):
    b = GltfBuilder()
    b.add_scene([b.add_node(mesh=b.add_mesh([b.primitive(TRIANGLE)]))])
    b.doc["asset"] = {"version": "1.0"}
    with pytest.raises(mbao.LoadError, match="says_1.gltf"):
        mbao.load(b.write(tmp_path / "says_1.gltf"))


def test_required_extensions_are_refused_by_name(tmp_path):
    # Instances placed by the extension would be missing, silently.
    b = GltfBuilder()
    b.add_scene([b.add_node(mesh=b.add_mesh([b.primitive(TRIANGLE)]))])
    b.doc["extensionsUsed"] = b.doc["extensionsRequired"] = ["EXT_mesh_gpu_instancing"]
    assert_load_error(b.write(tmp_path / "instanced.glb"), "EXT_mesh_gpu_instancing", "extensionsRequired")


def test_extensions_used_but_not_required_are_ignored(tmp_path):
    b = GltfBuilder()
    b.add_scene([b.add_node(mesh=b.add_mesh([b.primitive(TRIANGLE)]))])
    b.doc["extensionsUsed"] = ["KHR_materials_emissive_strength"]
    np.testing.assert_array_equal(load_clean(b.write(tmp_path / "used.gltf")).vertices, TRIANGLE)


def test_missing_external_bin(tmp_path):
    b = GltfBuilder()
    mesh = b.add_mesh([b.primitive(TRIANGLE)])
    b.add_scene([b.add_node(mesh=mesh)])
    path = b.write_gltf_external(tmp_path / "lost.gltf")
    (tmp_path / "lost.bin").unlink()
    assert_load_error(path)


def mesh_of_two_primitives(b):
    """Primitive 0 a fine quad; primitive 1 a triangle (accessors 2 and 3 when indexed)."""
    return [b.primitive(QUAD, QUAD_INDICES), b.primitive(TRIANGLE, [0, 1, 2])]


def test_accessor_count_past_its_buffer_view(tmp_path, container):
    b = GltfBuilder()
    mesh = b.add_mesh(mesh_of_two_primitives(b))
    b.add_scene([b.add_node(mesh=mesh)])
    position = b.doc["meshes"][0]["primitives"][1]["attributes"]["POSITION"]
    assert position == 2
    b.doc["accessors"][position]["count"] = 4  # the view holds 3 vertices
    assert_load_error(b.write(tmp_path / file_name("long", container), container), f"accessor {position}")


def test_accessor_byte_offset_past_its_buffer_view(tmp_path):
    b = GltfBuilder()
    mesh = b.add_mesh(mesh_of_two_primitives(b))
    b.add_scene([b.add_node(mesh=mesh)])
    b.doc["accessors"][3]["byteOffset"] = 4  # indices: 3 uint32 in a 12-byte view
    assert_load_error(b.write(tmp_path / "offset.gltf"), "accessor 3")


def test_accessor_whose_buffer_view_does_not_exist(tmp_path):
    b = GltfBuilder()
    mesh = b.add_mesh(mesh_of_two_primitives(b))
    b.add_scene([b.add_node(mesh=mesh)])
    b.doc["accessors"][2]["bufferView"] = 9  # POSITION of primitive 1
    assert_load_error(b.write(tmp_path / "noview.gltf"), "accessor 2")


@pytest.mark.parametrize(
    "field, value",
    [("byteLength", 1000), ("byteLength", 2**40), ("byteOffset", 2**40), ("byteLength", 2**64 - 1)],
)
def test_buffer_view_past_the_end_of_its_buffer(tmp_path, field, value):
    b = GltfBuilder()
    mesh = b.add_mesh(mesh_of_two_primitives(b))
    b.add_scene([b.add_node(mesh=mesh)])
    b.doc["bufferViews"][2][field] = value
    assert_load_error(b.write(tmp_path / "shortbuffer.glb"), "accessor 2", "bufferView 2")


def test_buffer_view_stride_smaller_than_the_elements(tmp_path):
    b = GltfBuilder()
    mesh = b.add_mesh(mesh_of_two_primitives(b))
    b.add_scene([b.add_node(mesh=mesh)])
    b.doc["bufferViews"][2]["byteStride"] = 8  # POSITION of primitive 1: 12-byte elements
    assert_load_error(b.write(tmp_path / "stride.gltf"), "accessor 2", "bufferView 2", "byteStride")


@pytest.mark.parametrize(
    "container, element",
    [("glb", "byteLength"), ("gltf+bin", "buffer.bin"), ("gltf", "Buffer")],
)
def test_buffer_longer_than_its_data(tmp_path, container, element):
    # tinygltf checks buffers while parsing; its message names what it checked.
    b = GltfBuilder()
    b.add_scene([b.add_node(mesh=b.add_mesh([b.primitive(TRIANGLE)]))])
    b.buffer_byte_length = 2**40
    message = assert_load_error(b.write(tmp_path / file_name("buffer", container), container), element)
    assert container == "gltf" or str(2**40) in message


@pytest.mark.parametrize("bad_index", [3, 255, 100_000])
def test_index_out_of_vertex_range(tmp_path, container, bad_index):
    b = GltfBuilder()
    fine = b.primitive(QUAD, QUAD_INDICES)
    bad = b.primitive(TRIANGLE, [0, 1, bad_index], index_type=UNSIGNED_INT)
    mesh = b.add_mesh([fine, bad])
    b.add_scene([b.add_node(mesh=mesh)])
    message = assert_load_error(b.write(tmp_path / file_name("oob", container), container), "mesh 0 primitive 1")
    assert re.search(rf"\b{bad_index}\b", message.replace(str(tmp_path), ""))  # names the bad index


@pytest.mark.parametrize("index_type", [FLOAT, SHORT, BYTE], ids=["FLOAT", "SHORT", "BYTE"])
def test_unsupported_index_component_type(tmp_path, index_type):
    b = GltfBuilder()
    mesh = b.add_mesh([b.primitive(QUAD, QUAD_INDICES), b.primitive(TRIANGLE, [0, 1, 2], index_type=index_type)])
    b.add_scene([b.add_node(mesh=mesh)])
    assert b.doc["meshes"][0]["primitives"][1]["indices"] == 3
    assert_load_error(b.write(tmp_path / "itype.gltf"), "accessor 3")


def test_normals_must_be_float(tmp_path):
    def primitives(b):
        fine = b.primitive(QUAD, QUAD_INDICES)  # accessors 0 and 1
        normal = b.add_array(np.tile([0, 0, 127], (3, 1)), BYTE, 3)  # accessor 2
        return [fine, b.primitive(TRIANGLE, normal_accessor=normal)]

    assert_load_error(single_mesh_file(tmp_path / "byte_normals.gltf", primitives), "accessor 2", "NORMAL")


@pytest.mark.parametrize(
    "component_type, components",
    [(FLOAT, 2), (FLOAT, 4), (UNSIGNED_SHORT, 3), (BYTE, 3)],
    ids=["FLOAT_VEC2", "FLOAT_VEC4", "UNSIGNED_SHORT_VEC3", "BYTE_VEC3"],
)
def test_position_must_be_float_vec3(tmp_path, component_type, components):
    def primitives(b):
        fine = b.primitive(QUAD, QUAD_INDICES)  # accessors 0 and 1
        values = np.arange(3 * components).reshape(3, components)
        position = b.add_array(values, component_type, components)
        return [fine, b.primitive(position_accessor=position)]

    path = single_mesh_file(tmp_path / "pos.gltf", primitives)
    assert_load_error(path, "accessor 2")


def test_normal_count_must_match_position_count(tmp_path):
    path = single_mesh_file(tmp_path / "ncount.gltf",
                            lambda b: [b.primitive(QUAD, QUAD_INDICES, normals=QUAD_NORMALS[:3])])
    assert_load_error(path, "mesh 0 primitive 0")


def test_index_count_must_be_a_multiple_of_3(tmp_path):
    path = single_mesh_file(tmp_path / "i4.gltf",
                            lambda b: [b.primitive(TRIANGLE), b.primitive(QUAD, [0, 1, 2, 3])])
    assert_load_error(path, "mesh 0 primitive 1")


def test_non_indexed_vertex_count_must_be_a_multiple_of_3(tmp_path):
    path = single_mesh_file(tmp_path / "v4.gltf", lambda b: [b.primitive(QUAD)])
    assert_load_error(path, "mesh 0 primitive 0")


def test_sparse_index_past_the_accessor_count(tmp_path):
    def primitives(b):
        position = b.add_sparse(3, indices=[1, 3], values=[[5, 5, 5], [6, 6, 6]], base=TRIANGLE)
        return [b.primitive(position_accessor=position)]

    assert_load_error(single_mesh_file(tmp_path / "sparse_oob.gltf", primitives), "accessor 0")


@pytest.mark.parametrize("index_type", [SHORT, BYTE, FLOAT], ids=["SHORT", "BYTE", "FLOAT"])
def test_sparse_indices_must_be_unsigned_integers(tmp_path, index_type):
    # glTF allows only UNSIGNED_BYTE, UNSIGNED_SHORT and UNSIGNED_INT sparse indices.
    def primitives(b):
        position = b.add_sparse(3, indices=[1], values=[[5, 5, 5]], base=TRIANGLE, index_type=index_type)
        return [b.primitive(position_accessor=position)]

    assert_load_error(single_mesh_file(tmp_path / "sparse_type.gltf", primitives), "accessor 0")


@pytest.mark.parametrize(
    "children, culprit",
    [
        ({0: [1], 1: [2], 2: [1]}, "node 1"),  # 1 -> 2 -> 1
        ({0: [1], 1: [2], 2: [2]}, "node 2"),  # 2 is its own child
        ({0: [1], 1: [2], 2: [0]}, "node 0"),  # back to the root
    ],
    ids=["two_cycle", "self_loop", "back_to_root"],
)
def test_node_cycle(tmp_path, children, culprit):
    b = GltfBuilder()
    mesh = b.add_mesh([b.primitive(TRIANGLE)])
    for node in range(3):
        b.add_node(mesh=mesh, children=children[node])
    b.add_scene([0])
    assert_load_error(b.write(tmp_path / "cycle.gltf"), culprit)


def test_child_node_that_does_not_exist(tmp_path):
    b = GltfBuilder()
    mesh = b.add_mesh([b.primitive(TRIANGLE)])
    b.add_scene([b.add_node(mesh=mesh, children=[7])])
    assert_load_error(b.write(tmp_path / "child7.gltf"), "node 7")


def test_scene_root_that_does_not_exist(tmp_path):
    b = GltfBuilder()
    mesh = b.add_mesh([b.primitive(TRIANGLE)])
    b.add_scene([b.add_node(mesh=mesh), 5])
    assert_load_error(b.write(tmp_path / "root5.gltf"), "node 5")


def test_node_mesh_that_does_not_exist(tmp_path):
    b = GltfBuilder()
    mesh = b.add_mesh([b.primitive(TRIANGLE)])
    b.add_scene([b.add_node(mesh=mesh), b.add_node(mesh=4)])
    assert_load_error(b.write(tmp_path / "mesh4.gltf"), "node 1", "mesh 4")


@pytest.mark.parametrize("default", [2, 3, 100])
def test_default_scene_that_does_not_exist(tmp_path, default):
    assert_load_error(two_scene_file(tmp_path / "nosuchscene.gltf", default=default), f"scene {default}")


def test_file_with_no_scene(tmp_path):
    b = GltfBuilder()
    b.add_mesh([b.primitive(TRIANGLE)])
    b.add_node(mesh=0)
    assert_load_error(b.write(tmp_path / "sceneless.gltf"))


@pytest.mark.parametrize("layout", ["lines_only", "empty_scene", "nodes_without_meshes", "points_and_strips"])
def test_file_with_no_triangles_at_all(tmp_path, layout):
    b = GltfBuilder()
    if layout == "lines_only":
        b.add_scene([b.add_node(mesh=b.add_mesh([b.primitive(QUAD, [0, 1, 2, 3], mode=LINES)]))])
    elif layout == "empty_scene":
        b.add_mesh([b.primitive(TRIANGLE)])
        b.add_scene([])
    elif layout == "nodes_without_meshes":
        b.add_mesh([b.primitive(TRIANGLE)])
        b.add_scene([b.add_node(translation=(1, 0, 0), children=[b.add_node()])])
    else:
        mesh = b.add_mesh([b.primitive(QUAD, mode=POINTS), b.primitive(QUAD, [0, 1, 2, 3], mode=LINE_STRIP)])
        b.add_scene([b.add_node(mesh=mesh)])
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        message = assert_load_error(b.write(tmp_path / f"{layout}.gltf"))
    assert "triangle" in message


# == input that must not crash, hang or allocate what it declares ==================
#
# Each of these loads in a child process with 2 GiB of address space and a time
# limit, so that a regression fails its test (a crash, a timeout, a MemoryError)
# instead of taking pytest or the machine down.

CHILD_LOAD = """
import json, resource, sys
resource.setrlimit(resource.RLIMIT_AS, (2 << 30, 2 << 30))
import mbao
try:
    scene = mbao.load(sys.argv[1])
    print(json.dumps({"type": None, "triangles": scene.triangle_count, "warnings": scene.warnings}))
except Exception as e:
    print(json.dumps({"type": type(e).__name__, "message": str(e)}))
"""


def load_in_child(path, timeout=60):
    """What mbao.load(path) gives in a child process: {"type": None, "triangles": n,
    "warnings": [...]}, or the exception's {"type", "message"}."""
    done = subprocess.run([sys.executable, "-c", CHILD_LOAD, str(path)], capture_output=True, text=True,
                          timeout=timeout)
    assert done.returncode == 0, f"mbao.load crashed (exit {done.returncode}): {done.stderr[-3000:]}"
    return json.loads(done.stdout.splitlines()[-1])


def assert_child_load_error(path, *elements):
    outcome = load_in_child(path)
    assert outcome["type"] == "LoadError", outcome
    message = outcome["message"]
    assert str(path) in message
    for element in elements:
        assert re.search(rf"\b{re.escape(element)}\b", message), f"{element!r} not named in: {message}"
    return message


@pytest.mark.parametrize("count", [2**31, 2**40, 2**64 - 1])
@pytest.mark.parametrize("role", ["POSITION", "indices", "POSITION without bufferView"])
def test_huge_accessor_counts_are_refused_not_allocated(tmp_path, count, role):
    b = GltfBuilder()
    b.add_scene([b.add_node(mesh=b.add_mesh([b.primitive(TRIANGLE, [0, 1, 2])]))])
    accessor = 1 if role == "indices" else 0
    b.doc["accessors"][accessor]["count"] = count
    if role.endswith("without bufferView"):
        del b.doc["accessors"][accessor]["bufferView"]
    message = assert_child_load_error(b.write(tmp_path / "huge.glb"), f"accessor {accessor}")
    assert str(count) in message


@pytest.mark.parametrize("count", [2**31 - 1, 2**31, -1])
def test_huge_or_negative_sparse_counts(tmp_path, count):
    b = GltfBuilder()
    position = b.add_sparse(3, indices=[1], values=[[5, 5, 5]], base=TRIANGLE)
    b.add_scene([b.add_node(mesh=b.add_mesh([b.primitive(position_accessor=position)]))])
    b.doc["accessors"][position]["sparse"]["count"] = count
    assert_child_load_error(b.write(tmp_path / "sparse.gltf"), f"accessor {position}", "sparse")


@pytest.mark.parametrize("container", ["gltf", "glb"])
def test_deeply_nested_json_is_refused_before_parsing(tmp_path, container):
    # tinygltf copies `extras` recursively; 100000 levels would overflow its stack.
    b = GltfBuilder()
    b.add_scene([b.add_node(mesh=b.add_mesh([b.primitive(TRIANGLE)]))])
    b.doc["asset"]["extras"] = "x" * 199_998  # a string as long as the nesting, to keep GLB lengths right
    path = b.write(tmp_path / file_name("deep", container), container)
    path.write_bytes(path.read_bytes().replace(b'"' + b"x" * 199_998 + b'"', b"[" * 100_000 + b"]" * 100_000))
    assert_child_load_error(path, "JSON")


def test_json_nesting_up_to_the_limit_loads(tmp_path):
    b = GltfBuilder()
    b.add_scene([b.add_node(mesh=b.add_mesh([b.primitive(TRIANGLE)]))])
    b.doc["asset"]["extras"] = "@"
    path = b.write(tmp_path / "nested.gltf")
    # The document is one level, asset two, extras the third and deeper.
    path.write_text(path.read_text().replace('"@"', "[" * 126 + "]" * 126))
    np.testing.assert_array_equal(load_clean(path).vertices, TRIANGLE)
    path.write_text(path.read_text().replace("[" * 126, "[" * 127).replace("]" * 126, "]" * 127))
    assert_load_error(path, "128")


def test_a_deep_node_chain_loads_without_recursion(tmp_path):
    b = GltfBuilder()
    mesh = b.add_mesh([b.primitive(TRIANGLE)])
    depth = 100_000
    for i in range(depth):
        b.add_node(children=[i + 1]) if i < depth - 1 else b.add_node(mesh=mesh, translation=(0, 0, 1))
    b.add_scene([0])
    assert load_in_child(b.write(tmp_path / "chain.glb")) == {"type": None, "triangles": 1, "warnings": []}


@pytest.mark.parametrize(
    "children, roots, culprit",
    [
        ({0: [1, 2], 1: [3], 2: [3]}, [0], "node 3 is reached twice, from node 1 and from node 2"),
        ({0: [1, 1]}, [0], "node 0 lists node 1 twice"),
        ({0: [1]}, [0, 0], "the scene lists node 0 twice"),
        ({0: [1]}, [0, 1], "node 1 is reached twice, from node 0 and from the scene"),
    ],
    ids=["two_parents", "child_twice", "root_twice", "root_and_child"],
)
def test_node_reached_twice(tmp_path, children, roots, culprit):
    b = GltfBuilder()
    mesh = b.add_mesh([b.primitive(TRIANGLE)])
    for node in range(4):
        b.add_node(mesh=mesh, children=children.get(node))
    b.add_scene(roots)
    assert culprit in assert_load_error(b.write(tmp_path / "shared.gltf"))


def test_a_node_graph_that_doubles_at_every_level_is_refused_at_once(tmp_path):
    # 60 levels, each node listing the next twice: 2^60 paths to the mesh. The
    # first path is followed to the end, where the second child is refused.
    b = GltfBuilder()
    mesh = b.add_mesh([b.primitive(TRIANGLE)])
    for i in range(60):
        b.add_node(children=[i + 1, i + 1])
    b.add_node(mesh=mesh)
    b.add_scene([0])
    assert "node 59 lists node 60 twice" in assert_child_load_error(b.write(tmp_path / "doubling.glb"))


def test_a_directory_is_not_a_file(tmp_path):
    assert_load_error(tmp_path, "not a regular file")


def external_buffer_file(tmp_path, bin_name):
    b = GltfBuilder()
    b.add_scene([b.add_node(mesh=b.add_mesh([b.primitive(TRIANGLE)]))])
    path = tmp_path / "scene.gltf"
    path.write_text(b.gltf_text(bin_name))
    return path


def mask_image_file(tmp_path, uri):
    b = GltfBuilder()
    material = b.add_material(alpha_mode="MASK", texture=b.add_texture(b.add_image(b"", where="file",
                                                                                   file_name=uri)))
    b.files.clear()
    b.add_scene([b.add_node(mesh=b.add_mesh([b.primitive(QUAD, QUAD_INDICES, texcoords=QUAD[:, :2],
                                                           material=material)]))])
    return b.write(tmp_path / "masked.glb")


def assert_child_load_warns_of_image(path, *elements):
    """A load that skips its mask image, with a warning naming it: the surface is opaque (SPEC 3.2)."""
    outcome = load_in_child(path)
    assert outcome["type"] is None and outcome["triangles"] == 2, outcome
    warning = next((w for w in outcome["warnings"] if "the surface is opaque" in w), None)
    assert warning is not None, outcome["warnings"]
    for element in elements:
        assert re.search(rf"\b{re.escape(element)}\b", warning), f"{element!r} not named in: {warning}"


@pytest.mark.skipif(not hasattr(os, "mkfifo"), reason="needs FIFOs")
def test_an_external_fifo_buffer_is_refused_not_read(tmp_path):
    # Opening a FIFO with no writer blocks forever.
    os.mkfifo(tmp_path / "pipe")
    assert_child_load_error(external_buffer_file(tmp_path, "pipe"), "not a regular file")


@pytest.mark.skipif(not hasattr(os, "mkfifo"), reason="needs FIFOs")
def test_an_external_fifo_mask_image_is_skipped_not_read(tmp_path):
    os.mkfifo(tmp_path / "pipe")
    assert_child_load_warns_of_image(mask_image_file(tmp_path, "pipe"), "image 0", "not a regular file")


@pytest.mark.skipif(not os.path.exists("/dev/zero"), reason="needs /dev/zero")
def test_endless_device_as_a_mask_image_is_skipped_not_read(tmp_path):
    assert_child_load_warns_of_image(mask_image_file(tmp_path, "/dev/zero"), "image 0", "not a regular file")


def test_a_missing_mask_image_is_named_and_its_surface_is_opaque(tmp_path):
    """SPEC 3.2: no load fails for a texture."""
    with pytest.warns(UserWarning, match=r"masked.glb: material 0's image 0: cannot read .*missing.png: no such file; "
                                         r"the surface is opaque"):
        scene = mbao.load(mask_image_file(tmp_path, "missing.png"))
    assert scene.triangle_count == 2 and scene.alpha_masks is None


def test_a_jpeg_mask_image_is_not_opened(tmp_path):
    """A JPEG holds no alpha: the material's constant alpha alone cuts, and a missing one is no matter to AO."""
    scene = mbao.load(mask_image_file(tmp_path, "missing.jpg"))
    assert scene.triangle_count == 2 and scene.alpha_masks is None
    assert not [w for w in scene.warnings if "the surface is opaque" in w]
