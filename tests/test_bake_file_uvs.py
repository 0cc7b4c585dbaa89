"""Baked glTF files in UV sets they did not have: generated charts written as
the next free TEXCOORD_n, and files of other formats (OBJ) written as glTF with
their own UVs, materials and the bake."""

import numpy as np
import pytest

import mbao
from baked_files import floor_and_wall_obj, validation_errors
from conftest import shared_scene
from gltf_writer import GltfBuilder
from meshes import plane
from mbao._gltf import GltfDocument
from test_bake_gltf import floor_and_wall


def test_generated_uvs_are_written_as_the_next_free_set_with_seams_split(tmp_path):
    """The floor (two sets) gets TEXCOORD_2, the wall (one) TEXCOORD_1; the
    triangles keep their order and corners, and each corner's new UV is the one
    baked into (SPEC 6.5)."""
    source, output = floor_and_wall(tmp_path), tmp_path / "baked.glb"
    result = mbao.bake_file(
        source, output, target="texture", texcoord="generate", resolution=64, samples=4, progress=False
    )
    assert validation_errors(output) == []
    before, after = mbao.load(source, texcoords=True), mbao.load(output, texcoords=True)
    np.testing.assert_array_equal(after.vertices[after.indices], before.vertices[before.indices])
    document = GltfDocument(output)
    for material, new_set in ((0, 2), (1, 1)):
        assert document.doc["materials"][material]["occlusionTexture"]["texCoord"] == new_set
        texture = result.textures[material]
        written = after.uv_sets["sets"][new_set][after.indices[texture.triangles]]
        np.testing.assert_array_equal(written, texture.texcoords)


def test_a_strip_baked_into_generated_uvs_is_written_as_a_triangle_list(tmp_path):
    """A strip's triangles, rewritten with their seams split, are a list: the primitive's mode says so."""
    from gltf_writer import TRIANGLE_STRIP

    vertices, triangles = plane(1.0)
    corners = [triangles[0][0], triangles[0][1], triangles[0][2]] + [v for v in triangles[1] if v not in triangles[0]]
    builder = GltfBuilder()
    builder.add_scene([builder.add_node(mesh=builder.add_mesh([
        builder.primitive(vertices, corners, mode=TRIANGLE_STRIP)]))], default=True)  # fmt: skip
    source, output = builder.write(tmp_path / "strip.glb"), tmp_path / "baked.glb"
    mbao.bake_file(source, output, target="texture", texcoord="generate", resolution=32, samples=2, progress=False)
    assert validation_errors(output) == []
    assert GltfDocument(output).doc["meshes"][0]["primitives"][0]["mode"] == 4
    before, after = mbao.load(source), mbao.load(output)
    np.testing.assert_array_equal(after.vertices[after.indices], before.vertices[before.indices])


def test_generated_uvs_of_a_mesh_two_nodes_place_go_into_a_copy_each(tmp_path):
    b = GltfBuilder()
    floor = b.add_mesh([b.primitive(*plane(1.0, divisions=2))])
    b.add_scene([b.add_node(mesh=floor), b.add_node(mesh=floor, translation=(10, 0, 0))], default=True)
    source, output = b.write(tmp_path / "instances.glb"), tmp_path / "baked.glb"
    result = mbao.bake_file(
        source, output, target="texture", texcoord="generate", resolution=32, samples=2, progress=False
    )
    assert validation_errors(output) == []
    document = GltfDocument(output)
    assert [node["mesh"] for node in document.doc["nodes"]] == [0, 1]
    # Both placed floors, the copy too, get the material that holds the new occlusion texture.
    materials = {mesh["primitives"][0].get("material") for mesh in document.doc["meshes"]}
    assert len(materials) == 1 and "occlusionTexture" in document.doc["materials"][materials.pop()]
    assert result.textures[-1].stats["charts"] == 2  # one per placed floor
    after = mbao.load(output, texcoords=True)
    texture = result.textures[-1]
    np.testing.assert_array_equal(after.uv_sets["sets"][0][after.indices[texture.triangles]], texture.texcoords)


def test_the_damaged_helmet_baked_into_generated_uvs_is_valid(tmp_path):
    source = shared_scene("damaged_helmet") / "scene.glb"
    output = tmp_path / "helmet.glb"
    mbao.bake_file(source, output, target="texture", texcoord="generate", resolution=256, samples=2, progress=False)
    assert validation_errors(output) == []
    document = GltfDocument(output)
    assert document.doc["materials"][0]["occlusionTexture"]["texCoord"] == 2
    before, after = mbao.load(source), mbao.load(output)
    np.testing.assert_array_equal(after.vertices[after.indices], before.vertices[before.indices])
    assert len(after.vertices) > len(before.vertices)  # its 1296 charts' seams split vertices


def test_the_damaged_helmet_baked_per_vertex_keeps_its_materials_and_images(tmp_path):
    source = shared_scene("damaged_helmet") / "scene.glb"
    output = tmp_path / "helmet.glb"
    mbao.bake_file(source, output, samples=4, progress=False)
    assert validation_errors(output) == []
    before, after = GltfDocument(source), GltfDocument(output)
    for key in ("materials", "textures", "images", "samplers", "nodes"):
        assert after.doc[key] == before.doc[key], key
    assert after.bin[: len(before.bin)] == before.bin


@pytest.mark.parametrize("output", ["baked.glb", "baked.gltf"])
def test_a_file_of_another_format_is_written_as_gltf_with_its_bake(tmp_path, output):
    """An OBJ's vertex bake: a valid glTF of its triangles in world space and
    its normals, each vertex with the value mbao.bake gives the loaded file."""
    source = floor_and_wall_obj(tmp_path)
    result = mbao.bake_file(source, tmp_path / output, samples=8, progress=False)
    assert validation_errors(tmp_path / output) == []
    written = mbao.load(tmp_path / output)
    loaded = mbao.load(source)
    np.testing.assert_array_equal(written.vertices[written.indices], loaded.vertices[loaded.indices])
    np.testing.assert_array_equal(written.normals, loaded.normals)
    np.testing.assert_array_equal(result.values, mbao.bake(loaded, samples=8, progress=False).values)
    document = GltfDocument(tmp_path / output)
    primitive = document.doc["meshes"][0]["primitives"][0]
    occlusion = document.elements(primitive["attributes"]["_OCCLUSION"]).view("<f4").ravel()
    np.testing.assert_array_equal(occlusion, result.values)


def test_a_texture_bake_of_another_format_without_uvs_needs_generated_ones(tmp_path):
    source = floor_and_wall_obj(tmp_path)
    with pytest.raises(ValueError, match='floor_and_wall.obj: it has no UV sets; bake it with texcoord="generate"'):
        mbao.bake_file(source, tmp_path / "t.glb", target="texture")
    mbao.bake_file(
        source, tmp_path / "t.glb", target="texture", texcoord="generate", resolution=32, samples=2, progress=False
    )
    assert validation_errors(tmp_path / "t.glb") == []
    material = GltfDocument(tmp_path / "t.glb").doc["materials"][0]
    assert material["occlusionTexture"]["texCoord"] == 0
