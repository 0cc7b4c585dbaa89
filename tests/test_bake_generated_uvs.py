"""Generated UV sets (mbao.bake(texcoord="generate"), SPEC 6.3): charts that
never overlap, one texel density, the stretch they report, and bakes into them."""

import re
import warnings

import numpy as np
import pytest

import mbao
from conftest import shared_scene
from meshes import box, icosphere, merge, plane, quads_to_triangles


def generated(vertices, indices, **settings):
    settings.setdefault("samples", 2)
    settings.setdefault("progress", False)
    return mbao.bake(mbao.Mesh(vertices, indices), target="texture", texcoord="generate", **settings).textures[0]


def test_a_plane_is_one_chart_without_stretch_and_bakes_to_one():
    texture = generated(*plane(1.0, divisions=4), resolution=32)
    assert texture.texcoord == "generated"
    assert texture.stats["charts"] == 1 and texture.stats["worst_stretch"] == 1.0
    assert texture.stats["claimed_twice"] == 0
    np.testing.assert_array_equal(texture.image, 1.0)


@pytest.mark.parametrize("padding", [3, 4])
def test_a_chart_lies_half_the_padding_from_the_border(padding):
    """Generated UVs wrap with REPEAT: a chart at one edge and one at the other
    lie `padding` apart across it where each lies half of it (rounded up) from
    the border. A 2 x 2 plane's box, a texel more than its chart, then takes
    32 - 2 * 2 texels of 32: 27 texels per 2 units, to the density's 0.1%."""
    resolution, border = 32, (padding + 1) // 2
    texture = generated(*plane(1.0, divisions=2), resolution=resolution, padding=padding)
    assert texture.stats["charts"] == 1 and texture.stats["chart_padding"] == padding
    assert 27 / 2 / 1.001 <= texture.stats["texels_per_unit"] <= 27 / 2
    texels = texture.texcoords.reshape(-1, 2) * resolution
    assert texels.min() >= border + 0.5 - 1e-4 and texels.max() <= resolution - border + 1e-4


def stretches(texture, vertices, indices, resolution):
    """Per triangle, the two factors (largest first) by which its map onto the texture lengthens a direction
    in it, in texels per unit: the singular values of the map from the triangle's plane to its UVs."""
    corners = vertices[indices[texture.triangles]]
    e1, e2 = corners[:, 1] - corners[:, 0], corners[:, 2] - corners[:, 0]
    x = e1 / np.linalg.norm(e1, axis=1, keepdims=True)
    y = e2 - np.sum(e2 * x, axis=1, keepdims=True) * x
    y /= np.linalg.norm(y, axis=1, keepdims=True)
    flat = np.stack(
        [np.stack([np.sum(e1 * x, 1), np.sum(e1 * y, 1)], 1), np.stack([np.sum(e2 * x, 1), np.sum(e2 * y, 1)], 1)], 2
    )
    uv = texture.texcoords.astype(float) * resolution
    mapped = np.stack([uv[:, 1] - uv[:, 0], uv[:, 2] - uv[:, 0]], 2)
    return np.linalg.svd(mapped @ np.linalg.inv(flat), compute_uv=False)


def test_charts_share_one_density_and_stretch_at_most_1_25():
    """Every triangle's map onto the texture is the density (texels per unit)
    times a map that lengthens or shortens no direction by more than
    worst_stretch <= 1.25 (up to float32 UVs: 1e-3)."""
    vertices, indices = icosphere(1.0, subdivisions=3)
    resolution = 256
    texture = generated(vertices, indices, resolution=resolution)
    stats = texture.stats
    assert stats["charts"] > 2 and 1.0 < stats["worst_stretch"] <= 1.25 and stats["claimed_twice"] == 0
    factors = stretches(texture, vertices, indices, resolution) / stats["texels_per_unit"]
    assert factors.max() <= stats["worst_stretch"] + 1e-3 and factors.min() >= 1.0 / stats["worst_stretch"] - 1e-3
    assert 0.05 < stats["texels_used"] <= 1.0


def test_a_tubes_side_unrolls_into_two_charts_without_stretch():
    """A tube's side is cut in two and each half laid flat by a conformal map,
    which keeps its lengths; charts projected onto planes would each take at
    most 74 degrees of its 360, and squeeze their sides."""
    around, rows = 24, 4
    angle = 2 * np.pi * np.arange(around) / around
    vertices = np.array([[np.cos(a), 0.5 * j, np.sin(a)] for j in range(rows + 1) for a in angle])
    quads = [[j * around + i, (j + 1) * around + i, (j + 1) * around + (i + 1) % around, j * around + (i + 1) % around]
             for j in range(rows) for i in range(around)]  # fmt: skip
    indices = quads_to_triangles(quads)
    resolution = 32  # where seven charts' padding costs more than two's
    texture = generated(vertices, indices, resolution=resolution)
    assert texture.stats["charts"] == 2 and texture.stats["claimed_twice"] == 0
    assert texture.stats["worst_stretch"] < 1.0 + 1e-6
    factors = stretches(texture, vertices, indices, resolution) / texture.stats["texels_per_unit"]
    np.testing.assert_allclose(factors, 1.0, atol=2e-3)


def floor_cells(cells, y=0.0):
    """Unit squares of the floor y = const, facing up, one per (i, j) cell."""
    vertices, quads = [], []
    for i, j in cells:
        quads.append(len(vertices) + np.arange(4))
        vertices += [[i, y, j], [i, y, j + 1], [i + 1, y, j + 1], [i + 1, y, j]]
    return np.array(vertices, float), quads_to_triangles(quads)


def test_a_small_chart_is_packed_into_the_gap_a_larger_one_leaves():
    """An L of floor (a 3 x 3 square less a corner) and a wall square: first
    fit, largest first, puts the square in the L's missing corner, inside the
    L's box, where packing boxes would need room beside it."""
    floor = floor_cells([(i, j) for i in range(3) for j in range(3) if (i, j) != (2, 2)])
    wall = (np.array([[5.0, 0.0, 0.0], [5.0, 0.8, 0.0], [5.0, 0.8, 0.8], [5.0, 0.0, 0.8]]), [[0, 1, 2], [0, 2, 3]])
    texture = generated(*merge(floor, wall), resolution=64, padding=2)
    assert texture.stats["charts"] == 2 and texture.stats["claimed_twice"] == 0
    uv = texture.texcoords[np.argsort(texture.triangles)]
    floor_uv, wall_uv = uv[:16].reshape(-1, 2), uv[16:].reshape(-1, 2)
    assert np.all(wall_uv >= floor_uv.min(axis=0)) and np.all(wall_uv <= floor_uv.max(axis=0))


def test_a_long_strip_is_cut_so_that_it_does_not_set_the_density():
    """A floor 32 units long and 1 wide, uncut, would fit 64 texels at no more
    than (64 - 2 * padding - 1) / 32 texels per unit; cut across into pieces,
    it packs denser."""
    resolution, padding = 64, 2
    texture = generated(*floor_cells([(i, 0) for i in range(32)]), resolution=resolution, padding=padding)
    assert texture.stats["charts"] > 1 and texture.stats["claimed_twice"] == 0
    assert texture.stats["texels_per_unit"] > 2 * (resolution - 2 * padding - 1) / 32


def test_a_strip_whose_triangles_span_it_is_not_cut():
    """Four quads apart, each 32 units long and 1 wide, of two triangles that
    both span its length (a chain's links): cut across, each would only part
    into its two triangles, as long as the quad and padded apart, so each
    stays one chart."""
    quad = np.array([[0.0, 0.0, 0.0], [32.0, 0.0, 0.0], [32.0, 0.0, -1.0], [0.0, 0.0, -1.0]])
    vertices = np.concatenate([quad + [0.0, 0.0, 3.0 * k] for k in range(4)])
    indices = np.concatenate([np.array([[0, 1, 2], [0, 2, 3]]) + 4 * k for k in range(4)])
    texture = generated(vertices, indices, resolution=64, padding=2)
    assert texture.stats["charts"] == 4 and texture.stats["claimed_twice"] == 0


def test_duplicated_triangles_and_folds_get_charts_of_their_own():
    """Two copies of one floor (the same positions, the same winding) would
    project onto one another in one chart: the second copy is taken out into
    charts of its own, and nothing is claimed twice."""
    vertices, indices = plane(1.0, divisions=3)
    texture = generated(*merge((vertices, indices), (vertices, indices)), resolution=64)
    assert texture.stats["charts"] >= 2 and texture.stats["claimed_twice"] == 0


@pytest.mark.filterwarnings("ignore:.*looks closed")
def test_a_closed_box_bakes_to_zero_inside_through_generated_uvs():
    vertices, indices = box((-1.0, -1.0, -1.0), (1.0, 1.0, 1.0))
    texture = generated(vertices, indices, resolution=64, samples=8, padding=2)
    assert texture.stats["claimed_twice"] == 0
    np.testing.assert_array_equal(texture.image[texture.coverage], 0.0)


def test_charts_that_fit_only_closer_are_packed_so_with_a_warning_naming_the_resolution_that_keeps_the_padding():
    sphere = icosphere(1.0, subdivisions=2)
    with pytest.warns(
        UserWarning,
        match=r"generated charts fit 16 x 16 texels only \d texels? apart, not padding=4, "
        r"at .* texels per unit; resolution=(\d+) keeps them 4 apart",
    ) as caught:
        texture = generated(*sphere, resolution=16, padding=4)
    assert texture.stats["chart_padding"] < 4 and texture.stats["claimed_twice"] == 0
    keeping = int(re.search(r"resolution=(\d+)", str(caught[0].message)).group(1))
    assert texture.stats["size_keeping_padding"] == (keeping, keeping)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        kept = generated(*sphere, resolution=keeping, padding=4)
    assert kept.stats["chart_padding"] == 4
    with pytest.warns(UserWarning, match="only"):  # the next smaller power of two does not keep it
        generated(*sphere, resolution=keeping // 2, padding=4)


def test_charts_that_cannot_fit_even_touching_are_refused():
    """20 triangles apart are 20 charts however they are laid flat; each needs a texel in a box of 2 x 2."""
    triangle = (np.array([[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]]), [[0, 1, 2]])
    apart = merge(*[(triangle[0] + (3.0 * k, 0.0, 0.0), triangle[1]) for k in range(20)])
    with pytest.raises(
        ValueError, match=r"20 charts do not fit 4 x 4 texels even at a texel each and touching; raise the resolution"
    ):
        generated(*apart, resolution=4, padding=4)


def test_the_damaged_helmet_bakes_into_generated_uvs_at_64_texels_with_a_warning():
    """Its nearly 500 charts fit 64 x 64 only closer than 4 texels apart (issue 60)."""
    path = shared_scene("damaged_helmet") / "scene.glb"
    with pytest.warns(UserWarning, match=r"resolution=\d+ keeps them 4 apart"):
        bake = mbao.bake(path, target="texture", texcoord="generate", resolution=64, samples=2, progress=False)
    assert bake.textures[0].stats["claimed_twice"] == 0


def test_the_damaged_helmet_bakes_into_generated_uvs():
    """Its own UVs are mirrored (refused: test_bake_gltf.py); generated ones hold it."""
    path = shared_scene("damaged_helmet") / "scene.glb"
    bake = mbao.bake(path, target="texture", texcoord="generate", resolution=256, samples=2, progress=False)
    texture = bake.textures[0]
    assert texture.stats["claimed_twice"] == 0 and texture.stats["charts"] > 100
    assert texture.stats["unmapped_triangles"] == 0


def test_vertices_split_at_minus_zero_still_join_one_chart():
    """Two halves of a floor whose vertices on the seam x = 0 are duplicated,
    the left half's with x = -0.0: equal positions, so one chart."""
    left = np.array([[-1.0, 0.0, -1.0], [-0.0, 0.0, -1.0], [-0.0, 0.0, 1.0], [-1.0, 0.0, 1.0]])
    right = np.array([[0.0, 0.0, -1.0], [1.0, 0.0, -1.0], [1.0, 0.0, 1.0], [0.0, 0.0, 1.0]])
    quad = [[0, 2, 1], [0, 3, 2]]  # facing up
    texture = generated(*merge((left, quad), (right, quad)), resolution=32)
    assert texture.stats["charts"] == 1


def ring(outer, inner, segments):
    """A flat ring in the floor y = 0, facing up: `segments` quads around."""
    angles = 2 * np.pi * np.arange(segments) / segments
    circle = np.stack([np.cos(angles), np.zeros(segments), -np.sin(angles)], axis=1)
    vertices = np.concatenate([outer * circle, inner * circle])
    k = np.arange(segments)
    following = (k + 1) % segments
    quads = np.stack([k, following, segments + following, segments + k], axis=1)
    return vertices, quads_to_triangles(quads)


def test_a_ring_is_cut_into_arcs_that_pack_denser_than_its_box():
    """A ring 2 units across, uncut, would fit 64 texels at no more than
    (64 - 2 * padding - 1) / 2 texels per unit; its triangles fill a fifth of
    its box, so it is cut into arcs, which pack denser."""
    resolution, padding = 64, 2
    texture = generated(*ring(1.0, 0.9, 64), resolution=resolution, padding=padding)
    assert texture.stats["charts"] > 1 and texture.stats["claimed_twice"] == 0
    assert texture.stats["texels_per_unit"] > 1.2 * (resolution - 2 * padding - 1) / 2


def test_thin_triangles_nest_in_pairs_one_half_turned():
    """16 equal obtuse triangles, apart, each 4 units long and 0.5 high. Two,
    one half turned, make a parallelogram 5 units long and 0.5 high, and eight
    of those fit a square 5 units a side. As they are, two leave a wedge empty
    between them: their boxes need a square 8 units a side, and first fit
    without turns (mbao before half turns) one of more than 7."""
    resolution, padding = 128, 1
    triangle = np.array([[0.0, 0.0, 0.0], [4.0, 0.0, 0.0], [1.0, 0.0, -0.5]])
    vertices = np.concatenate([triangle + [0.0, 0.0, 2.0 * k] for k in range(16)])
    indices = np.arange(48).reshape(16, 3)
    texture = generated(vertices, indices, resolution=resolution, padding=padding)
    assert texture.stats["charts"] == 16 and texture.stats["claimed_twice"] == 0
    assert texture.stats["texels_per_unit"] > (resolution - 2 * padding - 1) / 6


def test_a_chart_that_fits_no_other_way_is_packed_a_quarter_turned():
    """A quad 32 units long and 1 wide, of two triangles that span it (not
    cut), in a texture 16 texels wide and 64 high: lying along x it would fit
    at no more than (16 - 2 * padding - 1) / 32 texels per unit; standing
    along y it fits at more."""
    width, height, padding = 16, 64, 1
    vertices = np.array([[0.0, 0.0, 0.0], [32.0, 0.0, 0.0], [32.0, 0.0, -1.0], [0.0, 0.0, -1.0]])
    texture = generated(vertices, np.array([[0, 1, 2], [0, 2, 3]]), resolution=(width, height), padding=padding)
    assert texture.stats["charts"] == 1 and texture.stats["claimed_twice"] == 0
    assert texture.stats["texels_per_unit"] > 2 * (width - 2 * padding - 1) / 32


def test_a_few_large_charts_are_cut_where_that_packs_denser():
    """Five equal square floors, 2 units a side, apart: no five squares of
    side a fit a square of side less than (2 + 1 / sqrt(2)) a (Goebel, 1979),
    so uncut they fit 256 texels at no more than (256 - 2 * padding) /
    (2 * (2 + 1 / sqrt(2))) texels per unit. Cut, they pack denser. One floor
    alone is not cut (the plane above)."""
    resolution, padding = 256, 2
    floors = floor_cells([(3 * k + i, j) for k in range(5) for i in range(2) for j in range(2)])
    texture = generated(*floors, resolution=resolution, padding=padding)
    assert texture.stats["charts"] > 5 and texture.stats["claimed_twice"] == 0
    assert texture.stats["texels_per_unit"] > (resolution - 2 * padding) / (2 * (2 + 1 / np.sqrt(2)))
