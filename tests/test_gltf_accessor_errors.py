"""mbao.load: glTF files whose accessors, buffer views, buffers, indices or
vertex attributes are at fault, each refused with an error that names the file
and the element (SPEC 3.2).

Every file here is written by tests/gltf_writer.py, so each test states its
whole input.
"""

import re

import numpy as np
import pytest

from gltf_expected import QUAD, QUAD_INDICES, QUAD_NORMALS, TRIANGLE, assert_load_error, container, single_mesh_file
from gltf_writer import BYTE, FLOAT, SHORT, UNSIGNED_INT, UNSIGNED_SHORT, GltfBuilder, file_name


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
    path = single_mesh_file(
        tmp_path / "ncount.gltf", lambda b: [b.primitive(QUAD, QUAD_INDICES, normals=QUAD_NORMALS[:3])]
    )
    assert_load_error(path, "mesh 0 primitive 0")


def test_index_count_must_be_a_multiple_of_3(tmp_path):
    path = single_mesh_file(tmp_path / "i4.gltf", lambda b: [b.primitive(TRIANGLE), b.primitive(QUAD, [0, 1, 2, 3])])
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
