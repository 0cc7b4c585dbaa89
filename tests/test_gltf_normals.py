"""mbao.load: a glTF file's vertex normals (SPEC 3.3): read where the mesh has
them, carried by the inverse transpose of each node's transform, and zero where a
primitive has none. Expected normals come from numpy (tests/gltf_expected.py).
"""

import numpy as np
import pytest

from gltf_expected import (
    QUAD,
    QUAD_INDICES,
    QUAD_NORMALS,
    TRIANGLE,
    assert_close,
    container,
    load_clean,
    quaternion,
    rng,
    single_mesh_file,
    transform_normals,
    trs_matrix,
)
from gltf_writer import GltfBuilder, file_name


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
