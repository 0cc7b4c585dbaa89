"""mbao.load reads every format Assimp reads but glTF (SPEC 3.2): OBJ, PLY,
STL, Collada, FBX, ... with the nodes' transforms applied, triangles only,
normals where the file has them. The tests write the files they read."""

import pickle

import numpy as np
import pytest

import mbao
from conftest import shared_scene
from gltf_writer import png_bytes
from scene_files import COLLADA, write_obj, write_ply


@pytest.fixture(scope="module")
def bunny():
    return mbao.load(shared_scene("bunny") / "scene.glb")


def corners(scene):
    return scene.vertices[scene.indices]


@pytest.mark.parametrize(
    "name, write",
    [
        ("bunny.obj", lambda p, v, t: write_obj(p, v, t)),
        ("bunny.ply", lambda p, v, t: write_ply(p, v, t, binary=False)),
        ("bunny_binary.ply", lambda p, v, t: write_ply(p, v, t, binary=True)),
    ],
)
def test_the_bunny_in_other_formats_has_the_glbs_triangles(tmp_path, bunny, name, write):
    """The same triangles, corner for corner: exactly from binary PLY, within
    one unit in the last place from text (Assimp's decimal parser rounds so)."""
    path = tmp_path / name
    write(path, bunny.vertices, bunny.indices)
    loaded = mbao.load(path)
    assert loaded.triangle_count == bunny.triangle_count and loaded.name == str(path)
    if name.endswith("binary.ply"):
        np.testing.assert_array_equal(corners(loaded), corners(bunny))
    else:
        np.testing.assert_array_max_ulp(corners(loaded), corners(bunny), maxulp=1)


def test_a_ply_renders_as_its_glb_does(tmp_path, bunny):
    """With the same triangles and geometric normals (the PLY has no others), the same image."""
    write_ply(tmp_path / "bunny.ply", bunny.vertices, bunny.indices, binary=True)
    settings = dict(width=32, height=32, bounces=2, seed=1, camera=bunny.default_camera(32, 32), normals="geometric")
    np.testing.assert_array_equal(mbao.render(tmp_path / "bunny.ply", **settings).ao, mbao.render(bunny, **settings).ao)


def test_normals_are_read_where_the_file_has_them(tmp_path):
    vertices = np.array([[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]])
    normals = np.array([[0.0, 0.0, 1.0], [0.0, 0.6, 0.8], [0.6, 0.0, 0.8]])
    write_obj(tmp_path / "with.obj", vertices, np.array([[0, 1, 2]]), normals)
    np.testing.assert_allclose(mbao.load(tmp_path / "with.obj").normals, normals, atol=1e-6)
    assert mbao.load(tmp_path / "with.obj", normals=False).normals is None
    write_obj(tmp_path / "without.obj", vertices, np.array([[0, 1, 2]]))
    assert mbao.load(tmp_path / "without.obj").normals is None


def test_nodes_place_their_meshes(tmp_path):
    """A triangle under two nodes, translated and then scaled: world = outer x inner."""
    path = tmp_path / "placed.dae"
    path.write_text(COLLADA)
    with pytest.warns(UserWarning, match="camera 'eye' skipped: Assimp gives no aspect ratio"):
        scene = mbao.load(path)
    np.testing.assert_allclose(corners(scene)[0], [[10, 20, 30], [12, 20, 30], [10, 22, 30]])
    assert scene.camera is None


def test_points_and_lines_are_skipped_with_a_warning(tmp_path):
    path = tmp_path / "mixed.obj"
    path.write_text("v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nf 1 2 3\nl 3 4\n")
    with pytest.warns(UserWarning, match=r"1 points and lines skipped"):
        scene = mbao.load(path)
    assert scene.triangle_count == 1


CAMERA_ONLY_COLLADA = b"""<?xml version="1.0" encoding="utf-8"?>
<COLLADA xmlns="http://www.collada.org/2005/11/COLLADASchema" version="1.4.1">
  <library_cameras><camera id="c"><optics><technique_common><perspective><yfov>40</yfov>
    <aspect_ratio>1.5</aspect_ratio><znear>0.1</znear><zfar>100</zfar></perspective></technique_common></optics>
  </camera></library_cameras>
  <library_visual_scenes><visual_scene id="s"><node id="eye"><instance_camera url="#c"/></node>
    <node id="parent"><node id="child"/></node></visual_scene></library_visual_scenes>
  <scene><instance_visual_scene url="#s"/></scene>
</COLLADA>
"""


@pytest.mark.parametrize(
    "name, content, message",
    [
        (
            "truncated.ply",
            b"ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
            b"property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n\0\0",
            "out of range",
        ),
        ("bad_index.obj", b"v 0 0 0\nv 1 0 0\nf 1 2 7\n", "vertex index out of range"),
        ("garbage.fbx", b"garbage", "FBX"),
        ("truncated.stl", b"solid x\nfacet normal 0 0 1\n outer loop\n vertex 0 0 0\n", "STL"),
        ("noise.dae", bytes(range(256)) * 2, "XML"),
        ("empty.obj", b"", "too small"),
        ("lines_only.obj", b"v 0 0 0\nv 1 0 0\nl 1 2\n", "no triangles"),
        (
            "readme.obj",
            b"This is a text file, not a model.\nIt has a few lines of words.\n",
            r"readme.obj: no meshes in it",
        ),
        ("points.obj", b"v 0 0 0\nv 1 0 0\n", "points.obj: a mesh in it has vertices but no faces"),
        # Without meshes Assimp would build stand-in pyramids from the nodes and flag the scene incomplete.
        ("camera_only.dae", CAMERA_ONLY_COLLADA, "camera_only.dae: no meshes in it"),
    ],
)
def test_a_bad_file_raises_load_error_naming_it(tmp_path, name, content, message):
    path = tmp_path / name
    path.write_bytes(content)
    with pytest.raises(mbao.LoadError, match=message) as error:
        mbao.load(path)
    assert str(path) in str(error.value)


@pytest.mark.parametrize("name", ["scan", "scan.data"])
def test_a_file_whose_extension_names_no_format_is_read_by_its_content(tmp_path, name):
    """Assimp's test files include models without extensions; it tells their format from their signature."""
    vertices, triangles = np.float32([[0, 0, 0], [1, 0, 0], [0, 1, 0]]), np.int32([[0, 1, 2]])
    write_ply(tmp_path / name, vertices, triangles, binary=True)
    np.testing.assert_array_equal(corners(mbao.load(tmp_path / name)), vertices[triangles])


def test_a_file_that_is_neither_gltf_nor_of_a_format_assimp_recognises_says_both(tmp_path):
    (tmp_path / "notes").write_text("Not a model.\n")
    with pytest.raises(
        mbao.LoadError,
        match=r"notes: neither a GLB file .* nor glTF JSON .*; nor did Assimp "
        r"recognise its content: .*notes: No suitable reader",
    ):
        mbao.load(tmp_path / "notes")


def test_a_file_that_makes_assimp_abort_is_a_load_error(tmp_path, capfd):
    """Debian's Assimp asserts, and so aborts, in its triangulation on this
    PLY (a fuzzer's find); it runs in a process of its own, so the caller gets
    an error naming the file, with the assertion, instead of losing its own
    process, and nothing reaches stderr."""
    path = tmp_path / "aborts.ply"
    path.write_bytes(
        b"ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
        b"property(float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n"
        b"0\x000 0\n1 0 0\n0 1 0\n3 0 1 2\n"
    )
    with pytest.raises(mbao.LoadError, match=r"aborts.ply: the importer stopped on it \(signal 6.*ai_assert"):
        mbao.load(path)
    assert capfd.readouterr().err == ""


def test_a_missing_file_is_named(tmp_path):
    with pytest.raises(mbao.LoadError, match="no_such.obj"):
        mbao.load(tmp_path / "no_such.obj")


def two_material_obj(tmp_path):
    """A floor (material "floor", vt UVs) and a wall standing on it (material
    "wall", no vt): an OBJ whose UVs and materials texcoords=True reads."""
    (tmp_path / "two.mtl").write_text("newmtl floor\nKd 1 1 1\nnewmtl wall\nKd 1 1 1\n")
    (tmp_path / "two.obj").write_text(
        "mtllib two.mtl\n"
        "v -1 0 -1\nv 1 0 -1\nv 1 0 1\nv -1 0 1\nv -1 0 0\nv 1 0 0\nv 1 1 0\nv -1 1 0\n"
        "vt 0 0\nvt 0.5 0\nvt 0.5 0.25\nvt 0 0.25\n"
        "usemtl floor\nf 1/1 3/3 2/2\nf 1/1 4/4 3/3\n"
        "usemtl wall\nf 5 6 7\nf 5 7 8\n"
    )
    return tmp_path / "two.obj"


def test_uv_sets_and_materials_of_an_assimp_format_are_read(tmp_path):
    """texcoords=True reads each mesh's UV channels as TEXCOORD_n, v down the
    image as glTF's (an OBJ's vt (u, v) is (u, 1 - v)), NaN for a mesh without
    the channel, and the meshes' materials by name (SPEC 3.2)."""
    scene = mbao.load(two_material_obj(tmp_path), texcoords=True)
    uv_sets = scene.uv_sets
    names = [material["name"] for material in uv_sets["materials"]]
    assert {"floor", "wall"} <= set(names)
    floor = names.index("floor")
    floor_triangles = uv_sets["triangle_materials"] == floor
    assert floor_triangles.sum() == 2 and (uv_sets["triangle_materials"] == names.index("wall")).sum() == 2
    corners = scene.indices[floor_triangles].ravel()
    positions, uvs = scene.vertices[corners], uv_sets["sets"][0][corners]
    np.testing.assert_allclose(uvs[:, 0], (positions[:, 0] + 1) / 4)  # u = (x + 1) / 4
    np.testing.assert_allclose(uvs[:, 1], 1 - (positions[:, 2] + 1) / 8)  # v = (z + 1) / 8, flipped
    assert np.isnan(uv_sets["sets"][0][scene.indices[~floor_triangles].ravel()]).all()
    assert sum(p["triangles"][1] - p["triangles"][0] for p in uv_sets["primitives"]) == scene.triangle_count


def test_an_assimp_format_bakes_into_its_own_uvs_and_keeps_them_beside_generated_ones(tmp_path):
    """A texture bake of the floor into its vt set; bake_file writes the file's
    materials and UV sets into the glTF it makes, and a generated set after
    them (issue 60: the vt set was dropped)."""
    from mbao._gltf import GltfDocument
    from baked_files import validation_errors

    path = two_material_obj(tmp_path)
    with pytest.raises(ValueError, match=r"material \d+ \('wall'\) has no UV set"):
        mbao.bake(path, target="texture", resolution=8, samples=2, progress=False)
    output = tmp_path / "generated.gltf"
    result = mbao.bake_file(
        path, output, target="texture", texcoord="generate", resolution=32, samples=2, progress=False
    )
    document = GltfDocument(output)
    names = [material["name"] for material in document.doc["materials"]]
    assert {"floor", "wall"} <= set(names)
    primitives = document.doc["meshes"][0]["primitives"]
    floor = next(p for p in primitives if names[p["material"]] == "floor")
    assert {"TEXCOORD_0", "TEXCOORD_1"} <= set(floor["attributes"])  # the vt set, then the generated one
    assert document.doc["materials"][floor["material"]]["occlusionTexture"]["texCoord"] == 1
    assert all(texture.coverage.any() for texture in result.textures.values())
    assert validation_errors(output) == []


def tga_bytes(rgb):
    """An uncompressed 24-bit TGA of an (H, W, 3) uint8 image, rows from the top."""
    height, width, _ = rgb.shape
    header = bytes([0, 0, 2, 0, 0, 0, 0, 0, 0, 0, 0, 0, width & 255, width >> 8, height & 255, height >> 8, 24, 0x20])
    return header + np.ascontiguousarray(rgb[:, :, ::-1]).tobytes()


def test_bake_file_keeps_an_assimp_formats_base_colours(tmp_path):
    """A material's diffuse colour becomes its baseColorFactor and its diffuse map its baseColorTexture, in the
    UV set the map names; a TGA is written as a PNG of the same texels. A map that cannot be read, or whose UV set
    a primitive lacks, is named in a warning and left out, and the file stays valid."""
    import OpenImageIO as oiio
    from mbao._gltf import GltfDocument
    from mbao.scene import load_with_base_colors
    from baked_files import validation_errors

    texels = np.random.default_rng(3).integers(0, 256, (4, 6, 3), dtype=np.uint8)
    (tmp_path / "floor.tga").write_bytes(tga_bytes(texels))
    (tmp_path / "wall.png").write_bytes(png_bytes(np.full((2, 2), 200, np.uint8), tmp_path))
    (tmp_path / "scene.mtl").write_text(
        "newmtl floor\nKd 0.8 0.4 0.2\nmap_Kd floor.tga\n"
        "newmtl wall\nKd 0.1 0.2 0.3\nd 0.9\nmap_Kd wall.png\n"
        "newmtl roof\nKd 0.5 0.5 0.5\nmap_Kd missing.png\n"
    )
    (tmp_path / "scene.obj").write_text(
        "mtllib scene.mtl\n"
        "v -1 0 -1\nv 1 0 -1\nv 1 0 1\nv -1 0 1\nv -1 0 0\nv 1 0 0\nv 1 1 0\nv -1 1 0\n"
        "vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\n"
        "usemtl floor\nf 1/1 3/3 2/2\nf 1/1 4/4 3/3\n"
        "usemtl wall\nf 5 6 7\nf 5 7 8\n"
        "usemtl roof\nf 8/1 7/2 6/3\n"
    )
    with pytest.warns(UserWarning) as warned:
        mbao.bake_file(tmp_path / "scene.obj", tmp_path / "out.glb", samples=2, progress=False)
    messages = [str(w.message) for w in warned]
    assert any("material 'roof''s base colour image missing.png" in m and "without it" in m for m in messages)
    assert any(
        "material 'wall''s base colour image is looked up in TEXCOORD_0, which 1 of its primitives lack" in m
        for m in messages
    )
    document = GltfDocument(tmp_path / "out.glb")
    materials = {m["name"]: m["pbrMetallicRoughness"] for m in document.doc["materials"] if "name" in m}
    np.testing.assert_allclose(materials["floor"]["baseColorFactor"], [0.8, 0.4, 0.2, 1.0], rtol=1e-6)
    np.testing.assert_allclose(materials["wall"]["baseColorFactor"], [0.1, 0.2, 0.3, 0.9], rtol=1e-6)
    assert "baseColorTexture" not in materials["wall"] and "baseColorTexture" not in materials["roof"]
    texture = document.doc["textures"][materials["floor"]["baseColorTexture"]["index"]]
    image = document.doc["images"][texture["source"]]
    assert image["mimeType"] == "image/png" and materials["floor"]["baseColorTexture"]["texCoord"] == 0
    view = document.doc["bufferViews"][image["bufferView"]]
    start = view.get("byteOffset", 0)
    (tmp_path / "written.png").write_bytes(document.buffer_data(view["buffer"])[start : start + view["byteLength"]])
    written = oiio.ImageBuf(str(tmp_path / "written.png")).get_pixels(oiio.UINT8)
    np.testing.assert_array_equal(written, texels)
    assert validation_errors(tmp_path / "out.glb") == []
    with pytest.warns(UserWarning):
        scene = load_with_base_colors(tmp_path / "scene.obj")
    assert pickle.loads(pickle.dumps(scene)).uv_sets["materials"] == scene.uv_sets["materials"]  # Dask's transfer
