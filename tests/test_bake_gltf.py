"""Texture bakes of glTF files (SPEC 6.3): the UV sets, materials and samplers
that mbao.load(texcoords=True) reads, the UV set each material is baked into,
and the refusals that name the material."""

import numpy as np
import pytest

import mbao
from conftest import shared_scene
from gltf_writer import GltfBuilder, png_bytes
from meshes import plane

MIRRORED_REPEAT = 33648


def floor_and_wall(tmp_path):
    """Material 0: a floor (y = 0, facing up) whose TEXCOORD_0 tiles twice and
    whose TEXCOORD_1 covers [0, 1] once, with an occlusion texture reading
    TEXCOORD_1 through a MIRRORED_REPEAT sampler. Material 1: a wall standing
    on it (z = 0, facing +z) with TEXCOORD_0 only and no occlusion texture."""
    b = GltfBuilder()
    floor, floor_indices = plane(1.0, divisions=4)
    once = (floor[:, [0, 2]] + 1.0) / 2.0
    wall = np.array([[-0.5, 0.0, 0.0], [0.5, 0.0, 0.0], [0.5, 1.0, 0.0], [-0.5, 1.0, 0.0]])
    image = b.add_image(png_bytes(np.full((4, 4), 255, np.uint8), tmp_path))
    occlusion = b.add_texture(image, wrap_s=MIRRORED_REPEAT, wrap_t=MIRRORED_REPEAT)
    floor_material = b.add_material()
    b.doc["materials"][floor_material]["occlusionTexture"] = {"index": occlusion, "texCoord": 1}
    wall_material = b.add_material()
    b.doc["materials"][wall_material]["name"] = "wall"
    floor_primitive = b.primitive(floor, floor_indices, texcoords=2.0 * once, material=floor_material)
    floor_primitive["attributes"]["TEXCOORD_1"] = b.add_texcoords(once)
    wall_primitive = b.primitive(
        wall, [[0, 1, 2], [0, 2, 3]], texcoords=wall[:, :2] * [1.0, 0.5] + [0.5, 0.0], material=wall_material
    )
    b.add_scene([b.add_node(mesh=b.add_mesh([floor_primitive, wall_primitive]))], default=True)
    return b.write(tmp_path / "floor_and_wall.glb")


def test_load_reads_uv_sets_only_when_asked(tmp_path):
    path = floor_and_wall(tmp_path)
    assert mbao.load(path).uv_sets is None
    uv_sets = mbao.load(path, texcoords=True).uv_sets
    floor_vertices = 25
    assert [s.shape for s in uv_sets["sets"]] == [(29, 2), (29, 2)]
    assert np.isfinite(uv_sets["sets"][0]).all()
    assert (
        np.isfinite(uv_sets["sets"][1][:floor_vertices]).all() and np.isnan(uv_sets["sets"][1][floor_vertices:]).all()
    )
    np.testing.assert_array_equal(uv_sets["triangle_materials"], [0] * 32 + [1] * 2)
    assert uv_sets["materials"][0]["occlusion_texcoord"] == 1
    assert uv_sets["materials"][0]["wrap"] == ("mirrored-repeat", "mirrored-repeat")
    assert uv_sets["materials"][1] == dict(
        name="wall", occlusion_texcoord=None, wrap=("repeat", "repeat"), base_color=None
    )  # read for bake_file from other formats only


def test_each_material_is_baked_into_its_own_set(tmp_path):
    """The floor into its occlusion texture's TEXCOORD_1 with that sampler, the
    wall, which has no TEXCOORD_1, into TEXCOORD_0 (SPEC 6.3)."""
    bake = mbao.bake(floor_and_wall(tmp_path), target="texture", resolution=16, samples=64, progress=False)
    assert sorted(bake.textures) == [0, 1]
    floor, wall = bake.textures[0], bake.textures[1]
    assert floor.texcoord == 1 and floor.stats["wrap"] == ("mirrored-repeat", "mirrored-repeat")
    assert wall.texcoord == 0 and wall.stats["wrap"] == ("repeat", "repeat")
    assert floor.coverage.all()
    assert wall.coverage[:8].all() and wall.coverage.sum() == 16 * 8  # v in [0, 0.5]
    # The wall shades the floor at its foot (z = 0, the middle rows) more than at the floor's corners: about
    # 0.79 against 1 at b = 2. The foot's mean of 8 texels of 64 estimates has a standard error near 0.02:
    # a margin of 0.1 leaves more than 4 of them.
    foot, corners = floor.image[7:9, 6:10].mean(), floor.image[[0, 0, 15, 15], [0, 15, 0, 15]].mean()
    assert foot < corners - 0.1


def test_a_set_that_claims_texels_twice_is_refused_naming_the_material(tmp_path):
    with pytest.raises(mbao.Error, match=r"material 0 \(''\), UV set TEXCOORD_0: 100.0% of its 256 covered texels"):
        mbao.bake(floor_and_wall(tmp_path), target="texture", texcoord=0, resolution=16, samples=2, progress=False)


def test_a_set_a_material_lacks_is_refused(tmp_path):
    with pytest.raises(ValueError, match=r"material 1 \('wall'\): TEXCOORD_1 is missing .* it has TEXCOORD_0"):
        mbao.bake(floor_and_wall(tmp_path), target="texture", texcoord=1, resolution=16, samples=2, progress=False)


def test_a_scene_loaded_without_uv_sets_says_how_to_get_them(tmp_path):
    scene = mbao.load(floor_and_wall(tmp_path))
    with pytest.raises(ValueError, match=r"load it with mbao.load\(path, texcoords=True\), or pass its path"):
        mbao.bake(scene, target="texture", progress=False)


def test_a_material_without_uvs_is_refused(tmp_path):
    b = GltfBuilder()
    b.add_scene([b.add_node(mesh=b.add_mesh([b.primitive(*plane(1.0), material=b.add_material())]))], default=True)
    with pytest.raises(ValueError, match=r"material 0 \(''\) has no UV set"):
        mbao.bake(b.write(tmp_path / "bare.glb"), target="texture", progress=False)


def test_the_damaged_helmets_mirrored_uvs_are_refused():
    """Its two halves share texture space (shared/scenes/damaged_helmet/README.md):
    nearly every covered texel is claimed twice; only texels on the charts'
    borders, which one half reaches at fewer sample points, escape."""
    path = shared_scene("damaged_helmet") / "scene.glb"
    with pytest.raises(
        mbao.Error,
        match=r"material 0 \('Material_MR'\), UV set TEXCOORD_1: (9[0-9]|100)\.\d% of.*"
        r"bake into a new UV set of mbao's \(texcoord=\"generate\"\)",
    ):
        mbao.bake(path, target="texture", resolution=512, samples=2, progress=False)
