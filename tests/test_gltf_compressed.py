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
    done = subprocess.run([str(GLTF_TRANSFORM), command, str(source), str(output), *options], capture_output=True,
                          text=True, timeout=600)
    assert done.returncode == 0, done.stderr[-3000:]
    return output


@pytest.fixture(scope="module", params=["cornell_box", "sponza"])
def quantized(request, tmp_path_factory):
    source = shared_scene(request.param) / "scene.glb"
    output = transformed("quantize", source, tmp_path_factory.mktemp("quantized") / "scene.glb",
                         "--quantize-position", str(POSITION_BITS))
    return request.param, source, output


def test_a_quantized_file_requires_the_extension_mbao_reads(quantized):
    _, _, output = quantized
    from mbao._gltf import GltfDocument

    assert GltfDocument(output).doc["extensionsRequired"] == ["KHR_mesh_quantization"]


def test_a_quantized_file_has_the_triangles_of_the_original_within_its_rounding(quantized):
    """Positions are stored on a grid of 2^14 - 1 steps across the longest side
    of a mesh's box, the same step on every axis (a uniform scale); the
    scene's box bounds every mesh's. A vertex lies within a step of where it was."""
    _, source, output = quantized
    original, read = mbao.load(source), mbao.load(output)
    assert read.triangle_count == original.triangle_count and read.warnings == []
    lo, hi = (np.asarray(corner) for corner in original.bounds)
    step = (hi - lo).max() / (2 ** POSITION_BITS - 1)
    error = np.abs(read.vertices[read.indices] - original.vertices[original.indices]).max(axis=(0, 1))
    assert np.all(error <= step), (error, step)
    assert np.all(error > 0)  # the file was quantized: positions moved


def test_a_quantized_file_renders_the_originals_image(quantized):
    """The same seed, so the same noise: where a rounded vertex moves a hit the
    image may differ, but the means agree within four standard errors of each."""
    name, source, output = quantized
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
    padded[:, :values[0].nbytes] = values.view(np.uint8).reshape(4, -1)
    builder = GltfBuilder()
    position = builder.add_accessor(builder.add_buffer_view(padded.tobytes(), byte_stride=stride), component_type, 4,
                                    3, normalized=normalized, min=corners.min(axis=0).tolist(),
                                    max=corners.max(axis=0).tolist())
    mesh = builder.add_mesh([builder.primitive(position_accessor=position, indices=[0, 1, 2, 0, 2, 3])])
    builder.add_scene([builder.add_node(mesh=mesh, scale=(2, 2, 2))], default=True)
    builder.doc["extensionsUsed"] = builder.doc["extensionsRequired"] = ["KHR_mesh_quantization"]
    return builder.write(tmp_path / "square.glb")


@pytest.mark.parametrize("component_type", [BYTE, UNSIGNED_BYTE, SHORT, UNSIGNED_SHORT],
                         ids=["BYTE", "UNSIGNED_BYTE", "SHORT", "UNSIGNED_SHORT"])
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
    builder.doc["extensionsUsed"] = builder.doc["extensionsRequired"] = ["KHR_mesh_quantization",
                                                                         "KHR_draco_mesh_compression"]
    with pytest.raises(mbao.LoadError, match=r"extensionsRequired lists KHR_draco_mesh_compression, which mbao does "
                                             r"not read"):
        mbao.load(builder.write(tmp_path / "draco.glb"))
