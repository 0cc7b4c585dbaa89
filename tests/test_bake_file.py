"""Baked glTF files (mbao.bake_file, python -m mbao bake): the bake placed in
the file, everything else kept, and the Khronos glTF-Validator's verdict on
what mbao writes."""

import copy

import numpy as np
import pytest

import mbao
from gltf_writer import GltfBuilder
from meshes import plane
from mbao._gltf import GltfDocument
from baked_files import floor_and_wall_obj, validation_errors
from command_line import run_mbao
from test_bake_gltf import floor_and_wall


def accessor_rows(document, index, components):
    """An accessor of FLOAT values in a GLB file's binary chunk, as mbao writes them: (count, components)."""
    accessor = document.doc["accessors"][index]
    view = document.doc["bufferViews"][accessor["bufferView"]]
    assert view["buffer"] == 0 and accessor["componentType"] == 5126 and "byteStride" not in view
    start = view.get("byteOffset", 0) + accessor.get("byteOffset", 0)
    return np.frombuffer(document.bin, "<f4", accessor["count"] * components, start).reshape(-1, components)


def accessor_values(document, index):
    """An accessor of FLOAT SCALAR values, as mbao writes them."""
    assert document.doc["accessors"][index]["type"] == "SCALAR"
    return accessor_rows(document, index, 1).ravel()


def without(doc, pointers):
    """A copy of a glTF document without the members at `pointers` ((key, ...) paths)."""
    doc = copy.deepcopy(doc)
    for pointer in pointers:
        parent = doc
        for key in pointer[:-1]:
            parent = parent[key]
        del parent[pointer[-1]]
    return doc


def test_a_vertex_bake_adds_occlusion_and_keeps_everything_else(tmp_path):
    source = floor_and_wall(tmp_path)
    output = tmp_path / "baked.glb"
    result = mbao.bake_file(source, output, samples=16, progress=False)
    assert validation_errors(output) == []
    before, after = GltfDocument(source), GltfDocument(output)
    added = [("meshes", 0, "primitives", p, "attributes", "_OCCLUSION") for p in (0, 1)]
    kept = without(after.doc, added)
    for key, items in before.doc.items():
        if key in ("buffers", "bufferViews", "accessors"):  # grown by the new data, the old entries kept
            assert kept[key][: len(items)] == items if key != "buffers" else len(kept[key]) == len(items)
        else:
            assert kept[key] == items, key
    assert after.bin[: len(before.bin)] == before.bin
    scene = mbao.load(output, texcoords=True)
    for placed in scene.uv_sets["primitives"]:
        accessor = after.doc["meshes"][placed["mesh"]]["primitives"][placed["primitive"]]["attributes"]["_OCCLUSION"]
        first, end = placed["vertices"]
        np.testing.assert_array_equal(accessor_values(after, accessor), result.values[first:end])
    np.testing.assert_array_equal(scene.vertices, mbao.load(source).vertices)


def test_a_mesh_that_two_nodes_place_gets_a_copy_per_node(tmp_path):
    """The same floor in the open and under a low ceiling: two meshes in the
    output, each with its own AO (1 in the open, far less under the ceiling)."""
    b = GltfBuilder()
    floor = b.add_mesh([b.primitive(*plane(1.0, divisions=2))])
    vertices, indices = plane(1.2, y=0.2)
    ceiling = b.add_mesh([b.primitive(vertices, indices[:, ::-1])])  # facing down
    nodes = [
        b.add_node(mesh=floor),
        b.add_node(mesh=floor, translation=(10, 0, 0)),
        b.add_node(mesh=ceiling, translation=(10, 0, 0)),
    ]
    b.add_scene(nodes, default=True)
    source, output = b.write(tmp_path / "instances.glb"), tmp_path / "baked.glb"
    mbao.bake_file(source, output, bounces=1, samples=64, progress=False)
    assert validation_errors(output) == []
    after = GltfDocument(output)
    assert len(after.doc["meshes"]) == 3 and after.doc["nodes"][0]["mesh"] == 0
    copy_of_floor = after.doc["nodes"][1]["mesh"]
    assert copy_of_floor == 2 and after.doc["nodes"][2]["mesh"] == 1

    def occlusion(mesh):
        return accessor_values(after, after.doc["meshes"][mesh]["primitives"][0]["attributes"]["_OCCLUSION"])

    np.testing.assert_array_equal(occlusion(0), 1.0)
    assert occlusion(copy_of_floor).max() < 0.5


def test_vertex_colors_multiply_the_occlusion_into_color_0(tmp_path):
    """A primitive with normalized-byte RGBA colours gets them times the AO
    (alpha kept); one without gets the AO as its colour."""
    b = GltfBuilder()
    floor, indices = plane(1.0, divisions=2)
    colors = np.tile(np.array([[255, 128, 0, 200]], np.uint8), (len(floor), 1))
    painted = b.primitive(floor, indices)
    painted["attributes"]["COLOR_0"] = b.add_accessor(
        b.add_buffer_view(colors.tobytes()), 5121, len(floor), 4, normalized=True
    )
    wall = np.array([[-0.5, 0.0, 0.0], [0.5, 0.0, 0.0], [0.5, 1.0, 0.0], [-0.5, 1.0, 0.0]])
    bare = b.primitive(wall, [[0, 1, 2], [0, 2, 3]])
    b.add_scene([b.add_node(mesh=b.add_mesh([painted, bare]))], default=True)
    source, output = b.write(tmp_path / "painted.glb"), tmp_path / "baked.glb"
    result = mbao.bake_file(source, output, samples=16, vertex_colors=True, progress=False)
    assert validation_errors(output) == []
    after = GltfDocument(output)
    primitives = after.doc["meshes"][0]["primitives"]

    def color(primitive):
        accessor = after.doc["accessors"][primitive["attributes"]["COLOR_0"]]
        return accessor_rows(after, primitive["attributes"]["COLOR_0"], int(accessor["type"][-1]))

    ao = result.values.astype(np.float32)
    np.testing.assert_allclose(
        color(primitives[0]),
        np.column_stack([ao[:9] * 1.0, ao[:9] * (128 / 255), ao[:9] * 0.0, np.full(9, 200 / 255)]),
        rtol=1e-6,
    )
    np.testing.assert_allclose(color(primitives[1]), np.column_stack([ao[9:]] * 3), rtol=1e-6)
    with pytest.raises(ValueError, match='vertex_colors=True .* needs target="vertices"'):
        mbao.bake_file(source, tmp_path / "x.glb", target="texture", vertex_colors=True)


@pytest.mark.parametrize("bit_depth", [8, 16])
def test_a_texture_bake_points_each_material_at_its_texture(tmp_path, bit_depth):
    import OpenImageIO as oiio

    source = floor_and_wall(tmp_path)
    before = GltfDocument(source)
    before.doc["materials"][0]["occlusionTexture"]["strength"] = 0.7
    before.write(tmp_path / "with_strength.glb")
    source, output = tmp_path / "with_strength.glb", tmp_path / "baked.glb"
    result = mbao.bake_file(
        source, output, target="texture", resolution=(16, 8), samples=8, bit_depth=bit_depth, progress=False
    )
    assert validation_errors(output) == []
    assert result.stats["replaced_occlusion"] == [0]
    after = GltfDocument(output)
    for material, texture in result.textures.items():
        occlusion = after.doc["materials"][material]["occlusionTexture"]
        assert occlusion["texCoord"] == texture.texcoord
        assert occlusion.get("strength") == (0.7 if material == 0 else None)
        gltf_texture = after.doc["textures"][occlusion["index"]]
        # The floor's new texture keeps the sampler its occlusion texture had; the wall's has none (REPEAT).
        assert gltf_texture.get("sampler") == (before.doc["textures"][0]["sampler"] if material == 0 else None)
        image = after.doc["images"][gltf_texture["source"]]
        view = after.doc["bufferViews"][image["bufferView"]]
        png = tmp_path / f"occlusion{material}.png"
        png.write_bytes(after.bin[view["byteOffset"] : view["byteOffset"] + view["byteLength"]])
        decoded = oiio.ImageBuf(str(png))
        assert decoded.spec().format == (oiio.UINT16 if bit_depth == 16 else oiio.UINT8)
        pixels = decoded.get_pixels(oiio.FLOAT)
        assert pixels.shape == (8, 16, 3)
        for channel in range(3):
            np.testing.assert_allclose(pixels[..., channel], texture.image, atol=0.5 / (2**bit_depth - 1))
    assert after.doc["materials"][0]["pbrMetallicRoughness"] == before.doc["materials"][0]["pbrMetallicRoughness"]


def test_a_texture_baked_with_another_wrap_gets_a_sampler_that_wraps_so(tmp_path):
    """The floor's occlusion texture mirrors; baked with wrap="clamp-to-edge", its new texture must clamp."""
    source, output = floor_and_wall(tmp_path), tmp_path / "baked.glb"
    mbao.bake_file(source, output, target="texture", wrap="clamp-to-edge", resolution=16, samples=2, progress=False)
    assert validation_errors(output) == []
    document = GltfDocument(output)
    for material in document.doc["materials"]:
        sampler = document.doc["textures"][material["occlusionTexture"]["index"]]["sampler"]
        assert document.doc["samplers"][sampler] == {"wrapS": 33071, "wrapT": 33071}


def test_a_gltf_with_external_files_is_written_to_another_folder(tmp_path):
    b = GltfBuilder()
    b.add_scene([b.add_node(mesh=b.add_mesh([b.primitive(*plane(1.0, divisions=2))]))], default=True)
    source = b.write(tmp_path / "external.gltf", container="gltf+bin")
    assert any(
        "uri" in buffer and not buffer["uri"].startswith("data:") for buffer in GltfDocument(source).doc["buffers"]
    )
    (tmp_path / "out").mkdir()
    output = tmp_path / "out" / "baked.gltf"
    result = mbao.bake_file(source, output, samples=4, progress=False)
    assert validation_errors(output) == []
    np.testing.assert_array_equal(mbao.load(output).vertices, mbao.load(source).vertices)
    assert result.values.shape == (9,)


@pytest.mark.parametrize(
    "output, message",
    [
        ("baked.gltf", r"must be a \.glb file, as the input"),
        ("floor_and_wall.glb", "is the input"),
        ("missing/baked.glb", "cannot write in"),
    ],
)
def test_outputs_that_cannot_be_written_are_refused_before_the_bake(tmp_path, output, message):
    source = floor_and_wall(tmp_path)
    with pytest.raises(ValueError, match=message):
        mbao.bake_file(source, tmp_path / output, samples=2, progress=False)


# A texture bake of the floor and wall small enough for a test, as `python -m mbao bake` options.
SMALL_TEXTURE_BAKE = ("--target", "texture", "--resolution", 16, "--samples", 4, "--quiet")


def test_the_command_line_bakes_a_file(tmp_path):
    source = floor_and_wall(tmp_path)
    output = tmp_path / "baked.glb"
    run = run_mbao("bake", source, "-o", output, *SMALL_TEXTURE_BAKE, cwd=tmp_path)
    assert run.returncode == 0, run.stderr
    assert "replaced     material 0's occlusion texture" in run.stdout and f"wrote        {output}" in run.stdout
    assert validation_errors(output) == []
    generated = run_mbao(
        "bake",
        source,
        "-o",
        tmp_path / "g.glb",
        "--target",
        "texture",
        "--texcoord",
        "generate",
        "--resolution",
        "32",
        "16",
        "--samples",
        "2",
        "--quiet",
        cwd=tmp_path,
    )
    assert generated.returncode == 0, generated.stderr
    assert "32x16 into generated UVs" in generated.stdout and validation_errors(tmp_path / "g.glb") == []
    colored = run_mbao(
        "bake", source, "-o", tmp_path / "c.glb", "--vertex-colors", "--samples", "2", "--quiet", cwd=tmp_path
    )
    assert colored.returncode == 0, colored.stderr
    assert "darkens direct light too" in colored.stdout and validation_errors(tmp_path / "c.glb") == []
    assert "radius       inf (no camera suggests one)" in colored.stdout
    (tmp_path / "camera.json").write_text(
        '{"eye": [0, 1, 3], "target": [0, 0, 0], "up": [0, 1, 0], "vfov_deg": 60, "max_distance": 0.25}'
    )
    limited = run_mbao(
        "bake",
        source,
        "-o",
        tmp_path / "l.glb",
        "--camera",
        tmp_path / "camera.json",
        "--samples",
        "2",
        "--quiet",
        cwd=tmp_path,
    )
    assert limited.returncode == 0, limited.stderr
    assert "radius       0.25 (camera.json)" in limited.stdout
    obj = run_mbao(
        "bake", floor_and_wall_obj(tmp_path), "-o", tmp_path / "o.gltf", "--samples", "2", "--quiet", cwd=tmp_path
    )
    assert obj.returncode == 0, obj.stderr
    assert validation_errors(tmp_path / "o.gltf") == []
    obj_texture = run_mbao(
        "bake",
        floor_and_wall_obj(tmp_path),
        "-o",
        tmp_path / "ot.glb",
        "--target",
        "texture",
        "--texcoord",
        "generate",
        "--resolution",
        "32",
        "--samples",
        "2",
        "--quiet",
        cwd=tmp_path,
    )
    assert obj_texture.returncode == 0, obj_texture.stderr
    # Assimp gives an OBJ without materials one (its DefaultMaterial), which the file written keeps.
    assert "material 0   32x32 into generated UVs" in obj_texture.stdout and "material -1" not in obj_texture.stdout
    refused = run_mbao("bake", source, "-o", tmp_path / "x.gltf", cwd=tmp_path)
    assert refused.returncode == 2 and refused.stderr.startswith("mbao: output") and "must be a .glb" in refused.stderr


def test_the_command_line_bakes_on_a_dask_scheduler_the_same_file(tmp_path, dask_client):
    source = floor_and_wall(tmp_path)
    outputs = {}
    for name, extra in (("here", []), ("cluster", ["--scheduler", dask_client.scheduler.address])):
        outputs[name] = tmp_path / f"{name}.glb"
        run = run_mbao("bake", source, "-o", outputs[name], *SMALL_TEXTURE_BAKE, *extra, cwd=tmp_path)
        assert run.returncode == 0, run.stderr
    assert outputs["cluster"].read_bytes() == outputs["here"].read_bytes()
