"""mbao.load: how a glTF file's accessors are read (SPEC 3.2): 8, 16 and 32-bit
indices and none, interleaved and offset buffer layouts, and sparse accessors.
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
    single_mesh_file,
)
from gltf_writer import FLOAT, UNSIGNED_BYTE, UNSIGNED_INT, UNSIGNED_SHORT, GltfBuilder, file_name


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
