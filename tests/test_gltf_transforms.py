"""mbao.load: a glTF file's geometry in world space (SPEC 3.2): node transforms
(TRS and matrices), hierarchies, the order nodes are visited, meshes used twice,
and primitives concatenated. Expected positions come from numpy (tests/gltf_expected.py).
"""

import numpy as np
import pytest

from gltf_expected import (
    QUAD,
    QUAD_INDICES,
    TRIANGLE,
    assert_close,
    container,
    load_clean,
    quaternion,
    random_trs,
    rng,
    single_mesh_file,
    transform_points,
    trs_matrix,
)
from gltf_writer import GltfBuilder, file_name


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
