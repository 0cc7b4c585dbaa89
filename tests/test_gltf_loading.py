"""mbao.load: glTF 2.0 files (.gltf and .glb) into world-space triangles (SPEC 3.2):
containers, transforms, indices, normals, primitive modes, buffer layouts,
sparse accessors and the default scene.

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
    QUAD_NORMALS,
    TRIANGLE,
    assert_close,
    build_reference_scene,
    container,
    load_clean,
    quaternion,
    random_trs,
    rng,
    single_mesh_file,
    transform_normals,
    transform_points,
    trs_matrix,
    two_scene_file,
)
from gltf_writer import (
    CONTAINERS,
    FLOAT,
    LINE_LOOP,
    LINE_STRIP,
    LINES,
    POINTS,
    TRIANGLE_FAN,
    TRIANGLE_STRIP,
    TRIANGLES,
    UNSIGNED_BYTE,
    UNSIGNED_INT,
    UNSIGNED_SHORT,
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


# == geometry in world space ======================================================


def test_mesh_without_transform_is_loaded_verbatim(tmp_path, container):
    path = single_mesh_file(
        tmp_path / file_name("quad", container), lambda b: [b.primitive(QUAD, QUAD_INDICES)], container
    )
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
    path = single_mesh_file(
        tmp_path / file_name("idx", container), lambda b: [b.primitive(QUAD, indices, index_type=index_type)], container
    )
    scene = load_clean(path)
    assert scene.indices.dtype == np.uint32
    np.testing.assert_array_equal(scene.indices, indices)


def test_16_bit_indices_above_255(tmp_path):
    vertices = np.zeros((300, 3), np.float32)
    vertices[:, 0] = np.arange(300)
    vertices[1::2, 1] = 1
    indices = [[0, 257, 299], [299, 1, 256]]
    path = single_mesh_file(
        tmp_path / "i16.gltf", lambda b: [b.primitive(vertices, indices, index_type=UNSIGNED_SHORT)]
    )
    np.testing.assert_array_equal(load_clean(path).indices, indices)


def test_32_bit_indices_above_65535(tmp_path):
    vertices = np.zeros((70_000, 3), np.float32)
    vertices[:, 0] = np.arange(70_000)
    vertices[1::2, 1] = 1
    indices = [[0, 65_537, 69_999]]
    path = single_mesh_file(tmp_path / "i32.glb", lambda b: [b.primitive(vertices, indices, index_type=UNSIGNED_INT)])
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
    path = single_mesh_file(
        tmp_path / file_name("n", container),
        lambda b: [b.primitive(QUAD, QUAD_INDICES, normals=QUAD_NORMALS)],
        container,
    )
    normals = load_clean(path).normals
    assert normals.dtype == np.float32 and normals.shape == (4, 3)
    np.testing.assert_array_equal(normals, QUAD_NORMALS)


def test_normals_use_the_inverse_transpose_and_are_normalised(tmp_path, rng):
    normals = rng.normal(size=(4, 3)).astype(np.float32)
    normals /= np.linalg.norm(normals, axis=1, keepdims=True)
    # Non-uniform scale: the plain 3x3 would give wrong directions and lengths.
    node = {"translation": (3, 4, 5), "rotation": quaternion((1, 2, 3), 70), "scale": (4, 0.5, -2)}
    path = single_mesh_file(tmp_path / "n.gltf", lambda b: [b.primitive(QUAD, QUAD_INDICES, normals=normals)], **node)
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
