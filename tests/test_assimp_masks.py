"""Alpha masks from the materials of a format Assimp reads (an OBJ's map_d and
map_Kd, SPEC 3.2): a surface cut as a glTF mask cuts it, images found where the
file means them, and an image that is missing or undecodable leaving the surface
opaque with a warning."""


import numpy as np
import pytest

import mbao
from gltf_writer import png_bytes


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
