"""The viewer's "baked" method (mbao.viewer.baked): the occlusion a baked glTF
file stores, looked up at the camera's hits. Each lookup is checked against
one made here from what the bake wrote, with barycentrics of their own (sub-
triangle areas) and a bilinear sampler of its own (wrapping texel indices, not
coordinates)."""

import numpy as np
import pytest

import mbao
from conftest import REPO
from gltf_writer import CLAMP_TO_EDGE, MIRRORED_REPEAT, REPEAT, GltfBuilder, png_bytes
from mbao import load_bake
from mbao._gltf import GltfDocument
from mbao.viewer import messages
from mbao.viewer.baked import baked_occlusion
from mbao.viewer.session import to_8bit
from scene_files import write_obj
from test_bake_gltf import floor_and_wall
from viewer_client import connected, decode, run, served

SIZE = 48
# Sees floor_and_wall's floor and the front of its wall (which faces +z) from above.
CAMERA = mbao.Camera((0.7, 1.4, 2.2), (0.0, 0.3, 0.0), (0.0, 1.0, 0.0), 55.0)
WRAP_NAMES = {REPEAT: "repeat", CLAMP_TO_EDGE: "clamp-to-edge", MIRRORED_REPEAT: "mirrored-repeat"}


def hits(scene, camera):
    """The G-buffer, and per hit pixel (in row order) its triangle's corners and
    its barycentrics: the areas of the sub-triangles over the triangle's."""
    g = mbao.gbuffer(scene, camera=camera, width=SIZE, height=SIZE)
    corners = scene.indices[g.triangle[g.mask]].astype(np.int64)
    a, b, c = (scene.vertices[corners[:, k]].astype(np.float64) for k in range(3))
    p = g.position[g.mask].astype(np.float64)
    n = np.cross(b - a, c - a)
    area = (n * n).sum(axis=1)
    w1 = (np.cross(p - a, c - a) * n).sum(axis=1) / area
    w2 = (np.cross(b - a, p - a) * n).sum(axis=1) / area
    return g, corners, np.column_stack([1.0 - w1 - w2, w1, w2])


def wrapped(i, n, mode):
    if mode == "clamp-to-edge":
        return np.clip(i, 0, n - 1)
    if mode == "repeat":
        return np.mod(i, n)
    period = np.mod(i, 2 * n)
    return np.minimum(period, 2 * n - 1 - period)


def bilinear(image, uv, wrap):
    """image (H, W) at UVs (K, 2): texel centres at half-integers, row 0 at v = 0."""
    h, w = image.shape
    x, y = uv[:, 0] * w - 0.5, uv[:, 1] * h - 0.5
    i, j = np.floor(x).astype(np.int64), np.floor(y).astype(np.int64)
    fx, fy = x - i, y - j

    def at(di, dj):
        return image[wrapped(j + dj, h, wrap[1]), wrapped(i + di, w, wrap[0])].astype(np.float64)

    return (1 - fx) * (1 - fy) * at(0, 0) + fx * (1 - fy) * at(1, 0) + (1 - fx) * fy * at(0, 1) + fx * fy * at(1, 1)


def looked_up(path, camera=CAMERA):
    scene = mbao.load(path, texcoords=True)
    bake = load_bake(path, scene)
    return scene, bake, baked_occlusion(scene, bake, camera, SIZE, SIZE, None)


def check_frame(result, g, source, unbaked=0):
    """What every frame holds: the G-buffer's hits, 1 and coverage 0 where rays miss, a render's stats."""
    np.testing.assert_array_equal(result.mask, g.mask)
    np.testing.assert_array_equal(result.coverage, g.mask.astype(np.float32))
    assert (result.ao[~g.mask] == 1).all() and result.ao.dtype == np.float32 and result.variance is None
    assert result.stats["method"] == "baked" and result.stats["source"] == source
    assert result.stats["unbaked_pixels"] == unbaked
    assert result.stats["frame_ms"] >= result.stats["gbuffer_ms"] > 0 and result.stats["device"] == g.stats["device"]
    assert result.stats["rays_primary"] == SIZE * SIZE


@pytest.fixture
def vertex_baked(tmp_path):
    """floor_and_wall baked per vertex (its floor keeps its own occlusion texture, all 1), and the bake."""
    path = tmp_path / "vertices.glb"
    bake = mbao.bake_file(floor_and_wall(tmp_path), path, samples=4, progress=False)
    return path, bake


def test_a_vertex_bake_is_its_values_interpolated_at_the_hits(vertex_baked):
    path, bake = vertex_baked
    scene, stored, result = looked_up(path)
    # The attribute wins over the floor's occlusion texture, which the vertex bake kept from its input.
    assert stored.source == "vertices" and stored.textures == {}
    g, corners, weights = hits(scene, CAMERA)
    check_frame(result, g, "vertices")
    materials = scene.uv_sets["triangle_materials"][g.triangle[g.mask]]
    assert (materials == 0).sum() > 200 and (materials == 1).sum() > 100  # the floor and the wall are seen
    np.testing.assert_allclose(result.ao[g.mask], (bake.values[corners] * weights).sum(axis=1), rtol=0, atol=1e-5)
    assert np.ptp(result.ao[g.mask]) > 0.1  # values that differ, so that the weights matter


def without_occlusion(path, primitive, output):
    document = GltfDocument(path)
    del document.doc["meshes"][0]["primitives"][primitive]["attributes"]["_OCCLUSION"]
    document.write(output)
    return output


def test_a_triangle_without_values_reads_its_texture_else_is_open(vertex_baked, tmp_path):
    path, bake = vertex_baked
    # The wall has no values left and no occlusion texture: open, and counted.
    scene, stored, result = looked_up(without_occlusion(path, 1, tmp_path / "wall_unbaked.glb"))
    g, corners, weights = hits(scene, CAMERA)
    wall = scene.uv_sets["triangle_materials"][g.triangle[g.mask]] == 1
    check_frame(result, g, "vertices", unbaked=int(wall.sum()))
    assert (result.ao[g.mask][wall] == 1).all()
    np.testing.assert_allclose(
        result.ao[g.mask][~wall], (bake.values[corners[~wall]] * weights[~wall]).sum(axis=1), rtol=0, atol=1e-5
    )
    # The floor has no values left: it reads the file's own occlusion texture, white (a constant 1).
    scene, stored, result = looked_up(without_occlusion(path, 0, tmp_path / "floor_unbaked.glb"))
    assert list(stored.textures) == [0] and (stored.textures[0].image == 1).all()
    g, corners, weights = hits(scene, CAMERA)
    floor = scene.uv_sets["triangle_materials"][g.triangle[g.mask]] == 0
    check_frame(result, g, "vertices")
    np.testing.assert_array_equal(result.ao[g.mask][floor], 1.0)
    np.testing.assert_allclose(
        result.ao[g.mask][~floor], (bake.values[corners[~floor]] * weights[~floor]).sum(axis=1), rtol=0, atol=1e-5
    )


def triangle_uvs(scene, bake):
    """(M, 3, 2) the UVs of each scene triangle's corners as the texture bake baked them."""
    uvs = np.full((scene.triangle_count, 3, 2), np.nan)
    for texture in bake.textures.values():
        uvs[texture.triangles] = texture.texcoords
    return uvs


def baked_expectation(scene, bake, g, weights):
    """Per hit pixel, the bake's own (unquantized) texture sampled at the hit's UV with the wrap it baked with."""
    triangles = g.triangle[g.mask]
    uv = (triangle_uvs(scene, bake)[triangles] * weights[:, :, None]).sum(axis=1)
    materials = scene.uv_sets["triangle_materials"][triangles]
    expected = np.full(len(triangles), np.nan)
    for material, texture in bake.textures.items():
        here = materials == material
        expected[here] = bilinear(texture.image, uv[here], texture.stats["wrap"])
    return expected, materials


@pytest.mark.parametrize("bit_depth", [8, 16])
def test_a_texture_bake_is_its_png_sampled_bilinearly_at_the_hits(tmp_path, bit_depth):
    """The floor's texture reads TEXCOORD_1 through a MIRRORED_REPEAT sampler, the wall's TEXCOORD_0 (REPEAT)."""
    path = tmp_path / "texture.glb"
    bake = mbao.bake_file(
        floor_and_wall(tmp_path),
        path,
        target="texture",
        resolution=(16, 8),
        samples=4,
        bit_depth=bit_depth,
        progress=False,
    )
    scene, stored, result = looked_up(path)
    assert stored.source == "texture" and sorted(stored.textures) == [0, 1]
    assert [stored.textures[m].texcoord for m in (0, 1)] == [1, 0]
    g, corners, weights = hits(scene, CAMERA)
    check_frame(result, g, "texture")
    expected, materials = baked_expectation(scene, bake, g, weights)
    assert (materials == 0).sum() > 200 and (materials == 1).sum() > 100
    # The PNG holds the values rounded to its bit depth; bilinear weights sum to 1, so the error stays within that.
    np.testing.assert_allclose(result.ao[g.mask], expected, rtol=0, atol=0.5 / (2**bit_depth - 1) + 1e-6)
    assert np.ptp(result.ao[g.mask]) > 0.1


def test_a_texture_bake_into_generated_uvs_reads_the_new_uv_set(tmp_path):
    """The Cornell box (one material, no UVs): new charts packed into a new TEXCOORD_0."""
    source, path = REPO / "tests" / "data" / "cornell_box.glb", tmp_path / "cornell.glb"
    bake = mbao.bake_file(source, path, target="texture", texcoord="generate", resolution=32, samples=2, progress=False)
    scene, stored, result = looked_up(path, camera=None)
    assert stored.source == "texture" and list(stored.textures) == list(bake.textures) == [0]
    g, corners, weights = hits(scene, None)
    check_frame(result, g, "texture")
    triangles = g.triangle[g.mask]
    uv = (triangle_uvs(scene, bake)[triangles] * weights[:, :, None]).sum(axis=1)
    (texture,) = bake.textures.values()
    np.testing.assert_allclose(
        result.ao[g.mask], bilinear(texture.image, uv, texture.stats["wrap"]), rtol=0, atol=0.5 / 255 + 1e-6
    )
    assert g.mask.sum() > SIZE * SIZE / 4 and np.ptp(result.ao[g.mask]) > 0.1


@pytest.mark.parametrize(
    "where, wrap_s, wrap_t",
    [
        ("bufferView", REPEAT, MIRRORED_REPEAT),
        ("data-uri", CLAMP_TO_EDGE, REPEAT),
        ("file", MIRRORED_REPEAT, CLAMP_TO_EDGE),
    ],
)
def test_an_occlusion_texture_wraps_uvs_outside_the_image(tmp_path, rng, where, wrap_s, wrap_t):
    """A hand-made 5 x 3 RGB texture, R unlike G and B, on a quad whose TEXCOORD_1
    (the one the texture reads; TEXCOORD_0 is a decoy) runs from -1.3 to 2.2."""
    pixels = rng.integers(0, 256, (3, 5, 3), dtype=np.uint8)
    b = GltfBuilder()
    image = b.add_image(png_bytes(pixels, tmp_path), where=where, file_name="occlusion.png")
    material = b.add_material()
    b.doc["materials"][material]["occlusionTexture"] = {"index": b.add_texture(image, wrap_s, wrap_t), "texCoord": 1}
    quad = np.array([[-1, -1, 0], [1, -1, 0], [1, 1, 0], [-1, 1, 0]], float)
    texcoords = np.array([[-1.3, 1.9], [2.2, 1.9], [2.2, -0.7], [-1.3, -0.7]])
    primitive = b.primitive(quad, [[0, 1, 2], [0, 2, 3]], texcoords=np.zeros((4, 2)), material=material)
    primitive["attributes"]["TEXCOORD_1"] = b.add_texcoords(texcoords)
    b.add_scene([b.add_node(mesh=b.add_mesh([primitive]))], default=True)
    path = b.write(tmp_path / "quad.gltf")
    camera = mbao.Camera((0.0, 0.0, 3.0), (0.0, 0.0, 0.0), (0.0, 1.0, 0.0), 45.0)
    scene, stored, result = looked_up(path, camera)
    assert stored.textures[0].wrap == (WRAP_NAMES[wrap_s], WRAP_NAMES[wrap_t])
    g, corners, weights = hits(scene, camera)
    check_frame(result, g, "texture")
    uv = (texcoords[corners] * weights[:, :, None]).sum(axis=1)
    assert uv.min() < -1 and uv.max() > 2 and g.mask.sum() > SIZE * SIZE / 2
    expected = bilinear(pixels[:, :, 0] / 255.0, uv, (WRAP_NAMES[wrap_s], WRAP_NAMES[wrap_t]))
    np.testing.assert_allclose(result.ao[g.mask], expected, rtol=0, atol=1e-5)


def test_a_file_without_a_bake_has_none(tmp_path):
    b = GltfBuilder()
    b.add_scene([b.add_node(mesh=b.add_mesh([b.primitive(*square())]))], default=True)
    path = b.write(tmp_path / "plain.glb")
    assert load_bake(path, mbao.load(path, texcoords=True)) is None
    obj = tmp_path / "plain.obj"
    write_obj(obj, *square())
    assert load_bake(obj, mbao.load(obj)) is None  # not glTF: mbao reads no bake from it


def square():
    vertices = np.array([[-1, 0, -1], [1, 0, -1], [1, 0, 1], [-1, 0, 1]], float)
    return vertices, np.array([[0, 2, 1], [0, 3, 2]])


def test_a_corrupt_bake_is_a_load_error_naming_the_file(vertex_baked, tmp_path):
    path, _ = vertex_baked
    document = GltfDocument(path)
    accessor = document.doc["meshes"][0]["primitives"][1]["attributes"]["_OCCLUSION"]
    document.doc["accessors"][accessor]["count"] -= 1
    corrupt = tmp_path / "corrupt.glb"
    document.write(corrupt)
    scene = mbao.load(corrupt, texcoords=True)  # the loader reads no _OCCLUSION
    with pytest.raises(
        mbao.LoadError,
        match=rf"corrupt\.glb: mesh 0 primitive 1 _OCCLUSION \(accessor {accessor}\) " r"has 3 values for 4 positions",
    ):
        load_bake(corrupt, scene)


def test_an_occlusion_image_that_does_not_decode_is_a_load_error(tmp_path):
    b = GltfBuilder()
    image = b.add_image(b"not a PNG", where="file", file_name="broken.png")
    material = b.add_material()
    b.doc["materials"][material]["occlusionTexture"] = {"index": b.add_texture(image)}
    vertices, indices = square()
    b.add_scene(
        [
            b.add_node(
                mesh=b.add_mesh([b.primitive(vertices, indices, texcoords=vertices[:, [0, 2]], material=material)])
            )
        ],
        default=True,
    )
    path = b.write(tmp_path / "broken.gltf")
    with pytest.raises(mbao.LoadError, match=r"broken\.gltf: image 0: cannot decode it"):
        load_bake(path, mbao.load(path, texcoords=True))


def test_the_viewer_offers_a_files_bake_and_shows_it(vertex_baked):
    """The page's "baked" method shows baked_occlusion's image of the same camera."""
    path, _ = vertex_baked
    with served(path, width=SIZE, height=SIZE) as viewer:

        async def baked_view():
            async with connected(viewer) as page:
                methods = next(s["choices"] for s in page.hello["specs"] if s["name"] == "method")
                await page.send(type="set", camera=messages.camera_json(CAMERA), settings={"method": "baked"})
                return methods, await page.still_frame(1)

        methods, (header, payload) = run(baked_view())
    assert "baked" in methods and header["final"]
    _, _, expected = looked_up(path)
    np.testing.assert_array_equal(decode(payload), to_8bit(expected.ao))
