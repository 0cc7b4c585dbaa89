"""mbao.load: glTF files it refuses, each with an error that names the file and
the element at fault (SPEC 3.2), and the versions and extensions it reads
(accessors, buffers and attributes at fault: test_gltf_accessor_errors.py).

Every file here is written by tests/gltf_writer.py, so each test states its
whole input.
"""

import base64
import json
import struct
import warnings

import numpy as np
import pytest

import mbao
from gltf_expected import QUAD, QUAD_INDICES, TRIANGLE, assert_load_error, load_clean, two_scene_file
from gltf_writer import LINE_STRIP, LINES, POINTS, GltfBuilder


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
