"""mbao.load: glTF files it refuses, each with an error that names the file and
the element at fault (SPEC 3.2), and the versions and extensions it reads.

Every file here is written by tests/gltf_writer.py, so each test states its
whole input.
"""

import base64
import json
import re
import struct
import warnings

import numpy as np
import pytest

import mbao
from gltf_expected import (
    QUAD,
    QUAD_INDICES,
    QUAD_NORMALS,
    TRIANGLE,
    assert_load_error,
    container,
    load_clean,
    single_mesh_file,
    two_scene_file,
)
from gltf_writer import (
    BYTE,
    FLOAT,
    LINE_STRIP,
    LINES,
    POINTS,
    SHORT,
    UNSIGNED_INT,
    UNSIGNED_SHORT,
    GltfBuilder,
    file_name,
)


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
        "asset": {"version": "1.0"},
        "scene": "scene",
        "scenes": {"scene": {"nodes": ["node"]}},
        "nodes": {"node": {"meshes": ["mesh"], "children": []}},
        "meshes": {
            "mesh": {
                "primitives": [
                    {"attributes": {"POSITION": "positions"}, "indices": "indices", "mode": 4, "material": "material"}
                ]
            }
        },
        "materials": {"material": {"values": {}}},
        "accessors": {
            "positions": {
                "bufferView": "vertices",
                "byteOffset": 0,
                "byteStride": 12,
                "componentType": 5126,
                "count": len(positions),
                "type": "VEC3",
            },
            "indices": {
                "bufferView": "triangles",
                "byteOffset": 0,
                "componentType": 5123,
                "count": len(indices),
                "type": "SCALAR",
            },
        },
        "bufferViews": {
            "vertices": {"buffer": "data", "byteOffset": 0, "byteLength": position_bytes, "target": 34962},
            "triangles": {
                "buffer": "data",
                "byteOffset": position_bytes,
                "byteLength": len(data) - position_bytes,
                "target": 34963,
            },
        },
        "buffers": {
            "data": {
                "uri": "data:application/octet-stream;base64," + base64.b64encode(data).decode(),
                "byteLength": len(data),
                "type": "arraybuffer",
            }
        },
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
    np.testing.assert_array_equal(
        mbao.render(scene, camera=camera, width=8, height=8).mask,
        mbao.render(two, camera=camera, width=8, height=8).mask,
    )


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
