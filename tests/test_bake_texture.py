"""Baking per texel (SPEC 6.3): closed-form answers, agreement with the vertex
bake, wrap modes, coverage, dilation and the refusal of UVs that claim a texel
twice. Statistical checks allow 4 standard errors of the estimator."""

import math
import warnings

import numpy as np
import pytest

import mbao
from analytic import assert_within_standard_errors, polygon_occlusion, spec_ray_directions
from meshes import box, disk, merge, plane


def bake(vertices, indices, texcoords, **settings):
    settings.setdefault("progress", False)
    return mbao.bake(mbao.Mesh(vertices, indices, texcoords=texcoords), target="texture", **settings)


def floor_uvs(vertices, half_size, lo=0.0, hi=1.0):
    """The floor's (x, z) mapped onto [lo, hi]^2 of the texture."""
    return lo + (vertices[:, [0, 2]] + half_size) / (2.0 * half_size) * (hi - lo)


def floor_with_a_box(lo=0.0, hi=1.0, box_at=(0.0, 0.0)):
    """A floor of 4 x 4 (y = 0, facing up) with UVs, and a unit box on it centred
    at (x, z) = box_at, whose triangles have no UV area."""
    floor, floor_indices = plane(2.0, divisions=16)
    x, z = box_at
    block, block_indices = box((x - 0.5, 0.0, z - 0.5), (x + 0.5, 1.0, z + 0.5))
    vertices, indices = merge((floor, floor_indices), (block, block_indices[:, ::-1]))
    texcoords = np.full((len(vertices), 2), 0.5)
    texcoords[: len(floor)] = floor_uvs(floor, 2.0, lo, hi)
    return vertices, indices, texcoords


def test_a_plane_bakes_to_one_in_every_texel():
    """A lone plane whose UVs cover the texture: every texel covered, exactly 1, no spread."""
    vertices, indices = plane(1.0, divisions=8)
    result = bake(vertices, indices, floor_uvs(vertices, 1.0), resolution=(32, 16), samples=16, bounces=2)
    texture = result.textures[0]
    assert texture.image.shape == (16, 32)
    assert texture.coverage.all()
    np.testing.assert_array_equal(texture.image, 1.0)
    np.testing.assert_array_equal(texture.standard_error, 0.0)
    assert texture.stats["claimed_twice"] == 0


@pytest.mark.filterwarnings("ignore:.*left out of the bake")  # the disk has no UV area: it only occludes
def test_the_texel_under_a_parallel_disk():
    """The texel under the centre of a parallel disk (b = 1) holds the mean over
    its square of 1 - F, F the disk's form factor; at the centre that is h^2 / (h^2 + R^2)."""
    height, radius, half_size, resolution = 1.0, 0.8, 1.5, 15  # the middle texel is centred on the axis
    floor, floor_indices = plane(half_size, divisions=6)
    disk_vertices, disk_indices = disk(radius, height, 64)
    vertices, indices = merge((floor, floor_indices), (disk_vertices, disk_indices))
    texcoords = np.zeros((len(vertices), 2))
    texcoords[: len(floor)] = floor_uvs(floor, half_size)
    samples = 20000
    # One direction per estimate: each is 0 or 1, a Bernoulli variable.
    texture = bake(
        vertices, indices, texcoords, resolution=resolution, samples=samples, bounces=1, directions=1
    ).textures[0]

    texel = 2.0 * half_size / resolution
    nodes, weights = np.polynomial.legendre.leggauss(8)
    expected = (
        sum(
            wi
            * wj
            * (1.0 - polygon_occlusion(np.array([xi * texel / 2, 0.0, zj * texel / 2]), (0, 1, 0), disk_vertices[1:]))
            for xi, wi in zip(nodes, weights)
            for zj, wj in zip(nodes, weights)
        )
        / 4.0
    )
    middle = resolution // 2
    assert abs(expected - height**2 / (height**2 + radius**2)) < 5e-3
    assert_within_standard_errors(float(texture.image[middle, middle]), expected, samples)


@pytest.mark.filterwarnings("ignore:.*left out of the bake")  # walls seen edge-on in the UVs
def test_texels_and_vertices_agree_on_the_surfaces_mean():
    """Both bakes estimate the floor's mean of L_b: the texels' mean (texels of
    equal area) and the vertices' mean weighted by their hat functions'
    integrals (they sum to 1 everywhere) agree within 4 standard errors."""
    vertices, indices, texcoords = floor_with_a_box()
    texture = bake(vertices, indices, texcoords, resolution=32, samples=64, bounces=2).textures[0]
    per_vertex = mbao.bake(mbao.Mesh(vertices, indices), samples=256, bounces=2, progress=False)
    texel_mean = texture.image.mean()
    texel_error = math.sqrt(np.sum(texture.standard_error.astype(float) ** 2)) / texture.image.size

    floor_vertices = len(plane(2.0, divisions=16)[0])
    floor_triangles = indices[: 2 * 16 * 16]
    corners = vertices[floor_triangles]
    areas = 0.5 * np.linalg.norm(np.cross(corners[:, 1] - corners[:, 0], corners[:, 2] - corners[:, 0]), axis=1)
    weights = np.zeros(floor_vertices)
    np.add.at(weights, floor_triangles.ravel(), np.repeat(areas / 3.0, 3))
    values = per_vertex.values[:floor_vertices].astype(float)
    vertex_mean = np.sum(weights * values) / weights.sum()
    vertex_error = math.sqrt(np.sum((weights * per_vertex.standard_error[:floor_vertices]) ** 2)) / weights.sum()
    assert 0.3 < texel_mean < 0.95
    assert abs(texel_mean - vertex_mean) <= 4.0 * math.hypot(texel_error, vertex_error)


def one_quad(u0, v0, u1, v1):
    """A unit quad facing up whose UVs span [u0, u1] x [v0, v1]."""
    vertices, indices = plane(0.5, divisions=1)
    texcoords = np.column_stack([np.where(vertices[:, 0] < 0, u0, u1), np.where(vertices[:, 2] < 0, v0, v1)])
    return vertices, indices, texcoords


def coverage(u0, v0, u1, v1, wrap, resolution=16):
    return bake(*one_quad(u0, v0, u1, v1), resolution=resolution, samples=2, wrap=wrap).textures[0].coverage


def test_uvs_beyond_the_unit_square_follow_the_wrap_mode():
    """REPEAT takes the fractional part, MIRRORED_REPEAT mirrors odd periods,
    CLAMP_TO_EDGE gives the edge texel everything beyond it (SPEC 6.3)."""
    inside = coverage(0.0, 0.0, 0.5, 0.25, "repeat")
    assert inside.sum() == 8 * 4 and inside[:4, :8].all()
    np.testing.assert_array_equal(coverage(1.0, -2.0, 1.5, -1.75, "repeat"), inside)
    np.testing.assert_array_equal(coverage(1.0, 0.0, 1.5, 0.25, "mirrored-repeat"), np.fliplr(inside))
    np.testing.assert_array_equal(coverage(1.0, 0.0, 1.5, 0.25, ("mirrored-repeat", "repeat")), np.fliplr(inside))
    np.testing.assert_array_equal(coverage(0.0, -1.0, 0.5, -0.75, ("repeat", "mirrored-repeat")), np.flipud(inside))
    clamped = coverage(-0.5, 0.0, 0.25, 0.25, "clamp-to-edge")
    assert clamped[:4, :4].all() and clamped.sum() == 16


@pytest.mark.parametrize(
    "texcoords, fraction",
    [
        (lambda v: np.abs(v[:, [0, 2]]), "100.0%"),  # mirrored halves: both halves of the plane share one quarter
        (lambda v: (v[:, [0, 2]] + 1.0), "100.0%"),  # tiled: the UVs span [0, 2]^2, each texel four times
    ],
)
def test_uvs_that_claim_a_texel_twice_are_refused(texcoords, fraction):
    vertices, indices = plane(1.0, divisions=8)
    with pytest.raises(
        mbao.Error,
        match=f"the mesh, UV set TEXCOORD_0: {fraction} of its .* covered texels are claimed by more than one",
    ):
        bake(vertices, indices, texcoords(vertices), resolution=16, samples=2)


def test_an_edge_through_sample_points_claims_each_once():
    """The diagonal of a quad whose UVs fill the texture passes through the
    sample points of the diagonal texels: the fill rule gives each to one triangle."""
    vertices, indices = plane(1.0, divisions=1)
    texture = bake(vertices, indices, floor_uvs(vertices, 1.0), resolution=8, samples=2).textures[0]
    assert texture.stats["claimed_twice"] == 0 and texture.coverage.all()


@pytest.mark.filterwarnings("ignore:.*left out of the bake")  # walls seen edge-on in the UVs
def test_dilation_fills_padding_texels_from_the_nearest_covered():
    """The floor's UVs fill the middle 8 x 8 of 16 x 16: with padding 2 the ring
    of 2 texels around takes the nearest covered texel's value; beyond it, 1 (SPEC 6.3)."""
    vertices, indices, texcoords = floor_with_a_box(0.25, 0.75)
    texture = bake(vertices, indices, texcoords, resolution=16, samples=16, padding=2).textures[0]
    image, error = texture.image, texture.standard_error
    assert texture.coverage[4:12, 4:12].all() and texture.coverage.sum() == 64
    assert texture.stats["dilated"] == 12 * 12 - 8 * 8
    assert image[5, 2] == image[5, 4] and image[2, 2] == image[4, 4] and image[13, 9] == image[11, 9]
    assert error[5, 2] == error[5, 4]
    assert image[5, 1] == 1.0 and error[5, 1] == 0.0 and image[0, 0] == 1.0


@pytest.mark.parametrize(
    "arguments, error, message",
    [
        (dict(resolution=0), ValueError, r"resolution must be in \[1, 16384\]"),
        (dict(resolution=(8, 8, 8)), ValueError, "resolution must be an int or"),
        (dict(padding=65), ValueError, r"padding must be in \[0, 64\]"),
        (dict(wrap="wrap"), ValueError, "wrap must be one of"),
        (dict(texcoord=1), ValueError, "texcoord must be None or 0 for an mbao.Mesh"),
    ],
)
def test_bad_texture_arguments_name_themselves(arguments, error, message):
    vertices, indices = plane(1.0)
    with pytest.raises(error, match=message):
        bake(vertices, indices, floor_uvs(vertices, 1.0), samples=2, **arguments)


def test_a_texture_bake_needs_uvs():
    with pytest.raises(ValueError, match="a texture bake needs UVs"):
        mbao.bake(mbao.Mesh(*plane(1.0)), target="texture", progress=False)


def bilinear(image, standard_error, uv):
    """The image looked up at texture coordinates uv (N, 2) between texel
    centres, as a viewer samples it, and the standard error of that lookup:
    of a weighted sum of independent texels, sqrt(sum of w^2 se^2)."""
    height, width = image.shape
    x, y = uv[:, 0] * width - 0.5, uv[:, 1] * height - 0.5
    x0, y0 = np.floor(x).astype(int), np.floor(y).astype(int)
    fx, fy = x - x0, y - y0
    value = variance = 0.0
    for i, j, w in (
        (x0, y0, (1 - fx) * (1 - fy)),
        (x0 + 1, y0, fx * (1 - fy)),
        (x0, y0 + 1, (1 - fx) * fy),
        (x0 + 1, y0 + 1, fx * fy),
    ):
        texel = np.clip(j, 0, height - 1), np.clip(i, 0, width - 1)
        value = value + w * image[texel]
        variance = variance + w**2 * standard_error[texel] ** 2
    return value, np.sqrt(variance)


@pytest.mark.filterwarnings("ignore:.*left out of the bake")  # walls seen edge-on in the UVs
def test_a_baked_texture_looked_up_at_the_cameras_hits_matches_the_render():
    """Where the camera sees the floor, the texture looked up at each pixel's
    hit (bilinear, as a viewer samples it) and the render agree within their
    noise: the mean of z^2 = (render - lookup)^2 / (se_render^2 + se_texel^2)
    is 1 within 4 of its standard errors, sqrt(2 / n). Pixels within a quarter
    of a unit of the box's foot are left out: there AO bends too fast for a
    bilinear lookup of 1/16-unit texels. The box stands off the floor's centre,
    so a flipped u or v would show."""
    box_at = (0.6, -0.5)
    vertices, indices, texcoords = floor_with_a_box(box_at=box_at)
    scene = mbao.Mesh(vertices, indices, texcoords=texcoords)
    resolution, samples, r = 64, 256, 256
    texture = mbao.bake(
        scene, target="texture", resolution=resolution, samples=samples, bounces=1, progress=False
    ).textures[0]
    camera = mbao.Camera((0.3, 5.0, 3.0), (0.0, 0.0, 0.0), vfov_deg=40.0)
    width = height = 48
    render = mbao.render(scene, camera=camera, width=width, height=height, bounces=1, samples=r)
    directions = spec_ray_directions(camera, width, height).reshape(-1, 3)
    _, triangle, barycentrics = mbao.trace(scene, np.tile(camera.eye, (len(directions), 1)), directions)
    floor_triangles = 2 * 16 * 16
    on_floor = (triangle >= 0) & (triangle < floor_triangles)
    corners = scene.indices[triangle[on_floor]]
    b1, b2 = barycentrics[on_floor, 0:1], barycentrics[on_floor, 1:2]
    uv = (1 - b1 - b2) * texcoords[corners[:, 0]] + b1 * texcoords[corners[:, 1]] + b2 * texcoords[corners[:, 2]]
    point = uv * 4.0 - 2.0  # the floor's (x, z)
    from_box = np.maximum(np.abs(point - box_at) - 0.5, 0.0)
    away = np.max(from_box, axis=1) > 0.25
    inside = np.max(np.abs(point), axis=1) < 2.0 - 2.0 / resolution * 4.0  # a texel from the floor's edge
    keep = away & inside
    assert keep.sum() > 800
    rendered = render.ao.reshape(-1)[on_floor][keep].astype(float)
    looked_up, texel_error = bilinear(texture.image.astype(float), texture.standard_error.astype(float), uv[keep])
    # Each pixel is a mean of r Bernoulli outcomes, whose mean the texture estimates
    # with less noise than the pixel itself.
    render_error2 = np.maximum(looked_up * (1 - looked_up), 1.0 / r) / r
    z2 = (rendered - looked_up) ** 2 / (render_error2 + texel_error**2)
    assert abs(z2.mean() - 1.0) <= 4.0 * math.sqrt(2.0 / keep.sum()), z2.mean()


def test_a_uv_set_without_area_is_refused_before_tracing():
    """SPEC 6.3: UVs collapsed onto a line leave nothing to bake into."""
    vertices, indices = plane(1.0, divisions=2)
    on_a_line = np.column_stack([(vertices[:, 0] + 1) / 2, np.zeros(len(vertices))])
    with pytest.raises(
        ValueError,
        match=r"the mesh, UV set TEXCOORD_0: the UVs of all its 8 triangles have no area " r".*texcoord=\"generate\"",
    ):
        bake(vertices, indices, on_a_line, resolution=16, samples=2)


def test_a_texture_bake_of_some_triangles_is_the_bake_of_those_texels():
    """SPEC 6: the floor baked alone, the box on it only occluding. No warning of
    the box's UVs (it is not baked), and the texels are those of the bake of
    everything, bit for bit: the same texels hold the same surface."""
    vertices, indices, texcoords = floor_with_a_box()
    floor_triangles = np.arange(len(indices) - 12)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        alone = bake(vertices, indices, texcoords, resolution=16, samples=8, triangles=floor_triangles).textures[0]
    np.testing.assert_array_equal(alone.triangles, floor_triangles)
    assert alone.image.min() < 0.9  # beside the box
    with pytest.warns(UserWarning, match="12 of its"):
        everything = bake(vertices, indices, texcoords, resolution=16, samples=8).textures[0]
    np.testing.assert_array_equal(alone.image, everything.image)
    np.testing.assert_array_equal(alone.standard_error, everything.standard_error)


def test_a_uv_set_with_area_in_part_bakes_with_a_warning_of_what_it_left_out():
    """Two quads, the second's UVs all on one point: its 2 triangles are left out, with a warning."""
    vertices, indices = plane(1.0)
    texcoords = np.vstack([(vertices[:, [0, 2]] + 1) / 2, np.full((len(vertices), 2), 0.5)])
    vertices, indices = merge((vertices, indices), (vertices + (3.0, 0.0, 0.0), indices))
    with pytest.warns(UserWarning, match=r"2 of its 4 triangles have UVs without area and are left out of the bake"):
        texture = bake(vertices, indices, texcoords, resolution=16, samples=2).textures[0]
    assert texture.coverage.any()
