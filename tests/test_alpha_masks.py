"""Alpha-masked geometry (SPEC 3.2): a MASK material makes its surface
transparent to every ray where baseColorFactor.a * texture alpha, sampled
bilinearly with the sampler's wrap modes, is below alphaCutoff."""

import math
import struct
import zlib

import numpy as np
import pytest

import mbao
from analytic import assert_within_standard_errors, one_pixel_access, polygon_occlusion
from conftest import shared_scene

from gltf_writer import (
    CLAMP_TO_EDGE, MIRRORED_REPEAT, REPEAT, UNSIGNED_BYTE, UNSIGNED_SHORT, GltfBuilder, png_bytes,
)  # fmt: skip
from meshes import plane

# A square in the plane z = 0 over [-1, 1]^2, with uv (0, 0) at its top-left
# corner (-1, 1) and v growing downwards, as glTF images are stored.
SQUARE = np.array([[-1.0, 1.0, 0.0], [1.0, 1.0, 0.0], [1.0, -1.0, 0.0], [-1.0, -1.0, 0.0]])
SQUARE_UV = np.array([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]])
SQUARE_TRIANGLES = np.array([[0, 3, 2], [0, 2, 1]])


def checkerboard(size=64, blocks=2, dtype=np.uint8):
    """Alpha blocks x blocks, opaque where (row block + column block) is even."""
    top = np.iinfo(dtype).max
    block = (np.arange(size) * blocks) // size
    return np.where((block[:, None] + block[None, :]) % 2 == 0, top, 0).astype(dtype)


def image_with_alpha(alpha, channels):
    """An image whose alpha is `alpha`: grey-alpha (2) or RGBA (4) channels."""
    colour = np.full(alpha.shape + (channels - 1,), np.iinfo(alpha.dtype).max // 3, alpha.dtype)
    return np.concatenate([colour, alpha[:, :, None]], axis=2)


def masked_scene(
    tmp_path,
    alpha_image,
    vertices=SQUARE,
    uv=SQUARE_UV,
    triangles=SQUARE_TRIANGLES,
    cutoff=None,
    factor=1.0,
    wrap=(None, None),
    where="bufferView",
    container="glb",
    extra=None,
    texcoord_type=np.float32,
    texture_transform=None,
):
    """A glTF file with one MASK-material mesh (and, if given, an opaque one) loaded as a scene;
    texture_transform: the KHR_texture_transform of its texture, or None."""
    builder = GltfBuilder()
    image = builder.add_image(png_bytes(alpha_image, tmp_path), where=where, file_name="mask.png")
    texture = builder.add_texture(image, *wrap)
    material = builder.add_material("MASK", cutoff, (1.0, 1.0, 1.0, factor), texture)
    if texture_transform is not None:
        info = builder.doc["materials"][material]["pbrMetallicRoughness"]["baseColorTexture"]
        info["extensions"] = {"KHR_texture_transform": texture_transform}
        builder.doc["extensionsUsed"] = builder.doc["extensionsRequired"] = ["KHR_texture_transform"]
    component = {np.float32: 5126, np.uint8: UNSIGNED_BYTE, np.uint16: UNSIGNED_SHORT}[texcoord_type]
    primitives = [builder.primitive(vertices, triangles, texcoords=uv, texcoord_type=component, material=material)]
    if extra is not None:
        primitives.append(builder.primitive(*extra))
    builder.add_scene([builder.add_node(mesh=builder.add_mesh(primitives))], default=True)
    path = tmp_path / ("scene.glb" if container == "glb" else "scene.gltf")
    builder.write(path, container)
    return mbao.load(path)


def square_coverage(width, height, camera_distance=2.0, vfov=60.0):
    """Where the pixel-centre rays of a camera on the z axis, looking at the
    square, meet the plane z = 0: (x, y) per pixel."""
    tan_half = math.tan(math.radians(vfov) / 2.0)
    u = ((np.arange(width) + 0.5) / width) * 2.0 - 1.0
    v = 1.0 - ((np.arange(height) + 0.5) / height) * 2.0
    x = np.broadcast_to(u[None, :] * tan_half * width / height * camera_distance, (height, width))
    y = np.broadcast_to(v[:, None] * tan_half * camera_distance, (height, width))
    return x, y


def render_square(scene, width=48, height=48):
    camera = mbao.Camera((0.0, 0.0, 2.0), (0.0, 0.0, 0.0), vfov_deg=60.0)
    return mbao.render(scene, camera=camera, width=width, height=height, samples=1)


def expected_checker_mask(width, height, blocks=2, period=1.0, margin=0.02):
    """Which pixels see an opaque block, and which are too close to a block edge to tell."""
    x, y = square_coverage(width, height)
    u, v = (x + 1.0) / 2.0 * period, (1.0 - y) / 2.0 * period
    inside = (np.abs(x) < 1.0) & (np.abs(y) < 1.0)
    cell_u, cell_v = np.floor(u * blocks), np.floor(v * blocks)
    opaque = inside & ((cell_u + cell_v) % 2 == 0)
    near_edge = (np.abs(u * blocks - np.round(u * blocks)) < margin) | (
        np.abs(v * blocks - np.round(v * blocks)) < margin
    )
    near_edge |= (np.abs(np.abs(x) - 1.0) < 0.02) | (np.abs(np.abs(y) - 1.0) < 0.02)
    return opaque, ~near_edge


@pytest.mark.parametrize("where, container", [("bufferView", "glb"), ("data-uri", "gltf"), ("file", "gltf")])
@pytest.mark.parametrize("dtype", [np.uint8, np.uint16])
@pytest.mark.parametrize("channels", [2, 4])
def test_camera_rays_pass_through_the_transparent_half(tmp_path, where, container, dtype, channels):
    """A checkerboard mask: the coverage mask is exactly the opaque blocks, for
    8- and 16-bit, grey-alpha and RGBA images, embedded in the glb, as a data
    URI or as a file beside the .gltf."""
    alpha = checkerboard(dtype=dtype)
    scene = masked_scene(tmp_path, image_with_alpha(alpha, channels), where=where, container=container)
    assert scene.alpha_masks == {
        "textures": 1,
        "masked_triangles": 2,
        "texels": 64 * 64,
        "bytes": scene.alpha_masks["bytes"],
    }
    result = render_square(scene)
    opaque, clear = expected_checker_mask(48, 48)
    assert opaque[clear].sum() > 300 and (~opaque[clear]).sum() > 300
    np.testing.assert_array_equal(result.mask[clear], opaque[clear])


@pytest.mark.parametrize(
    "transform, period, shifted",
    [
        ({"offset": [0.5, 0.0]}, 1.0, True),
        ({"scale": [2.0, 2.0]}, 2.0, False),
    ],
    ids=["offset", "scale"],
)
def test_a_texture_transform_moves_the_mask(tmp_path, transform, period, shifted):
    """KHR_texture_transform on the mask texture (SPEC 3.2): the UVs pass
    through its offset, rotation and scale before the lookup; an offset of
    half the checkerboard swaps its blocks, a scale of 2 repeats it."""
    scene = masked_scene(tmp_path, image_with_alpha(checkerboard(), 4), texture_transform=transform)
    result = render_square(scene)
    opaque, clear = expected_checker_mask(48, 48, period=period)
    if shifted:
        opaque = ~opaque & (np.abs(square_coverage(48, 48)[0]) < 1.0) & (np.abs(square_coverage(48, 48)[1]) < 1.0)
    assert opaque[clear].sum() > 300 and (~opaque[clear]).sum() > 300
    np.testing.assert_array_equal(result.mask[clear], opaque[clear])


def test_a_texture_transform_rotates_counter_clockwise_in_uv_space(tmp_path):
    """rotation pi/2 and offset (0, 1) map (u, v) to (v, 1 - u), as the
    extension's matrix says: the image's opaque top-left quadrant (u, v < 0.5)
    then covers the square where u > 0.5 and v < 0.5, its top right."""
    alpha = np.zeros((64, 64), np.uint8)
    alpha[:32, :32] = 255
    scene = masked_scene(
        tmp_path, image_with_alpha(alpha, 4), texture_transform={"rotation": math.pi / 2, "offset": [0.0, 1.0]}
    )
    result = render_square(scene)
    x, y = square_coverage(48, 48)
    clear = (
        (np.abs(x) > 0.05) & (np.abs(y) > 0.05) & (np.abs(np.abs(x) - 1.0) > 0.02) & (np.abs(np.abs(y) - 1.0) > 0.02)
    )
    top_right = (x > 0) & (x < 1) & (y > 0) & (y < 1)
    assert top_right[clear].sum() > 100
    np.testing.assert_array_equal(result.mask[clear], top_right[clear])


def test_normalized_integer_texture_coordinates(tmp_path):
    for texcoord_type in (np.uint8, np.uint16):
        scene = masked_scene(tmp_path, image_with_alpha(checkerboard(), 4), texcoord_type=texcoord_type)
        opaque, clear = expected_checker_mask(48, 48)
        np.testing.assert_array_equal(render_square(scene).mask[clear], opaque[clear])


@pytest.mark.parametrize("estimator", ["branching", "path"])
def test_a_checkered_occluder_occludes_exactly_its_opaque_half(tmp_path, estimator):
    """Under a checkered square at height h, only the opaque blocks occlude:
    L_1 = 1 minus the sum of their form factors (Lambert's formula)."""
    h, r = 0.8, 1 << 16
    # The square, lifted to y = h and facing down; the floor at y = 0.
    occluder = np.column_stack([SQUARE[:, 0], np.full(4, h), -SQUARE[:, 1]])
    floor = plane(20.0)
    scene = masked_scene(tmp_path, image_with_alpha(checkerboard(), 4), vertices=occluder, extra=floor)
    blocks = [[(-1, -1), (0, -1), (0, 0), (-1, 0)], [(0, 0), (1, 0), (1, 1), (0, 1)]]  # (x, z) of the opaque ones
    point, up = np.zeros(3), np.array([0.0, 1.0, 0.0])
    expected = 1.0 - sum(polygon_occlusion(point, up, [(x, h, z) for x, z in block]) for block in blocks)
    access, _ = one_pixel_access(scene, (1.6, 0.3, 0.2), (0.0, 0.0, 0.0), samples=r, estimator=estimator, seed=8)
    assert_within_standard_errors(access, expected, r)


@pytest.mark.parametrize(
    "texture_alpha, factor, cutoff, opaque",
    [(0.6, 1.0, None, True), (0.6, 1.0, 0.7, False), (0.6, 0.5, None, False), (0.2, 1.0, 0.1, True),
     (1.0, 0.49, None, False), (1.0, 0.5, None, True)],
)  # fmt: skip
def test_cutoff_and_alpha_factor(tmp_path, texture_alpha, factor, cutoff, opaque):
    """Opaque where baseColorFactor.a * texture alpha >= alphaCutoff (default 0.5)."""
    alpha = np.full((8, 8), round(texture_alpha * 255), np.uint8)
    scene = masked_scene(tmp_path, image_with_alpha(alpha, 4), cutoff=cutoff, factor=factor)
    covered = render_square(scene, 16, 16).mask
    x, y = square_coverage(16, 16)
    inside = (np.abs(x) < 0.98) & (np.abs(y) < 0.98)
    assert np.all(covered[inside] == opaque)


@pytest.mark.parametrize(
    "wrap, opaque_where",
    [
        (REPEAT, lambda u: (u - np.floor(u)) < 0.5),
        (MIRRORED_REPEAT, lambda u: np.where(np.floor(u) % 2 == 0, (u - np.floor(u)) < 0.5, (u - np.floor(u)) >= 0.5)),
        (CLAMP_TO_EDGE, lambda u: u < 0.5),
    ],
    ids=["repeat", "mirrored", "clamp"],
)
def test_wrap_modes(tmp_path, wrap, opaque_where):
    """The square's u runs from -1 to 2 over an image whose left half is opaque."""
    alpha = np.zeros((8, 16), np.uint8)
    alpha[:, :8] = 255
    uv = np.column_stack([SQUARE_UV[:, 0] * 3.0 - 1.0, SQUARE_UV[:, 1]])
    scene = masked_scene(tmp_path, image_with_alpha(alpha, 4), uv=uv, wrap=(wrap, REPEAT))
    result = render_square(scene, 60, 12)
    x, y = square_coverage(60, 12)
    u = (x + 1.0) / 2.0 * 3.0 - 1.0
    clear = (np.abs(x) < 0.98) & (np.abs(y) < 0.98) & (np.abs(u * 2 - np.round(u * 2)) > 0.1)
    expected = opaque_where(u)
    assert expected[clear].any() and not expected[clear].all()
    np.testing.assert_array_equal(result.mask[clear], expected[clear])


def test_a_transparent_mask_leaves_the_plane_below_open(tmp_path):
    """A plane under an occluder whose mask is transparent everywhere sees no
    occlusion at all: exactly 1, as without the occluder."""
    occluder = np.column_stack([SQUARE[:, 0], np.full(4, 0.5), -SQUARE[:, 1]])
    scene = masked_scene(tmp_path, image_with_alpha(np.zeros((4, 4), np.uint8), 4), vertices=occluder,
                         extra=plane(5.0))  # fmt: skip
    camera = mbao.Camera((0.3, 1.5, 2.0), (0.0, 0.0, 0.0), vfov_deg=50.0)
    result = mbao.render(scene, camera=camera, width=24, height=24, samples=16, bounces=2)
    assert result.mask.sum() > 200
    np.testing.assert_array_equal(result.ao[result.mask], 1.0)


def test_constant_alpha_masks_need_no_texture(tmp_path):
    """A MASK material without a texture is opaque or transparent everywhere:
    a transparent one's triangles are left out, no mask data is kept."""
    for factor, triangles in ((0.3, 2), (0.8, 4)):
        builder = GltfBuilder()
        transparent = builder.add_material("MASK", 0.5, (1, 1, 1, factor))
        primitives = [builder.primitive(SQUARE, SQUARE_TRIANGLES, material=transparent),
                      builder.primitive(SQUARE + (0, 0, 1), SQUARE_TRIANGLES)]  # fmt: skip
        builder.add_scene([builder.add_node(mesh=builder.add_mesh(primitives))], default=True)
        scene = mbao.load(builder.write(tmp_path / "constant.glb"))
        assert scene.triangle_count == triangles
        assert scene.alpha_masks is None


def test_images_without_alpha_are_opaque(tmp_path):
    """Grey and RGB images have no alpha channel: alpha 1, no mask data."""
    for pixels in (np.zeros((4, 4), np.uint8), np.zeros((4, 4, 3), np.uint8)):
        scene = masked_scene(tmp_path, pixels)
        assert scene.alpha_masks is None
        x, y = square_coverage(16, 16)
        assert render_square(scene, 16, 16).mask[(np.abs(x) < 0.98) & (np.abs(y) < 0.98)].all()


def test_only_mask_textures_are_decoded(tmp_path):
    """An opaque material's texture is never decoded, even a broken one; a
    broken mask texture is named in a warning, and its surface is opaque."""
    builder = GltfBuilder()
    broken = builder.add_image(b"not an image at all")
    opaque = builder.add_material("OPAQUE", texture=builder.add_texture(broken))
    builder.add_scene([builder.add_node(mesh=builder.add_mesh([
        builder.primitive(SQUARE, SQUARE_TRIANGLES, texcoords=SQUARE_UV, material=opaque)]))], default=True)  # fmt: skip
    assert mbao.load(builder.write(tmp_path / "opaque.glb")).triangle_count == 2
    builder.doc["materials"][opaque]["alphaMode"] = "MASK"
    with pytest.warns(UserWarning, match=r"mask.glb: material 0's image 0: cannot decode .*; the surface is opaque"):
        scene = mbao.load(builder.write(tmp_path / "mask.glb"))
    assert scene.triangle_count == 2 and scene.alpha_masks is None


def png_header_only(width, height, colour_type, bit_depth=8):
    """A PNG that declares width x height texels but holds a single
    zlib-compressed byte of them."""

    def chunk(kind, data):
        return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data))

    header = struct.pack(">IIBBBBB", width, height, bit_depth, colour_type, 0, 0, 0)
    return b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", header) + chunk(b"IDAT", zlib.compress(b"\0")) + chunk(b"IEND", b"")


GREY_ALPHA, RGB = 4, 2  # PNG colour types


def scene_masked_by(tmp_path, encoded_image):
    """The square with a MASK material whose texture is `encoded_image`, as a glb path."""
    builder = GltfBuilder()
    material = builder.add_material("MASK", texture=builder.add_texture(builder.add_image(encoded_image)))
    builder.add_scene([builder.add_node(mesh=builder.add_mesh([
        builder.primitive(SQUARE, SQUARE_TRIANGLES, texcoords=SQUARE_UV, material=material)]))], default=True)  # fmt: skip
    return builder.write(tmp_path / "masked.glb")


@pytest.mark.parametrize("width, height, bit_depth", [(16385, 16384, 8), (16384, 16385, 16), (20000, 14000, 8)])
def test_a_mask_image_over_2_to_the_28_texels_is_refused_from_its_header(tmp_path, width, height, bit_depth):
    """Refused before decoding, which would take 1-2 GiB (stb_image itself
    refuses images of more than 2^30 values): a warning, and the surface is opaque."""
    with pytest.warns(UserWarning, match=rf"image 0: the image is {width} x {height} texels; .* at most 2\^28"):
        scene = mbao.load(scene_masked_by(tmp_path, png_header_only(width, height, GREY_ALPHA, bit_depth)))
    assert scene.alpha_masks is None
    # Without an alpha channel the image is never decoded, whatever its size.
    assert mbao.load(scene_masked_by(tmp_path, png_header_only(width, height, RGB, bit_depth))).alpha_masks is None


def test_a_masked_primitive_needs_its_texture_coordinates(tmp_path):
    builder = GltfBuilder()
    image = builder.add_image(png_bytes(image_with_alpha(checkerboard(8), 4), tmp_path))
    material = builder.add_material("MASK", texture=builder.add_texture(image), texcoord_set=1)
    builder.add_scene([builder.add_node(mesh=builder.add_mesh([
        builder.primitive(SQUARE, SQUARE_TRIANGLES, texcoords=SQUARE_UV, material=material)]))], default=True)  # fmt: skip
    with pytest.raises(mbao.LoadError, match="TEXCOORD_1"):
        mbao.load(builder.write(tmp_path / "missing_uv.glb"))


def test_sponza_foliage_is_masked():
    """Sponza's leaves, plants and chains are masked quads: 3 textures, 34,940
    triangles. Seen close up, a potted plant's image differs from the one of
    the same triangles as solid quads (docs/sponza_plant_*.png show both)."""
    folder = shared_scene("sponza")
    scene = mbao.load(folder / "scene.glb")
    assert scene.alpha_masks["textures"] == 3 and scene.alpha_masks["masked_triangles"] == 34940
    solid = mbao.Mesh(scene.vertices, scene.indices, scene.normals)
    camera = mbao.Camera((-830.0, 170.0, -110.0), (-960.0, 50.0, -230.0), vfov_deg=40.0)
    settings = dict(camera=camera, width=32, height=32, samples=4, max_distance=300.0)
    assert not np.array_equal(mbao.render(scene, **settings).ao, mbao.render(solid, **settings).ao)
