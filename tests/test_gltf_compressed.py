"""glTF files as a real client writes them compressed or quantized (glTF-Transform's
command line, which `make test` installs into tests/gltf_transform): they load
as the triangles of the original, within the encoding's own rounding, and render
its image."""

import math
import subprocess

import numpy as np
import pytest

import mbao
from conftest import REPO, shared_scene
from gltf_writer import BYTE, NUMPY_TYPE, SHORT, UNSIGNED_BYTE, UNSIGNED_SHORT, GltfBuilder

GLTF_TRANSFORM = REPO / "tests" / "gltf_transform" / "node_modules" / ".bin" / "gltf-transform"
POSITION_BITS = 14  # glTF-Transform's default, given explicitly so the bound below holds


def transformed(command, source, output, *options):
    if not GLTF_TRANSFORM.exists():
        pytest.fail("glTF-Transform is not installed: `make test` installs it into tests/gltf_transform")
    done = subprocess.run(
        [str(GLTF_TRANSFORM), command, str(source), str(output), *options], capture_output=True, text=True, timeout=600
    )
    assert done.returncode == 0, done.stderr[-3000:]
    return output


# glTF-Transform's commands, and the extension each file then requires.
ENCODINGS = {
    "quantize": "KHR_mesh_quantization",
    "draco": "KHR_draco_mesh_compression",
    "meshopt": "EXT_meshopt_compression",
}


@pytest.fixture(
    scope="module",
    params=[(scene, command) for scene in ("cornell_box", "sponza") for command in ENCODINGS],
    ids=lambda p: f"{p[0]}-{p[1]}",
)
def encoded(request, tmp_path_factory):
    """(scene name, command, the original's path, the encoded copy's path)."""
    name, command = request.param
    source = shared_scene(name) / "scene.glb"
    output = transformed(
        command, source, tmp_path_factory.mktemp(command) / "scene.glb", "--quantize-position", str(POSITION_BITS)
    )
    return name, command, source, output


def test_an_encoded_file_requires_the_extension_mbao_reads(encoded):
    from mbao._gltf import GltfDocument

    _, command, _, output = encoded
    assert ENCODINGS[command] in GltfDocument(output).doc["extensionsRequired"]


def position_step(scene):
    """Positions are stored on a grid of 2^14 - 1 steps across the longest
    side of a mesh's box, the same step on every axis (a uniform scale); the
    scene's box bounds every mesh's."""
    lo, hi = (np.asarray(corner) for corner in scene.bounds)
    return (hi - lo).max() / (2**POSITION_BITS - 1)


def triangle_areas(scene):
    a, b, c = (scene.vertices[scene.indices[:, k]].astype(np.float64) for k in range(3))
    return 0.5 * np.linalg.norm(np.cross(b - a, c - a), axis=1)


def test_an_encoded_file_has_the_originals_surface_within_its_rounding(encoded):
    """The same triangles (Draco and meshopt reorder them), each corner within a step of
    the grid: the bounds move by at most a step, the total area by at most a
    step times the perimeters (a corner's move changes its triangle's area by
    at most that times the opposite side)."""
    _, _, source, output = encoded
    original, read = mbao.load(source), mbao.load(output)
    assert read.triangle_count == original.triangle_count and read.warnings == []
    assert read.alpha_masks == original.alpha_masks
    step = position_step(original)
    np.testing.assert_allclose(np.array(read.bounds), np.array(original.bounds), rtol=0, atol=step)
    corners = original.vertices[original.indices].astype(np.float64)
    perimeters = sum(np.linalg.norm(corners[:, k] - corners[:, (k + 1) % 3], axis=1) for k in range(3))
    assert abs(triangle_areas(read).sum() - triangle_areas(original).sum()) <= step * perimeters.sum()


@pytest.mark.parametrize(
    "encoded", [("cornell_box", "quantize"), ("sponza", "quantize")], indirect=True, ids=["cornell_box", "sponza"]
)
def test_a_quantized_file_keeps_each_corner_within_a_step(encoded):
    """Quantization keeps the triangles' order (Draco and meshopt reorder them), so corner by corner."""
    _, _, source, output = encoded
    original, read = mbao.load(source), mbao.load(output)
    error = np.abs(read.vertices[read.indices] - original.vertices[original.indices]).max(axis=(0, 1))
    assert np.all(error <= position_step(original)), error
    assert np.all(error > 0)  # the file was quantized: positions moved


def test_an_encoded_file_renders_the_originals_image(encoded):
    """The same seed, so the same noise: where a rounded vertex moves a hit the
    image may differ, but the means agree within four standard errors of each."""
    name, _, source, output = encoded
    camera = mbao.Camera.load(str(source.parent / "camera.json"))
    settings = dict(camera=camera, width=96, height=96, samples=4, variance=True)
    original, read = mbao.render(mbao.load(source), **settings), mbao.render(mbao.load(output), **settings)
    if name == "cornell_box":  # large, axis-aligned walls: no edge moves across a pixel centre
        np.testing.assert_array_equal(read.mask, original.mask)
    covered = original.mask & read.mask
    difference = read.ao[covered].mean() - original.ao[covered].mean()
    standard_error = math.sqrt((read.variance[covered].sum() + original.variance[covered].sum())) / covered.sum()
    assert abs(difference) <= 4 * standard_error, (difference, standard_error)
    assert np.mean(read.ao != original.ao) < 0.2  # most pixels see the same surfaces, to the bit


def quantized_square(tmp_path, component_type, normalized):
    """A square whose positions are `component_type` integers (KHR_mesh_quantization), scaled by its node."""
    largest = {BYTE: 127, UNSIGNED_BYTE: 255, SHORT: 32767, UNSIGNED_SHORT: 65535}[component_type]
    corners = np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]]) * (largest if normalized else 3)
    values = corners.astype(NUMPY_TYPE[component_type])
    stride = -values[0].nbytes % 4 + values[0].nbytes  # vertex attributes' elements start 4-byte aligned
    padded = np.zeros((4, stride), np.uint8)
    padded[:, : values[0].nbytes] = values.view(np.uint8).reshape(4, -1)
    builder = GltfBuilder()
    position = builder.add_accessor(
        builder.add_buffer_view(padded.tobytes(), byte_stride=stride),
        component_type,
        4,
        3,
        normalized=normalized,
        min=corners.min(axis=0).tolist(),
        max=corners.max(axis=0).tolist(),
    )
    mesh = builder.add_mesh([builder.primitive(position_accessor=position, indices=[0, 1, 2, 0, 2, 3])])
    builder.add_scene([builder.add_node(mesh=mesh, scale=(2, 2, 2))], default=True)
    builder.doc["extensionsUsed"] = builder.doc["extensionsRequired"] = ["KHR_mesh_quantization"]
    return builder.write(tmp_path / "square.glb")


@pytest.mark.parametrize(
    "component_type",
    [BYTE, UNSIGNED_BYTE, SHORT, UNSIGNED_SHORT],
    ids=["BYTE", "UNSIGNED_BYTE", "SHORT", "UNSIGNED_SHORT"],
)
@pytest.mark.parametrize("normalized", [True, False], ids=["normalized", "integers"])
def test_quantized_positions_decode_as_gltf_says(tmp_path, component_type, normalized):
    """Normalized values are c / (2^n - 1) (unsigned) or max(c / (2^(n-1) - 1), -1) (signed); others are c."""
    scene = mbao.load(quantized_square(tmp_path, component_type, normalized))
    side = 2.0 * (1.0 if normalized else 3.0)
    np.testing.assert_allclose(scene.vertices, [[0, 0, 0], [side, 0, 0], [side, side, 0], [0, side, 0]], atol=1e-6)


def test_a_required_extension_mbao_lacks_is_named(tmp_path):
    builder = GltfBuilder()
    builder.add_scene([builder.add_node(mesh=builder.add_mesh([builder.primitive(
        np.float32([[0, 0, 0], [1, 0, 0], [0, 1, 0]]))]))], default=True)  # fmt: skip
    builder.doc["extensionsUsed"] = builder.doc["extensionsRequired"] = [
        "KHR_mesh_quantization",
        "EXT_mesh_gpu_instancing",
    ]
    with pytest.raises(
        mbao.LoadError, match=r"extensionsRequired lists EXT_mesh_gpu_instancing, which mbao does " r"not read"
    ):
        mbao.load(builder.write(tmp_path / "instanced.glb"))


def overwritten(glb, offset, data, output):
    """`output`: the GLB file `glb` with `data` at `offset` of its binary chunk (buffer 0)."""
    content = bytearray(glb.read_bytes())
    start = 20 + int.from_bytes(content[12:16], "little") + 8 + offset  # past the JSON chunk and the binary's header
    content[start : start + len(data)] = data
    output.write_bytes(bytes(content))
    return output


def test_a_draco_mesh_that_does_not_decode_is_named(tmp_path):
    """The file, the primitive and the extension named; no crash on bytes that are not a Draco mesh."""
    from mbao._gltf import GltfDocument

    output = transformed("draco", shared_scene("cornell_box") / "scene.glb", tmp_path / "draco.glb")
    document = GltfDocument(output)
    extension = document.doc["meshes"][0]["primitives"][0]["extensions"]["KHR_draco_mesh_compression"]
    view = document.doc["bufferViews"][extension["bufferView"]]
    broken = overwritten(output, view.get("byteOffset", 0), bytes(view["byteLength"]), tmp_path / "broken.glb")
    with pytest.raises(
        mbao.LoadError,
        match=r"broken.glb: mesh 0 primitive 0 KHR_draco_mesh_compression: its Draco " r"mesh does not decode",
    ):
        mbao.load(broken)


def test_a_meshopt_view_that_does_not_decode_is_named(tmp_path):
    """The file, the bufferView and the extension named; no crash on bytes that are not meshopt's encoding."""
    from mbao._gltf import GltfDocument

    output = transformed("meshopt", shared_scene("cornell_box") / "scene.glb", tmp_path / "meshopt.glb")
    document = GltfDocument(output)
    view = next(
        i for i, v in enumerate(document.doc["bufferViews"]) if "EXT_meshopt_compression" in v.get("extensions", {})
    )
    encoding = document.doc["bufferViews"][view]["extensions"]["EXT_meshopt_compression"]
    broken = overwritten(
        output, encoding.get("byteOffset", 0), bytes([0xFF]) * encoding["byteLength"], tmp_path / "broken.glb"
    )
    with pytest.raises(
        mbao.LoadError,
        match=rf"broken.glb: bufferView {view} EXT_meshopt_compression: its "
        rf"{encoding['mode']} data does not decode",
    ):
        mbao.load(broken)


def test_a_meshopt_count_beyond_what_its_bytes_can_hold_is_refused_unallocated(tmp_path):
    """meshoptimizer's densest encoding decodes to 64 times its bytes: a view that claims more is refused."""
    from mbao._gltf import GltfDocument

    document = GltfDocument(transformed("meshopt", shared_scene("cornell_box") / "scene.glb", tmp_path / "m.glb"))
    view, encoding = next(
        (i, v["extensions"]["EXT_meshopt_compression"])
        for i, v in enumerate(document.doc["bufferViews"])
        if "EXT_meshopt_compression" in v.get("extensions", {})
    )
    encoding["count"] = 2**30 // encoding["byteStride"]  # a GiB (tinygltf reads numbers as 32-bit ints)
    document.doc["bufferViews"][view]["byteLength"] = encoding["count"] * encoding["byteStride"]
    document.write(tmp_path / "huge.glb")
    with pytest.raises(
        mbao.LoadError,
        match=rf"huge.glb: bufferView {view} EXT_meshopt_compression has byteStride "
        rf"\d+ and count \d+, more than its \d+ encoded bytes can hold",
    ):
        mbao.load(tmp_path / "huge.glb")


@pytest.mark.parametrize(
    "mode, change, message",
    [
        ("ATTRIBUTES", {"byteStride": 6}, "has mode ATTRIBUTES and byteStride 6; it must be a multiple of 4 up to 256"),
        (
            "ATTRIBUTES",
            {"byteStride": 260},
            "has mode ATTRIBUTES and byteStride 260; it must be a multiple of 4 up to 256",
        ),
        ("TRIANGLES", {"byteStride": 3}, "has mode TRIANGLES and byteStride 3; it must be 2 or 4"),
        ("TRIANGLES", {"count": 4}, "has mode TRIANGLES and count 4, not a multiple of 3"),
        ("TRIANGLES", {"filter": "OCTAHEDRAL"}, "has mode TRIANGLES and filter OCTAHEDRAL; index modes take no filter"),
        ("ATTRIBUTES", {"filter": "QUATERNION", "byteStride": 4}, "has filter QUATERNION and byteStride 4"),
        ("ATTRIBUTES", {"filter": "OCTAHEDRAL", "byteStride": 12}, "has filter OCTAHEDRAL and byteStride 12"),
    ],
)
def test_a_meshopt_view_against_the_extensions_layout_rules_is_named(tmp_path, mode, change, message):
    """EXT_meshopt_compression's rules on strides, counts and filters, which meshoptimizer asserts (an
    abort) rather than checks, are checked before decoding."""
    from mbao._gltf import GltfDocument

    square = GltfBuilder()
    square.add_scene(
        [
            square.add_node(
                mesh=square.add_mesh(
                    [square.primitive(np.float32([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]]), [0, 1, 2, 0, 2, 3])]
                )
            )
        ],
        default=True,
    )
    document = GltfDocument(transformed("meshopt", square.write(tmp_path / "square.glb"), tmp_path / "meshopt.glb"))
    view, encoding = next(
        (i, v["extensions"]["EXT_meshopt_compression"])
        for i, v in enumerate(document.doc["bufferViews"])
        if v.get("extensions", {}).get("EXT_meshopt_compression", {}).get("mode") == mode
    )
    encoding.update(change)
    document.write(tmp_path / "bad.glb")
    with pytest.raises(mbao.LoadError, match=rf"bad.glb: bufferView {view} EXT_meshopt_compression {message}"):
        mbao.load(tmp_path / "bad.glb")
