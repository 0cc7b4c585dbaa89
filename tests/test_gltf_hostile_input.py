"""mbao.load: glTF input that must not crash, hang or allocate what it declares:
huge counts, deep nesting, node graphs that repeat, and files that are not files.
"""

import json
import os
import re
import subprocess
import sys

import numpy as np
import pytest

import mbao
from gltf_expected import QUAD, QUAD_INDICES, TRIANGLE, assert_load_error, container, load_clean
from gltf_writer import GltfBuilder, file_name


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
    done = subprocess.run(
        [sys.executable, "-c", CHILD_LOAD, str(path)], capture_output=True, text=True, timeout=timeout
    )
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
    material = b.add_material(alpha_mode="MASK", texture=b.add_texture(b.add_image(b"", where="file", file_name=uri)))
    b.files.clear()
    b.add_scene(
        [b.add_node(mesh=b.add_mesh([b.primitive(QUAD, QUAD_INDICES, texcoords=QUAD[:, :2], material=material)]))]
    )
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
    with pytest.warns(
        UserWarning,
        match=r"masked.glb: material 0's image 0: cannot read .*missing.png: no such file; " r"the surface is opaque",
    ):
        scene = mbao.load(mask_image_file(tmp_path, "missing.png"))
    assert scene.triangle_count == 2 and scene.alpha_masks is None


def test_a_jpeg_mask_image_is_not_opened(tmp_path):
    """A JPEG holds no alpha: the material's constant alpha alone cuts, and a
    missing one is no matter to AO. Nothing looks for the file, so nothing warns."""
    scene = mbao.load(mask_image_file(tmp_path, "missing.jpg"))
    assert scene.triangle_count == 2 and scene.alpha_masks is None
    assert scene.warnings == []
