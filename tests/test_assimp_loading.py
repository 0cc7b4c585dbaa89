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


# Alpha masks from an OBJ's materials: the square of tests/test_alpha_masks.py,
# its UVs written with v up as OBJ has them.
def masked_obj(tmp_path, material_lines, images):
    from test_alpha_masks import SQUARE, SQUARE_TRIANGLES, SQUARE_UV

    for name, pixels in images.items():
        (tmp_path / name).write_bytes(png_bytes(pixels, tmp_path))
    (tmp_path / "square.mtl").write_text("newmtl cut\n" + "".join(line + "\n" for line in material_lines))
    lines = ["mtllib square.mtl", "usemtl cut"]
    lines += [f"v {x} {y} {z}" for x, y, z in SQUARE]
    lines += [f"vt {u} {1.0 - v}" for u, v in SQUARE_UV]
    lines += [f"f {a + 1}/{a + 1} {b + 1}/{b + 1} {c + 1}/{c + 1}" for a, b, c in SQUARE_TRIANGLES]
    (tmp_path / "square.obj").write_text("\n".join(lines) + "\n")
    return mbao.load(tmp_path / "square.obj")


@pytest.mark.parametrize(
    "material, images",
    [
        (["map_Kd colour.png"], {"colour.png": "rgba"}),  # the diffuse map's alpha
        (["map_d opacity.png"], {"opacity.png": "grey"}),  # an opacity map's grey
        (["map_Kd colour.png", "map_d opacity.png"], {"colour.png": "opaque rgb", "opacity.png": "grey"}),
    ],
    ids=["map_Kd alpha", "map_d grey", "map_d over an opaque map_Kd"],
)
def test_an_obj_material_cuts_its_surface_as_a_gltf_mask_does(tmp_path, material, images):
    from test_alpha_masks import checkerboard, expected_checker_mask, image_with_alpha, render_square

    alpha = checkerboard()
    pixels = {
        "rgba": image_with_alpha(alpha, 4),
        "grey": alpha,
        "opaque rgb": np.full(alpha.shape + (3,), 200, np.uint8),
    }
    scene = masked_obj(tmp_path, material, {name: pixels[kind] for name, kind in images.items()})
    assert scene.alpha_masks["textures"] == 1 and scene.alpha_masks["masked_triangles"] == 2
    opaque, clear = expected_checker_mask(48, 48)
    np.testing.assert_array_equal(render_square(scene).mask[clear], opaque[clear])


@pytest.mark.parametrize(
    "reference, place",
    [
        (r"C:\Users\artist\textures\cut.png", "cut.png"),  # another machine's drive: the file name beside the model
        (r"textures\cut.png", "textures/cut.png"),  # Windows' separators
        ("//textures/cut.png", "textures/cut.png"),  # Blender's "relative to the .blend"
        ("/no/such/folder/cut.png", "cut.png"),  # an absolute path that is not here
    ],
    ids=["drive letter", "backslashes", "blender relative", "absolute elsewhere"],
)
def test_an_image_path_from_another_machine_or_tool_is_found_as_it_means(tmp_path, reference, place):
    """SPEC 3.2: as Blender and Assimp's viewer find them, relative to the model, else beside it."""
    from test_alpha_masks import checkerboard

    (tmp_path / place).parent.mkdir(exist_ok=True)
    (tmp_path / place).write_bytes(png_bytes(checkerboard(), tmp_path))
    scene = masked_obj(tmp_path, [f"map_d {reference}"], {})
    assert scene.alpha_masks["textures"] == 1 and scene.warnings == []


def test_a_diffuse_map_that_cannot_cut_is_not_opened(tmp_path):
    """A JPEG has no alpha, so a missing one changes nothing; a missing PNG might have cut, and is named."""
    scene = masked_obj(tmp_path, ["map_Kd C:\\textures\\missing.jpg"], {})
    assert scene.alpha_masks is None and scene.warnings == []
    with pytest.warns(UserWarning, match=r"material 'cut''s image missing.png: cannot read .*; the surface is opaque"):
        scene = masked_obj(tmp_path, ["map_Kd missing.png"], {})
    assert scene.alpha_masks is None and scene.triangle_count == 2


def test_an_image_that_does_not_decode_leaves_the_surface_opaque(tmp_path):
    (tmp_path / "broken.png").write_bytes(b"\x89PNG but nothing after")
    with pytest.warns(UserWarning, match=r"square.obj: material 'cut''s image broken.png: cannot decode"):
        scene = masked_obj(tmp_path, ["map_d broken.png", "d 0.2"], {})
    assert scene.alpha_masks is None and scene.triangle_count == 2  # opaque, whatever its d says


def plane_and_triangle_obj(tmp_path, plane_material, triangle_material, materials):
    """glass.obj: a plane of two triangles in `plane_material` and a triangle in `triangle_material`, materials
    from glass.mtl, whose text is `materials`."""
    from meshes import plane

    vertices, triangles = plane(1.0)
    (tmp_path / "glass.mtl").write_text(materials)
    lines = ["mtllib glass.mtl", f"usemtl {plane_material}"] + [f"v {x} {y} {z}" for x, y, z in vertices]
    lines += [f"f {a + 1} {b + 1} {c + 1}" for a, b, c in triangles]
    lines += [f"usemtl {triangle_material}", "v 0 1 0", "v 1 1 0", "v 0 2 0", "f 5 6 7"]
    (tmp_path / "glass.obj").write_text("\n".join(lines) + "\n")
    return tmp_path / "glass.obj"


def test_an_obj_material_below_half_opacity_leaves_no_surface(tmp_path):
    scene = mbao.load(plane_and_triangle_obj(tmp_path, "glass", "wall", "newmtl glass\nd 0.3\nnewmtl wall\nd 1.0\n"))
    assert scene.triangle_count == 1 and scene.alpha_masks is None


def test_a_file_whose_every_material_is_below_half_opacity_loads_opaque_with_a_warning(tmp_path):
    """Leaving nothing helps no one, and Collada exporters often write transparency 0 for opaque (Assimp's own
    teapots.DAE): every opacity is taken as 1, and the warning names the materials."""
    path = plane_and_triangle_obj(tmp_path, "glass", "mist", "newmtl glass\nd 0.0\nnewmtl mist\nd 0.2\n")
    with pytest.warns(
        UserWarning,
        match=r"every triangle is in a material of opacity below 0.5 \('glass', 'mist'\), "
        r"which would leave nothing; their opacity is taken as 1",
    ):
        scene = mbao.load(path)
    assert scene.triangle_count == 3  # the plane's two and the triangle


def test_a_mask_image_that_is_not_there_is_named_and_its_surface_is_opaque(tmp_path):
    (tmp_path / "lost.mtl").write_text("newmtl lost\nmap_d missing.png\n")
    (tmp_path / "lost.obj").write_text(
        "mtllib lost.mtl\nusemtl lost\nv 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvt 1 0\n" "vt 0 1\nf 1/1 2/2 3/3\n"
    )
    expected = (
        r"lost.obj: material 'lost''s image missing.png: cannot read .*missing.png: no such file; the surface is opaque"
    )
    with pytest.warns(UserWarning, match=expected):
        scene = mbao.load(tmp_path / "lost.obj")
    assert scene.triangle_count == 1 and scene.alpha_masks is None


@pytest.mark.parametrize("alpha, triangles", [(200, 2), (100, 0)], ids=["opaque everywhere", "clear everywhere"])
def test_a_map_whose_alpha_is_on_one_side_of_the_cutoff_everywhere_is_no_mask(tmp_path, alpha, triangles):
    """An alpha map at 200/255 everywhere keeps the surface whole, one at
    100/255 removes it: no texel need be looked up (bilinear values stay
    between the texels'), so neither becomes a mask texture."""
    from test_alpha_masks import image_with_alpha

    rgba = image_with_alpha(np.full((8, 8), alpha, np.uint8), 4)
    if triangles:
        scene = masked_obj(tmp_path, ["map_Kd colour.png"], {"colour.png": rgba})
        assert scene.triangle_count == triangles and scene.alpha_masks is None
    else:
        with pytest.raises(
            mbao.LoadError,
            match=r"no triangles in it are left: the alpha of their materials' images "
            r"\('\w+'\) is below 0.5 everywhere",
        ):
            masked_obj(tmp_path, ["map_Kd colour.png"], {"colour.png": rgba})


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
