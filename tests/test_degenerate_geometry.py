"""Geometry that stresses the kd-tree and the ray/triangle test: triangles
without area, needles and slivers, duplicated and coplanar overlapping
triangles, T-junctions, thousands of triangles in one leaf, trees at their
depth limit, and non-finite or odd input. Every answer here is exact: a hit
or a miss, an image equal to another bit for bit, access exactly 0 or 1."""

import math
import warnings

import numpy as np
import pytest

import mbao
from meshes import (
    box,
    disk,
    icosphere,
    merge,
    needle_fan,
    plane,
    quads_to_triangles,
    shrinking_spiral,
    t_junction_box,
    tilted,
)
from exact_oracle import ExactBruteForce
from test_traversal import TRAVERSALS, assert_any_hit_matches_brute_force, assert_matches_brute_force, random_directions

ESTIMATORS = ("branching", "path")


def covered_access(scene, camera, **settings):
    result = mbao.render(scene, camera=camera, width=32, height=32, **settings)
    assert result.mask.sum() > 200, "the camera must see the surface"
    return result.ao[result.mask]


def traced_triangles(scene, origins, targets, **settings):
    """The triangle each ray from origins toward targets hits first (-1: none)."""
    origins = np.asarray(origins, np.float32)
    return mbao.trace(scene, origins, np.asarray(targets, np.float32) - origins, **settings)[1]


# Triangles without area -------------------------------------------------------------------------


def with_degenerate_triangles(rng, vertices, indices):
    """The mesh with triangles of zero area (collinear corners, exact in float32;
    a repeated corner; a single point) inserted between its own, in its box.
    Returns the new mesh, which of its triangles are degenerate, and the points
    the degenerate ones cover."""
    vertices = np.asarray(vertices, np.float32)
    lo, hi = vertices.min(axis=0) + 0.5, vertices.max(axis=0) - 0.5  # the mesh's box stays the same
    n = 60
    starts = np.round((lo + (hi - lo) * rng.random((n, 3))) * 2**10) / 2**10
    steps = 2.0**-4 * rng.integers(-4, 4, (n, 3))  # starts + k steps are exact in float32
    corners = np.stack([starts, starts + steps, starts + 2 * steps], axis=1).astype(np.float32)
    corners[1::3, 2] = corners[1::3, 0]  # a repeated corner
    corners[2::3, :] = corners[2::3, :1]  # a point
    base = len(vertices)
    degenerate = base + np.arange(3 * n).reshape(n, 3)
    order = rng.permutation(len(indices) + n)
    all_indices = np.concatenate([indices, degenerate])[order]
    is_degenerate = order >= len(indices)
    return (np.vstack([vertices, corners.reshape(-1, 3)]), all_indices), is_degenerate, corners.reshape(-1, 3)


def test_triangles_without_area_change_nothing(rng):
    """Zero-area triangles stay out of the tree, no ray hits them, also rays aimed
    at their corners, and the image is the same bit for bit as without them."""
    vertices, indices = merge(icosphere(1.0, (0.0, 1.2, 0.0), 2), plane(3.0, divisions=4))
    (all_vertices, all_indices), is_degenerate, points = with_degenerate_triangles(rng, vertices, indices)
    plain, padded = mbao.Mesh(vertices, indices), mbao.Mesh(all_vertices, all_indices)
    assert padded.build()["degenerate_triangles"] == is_degenerate.sum()
    origins = rng.uniform(-3.0, 3.0, (len(points), 3)) + [0.0, 4.0, 0.0]
    for traversal in TRAVERSALS:
        hit = traced_triangles(padded, origins, points, traversal=traversal)
        assert not np.any(is_degenerate[hit[hit >= 0]]), f"{traversal}: a ray hit a triangle without area"
    camera = mbao.Camera((2.0, 3.0, 4.0), (0.0, 0.8, 0.0), vfov_deg=60.0)
    for estimator in ESTIMATORS:
        settings = dict(camera=camera, width=32, height=32, bounces=2, samples=4, estimator=estimator)
        expected = mbao.render(plain, **settings)
        assert expected.ao[expected.mask].min() < 1.0  # the sphere shades the plane
        np.testing.assert_array_equal(mbao.render(padded, **settings).ao, expected.ao)


def test_only_triangles_without_area_give_an_empty_scene():
    vertices = [[0.0, 0.0, 0.0], [1.0, 1.0, 1.0], [2.0, 2.0, 2.0], [3.0, -1.0, 0.5]]
    scene = mbao.Mesh(vertices, [[0, 1, 2], [3, 3, 0], [1, 1, 1]])
    assert scene.build()["degenerate_triangles"] == 3 and scene.build()["leaf_references"] == 0
    result = mbao.render(scene, camera=mbao.Camera((1.0, 1.0, -5.0), (1.0, 1.0, 1.0)), width=8, height=8)
    assert not result.mask.any() and np.all(result.ao == 1.0)


# Needles and slivers ----------------------------------------------------------------------------


def test_a_sliver_whose_float_normal_is_zero_is_open():
    """Its corners' float cross product is exactly zero, its exact one is not (2^-46):
    rays hit it, and the surface they hit has a normal and sees the open sky
    (a normal from the float cross product was NaN and the access 0)."""
    a, b = 1.0 + 2.0**-23, 1.0 + 2.0**-22
    corners = np.array([[0.0, 0.0, 0.0], [a, b, 0.0], [1.0, a, 0.0]], np.float32)
    edges = (corners[1:] - corners[0]).astype(np.float32)
    assert not np.cross(edges[0], edges[1]).any() and np.cross(*edges.astype(np.float64)).any()
    scene = mbao.Mesh(corners, [[0, 1, 2]])
    for target in corners.astype(float):
        camera = mbao.Camera(target + [0.0, 0.0, 1.0], target, vfov_deg=10.0)
        for estimator in ESTIMATORS:
            result = mbao.render(scene, camera=camera, width=1, height=1, bounces=2, samples=16, estimator=estimator)
            assert result.mask[0, 0] and result.ao[0, 0] == 1.0, f"{estimator} at {target}: {result.ao[0, 0]}"


@pytest.mark.parametrize("normals", ["shading", "geometric"])
def test_needles_with_aspect_ratio_a_million_are_flat_and_open(normals):
    """A plane made of 1000 needles 1000 long and 1/1000 wide, tilted against every
    axis, with exact vertex normals: every covered pixel sees the open sky. A
    geometric normal from a float cross product is up to 3 degrees off on these
    needles, and the shading lobe then dipped below it (0.02% of the rays)."""
    vertices, indices, n = needle_fan(1000, 1000.0)
    scene = mbao.Mesh(vertices, indices, np.tile(n, (len(vertices), 1)))
    camera = mbao.Camera(1.5 * n, (0.0, 0.0, 0.0), up=np.cross(n, [1.0, 0.0, 0.0]), vfov_deg=30.0)
    access = covered_access(scene, camera, samples=64, normals=normals)
    np.testing.assert_array_equal(access, 1.0)


def test_rays_aimed_at_needles_match_brute_force(rng, device):
    vertices, indices, n = needle_fan(400, 2500.0)  # aspect ratio 10^6
    scene, oracle = mbao.Mesh(vertices, indices), ExactBruteForce(vertices, indices, device)
    count = 3000
    # Aimed at the base, where the needles are 1/400 wide, and at their long edges.
    k = rng.integers(0, 400, count)
    targets = vertices[1 + k] + rng.random((count, 1)) * (vertices[0] - vertices[1 + k]) * 1e-3
    origins = targets + rng.normal(size=(count, 3)) + 2.0 * n * rng.choice([-1.0, 1.0], (count, 1))
    hits = assert_matches_brute_force(scene, oracle, origins, targets - origins)
    assert hits.mean() > 0.9
    assert_any_hit_matches_brute_force(scene, oracle, origins, targets - origins)


# Duplicated and coplanar overlapping triangles -----------------------------------------------


def test_coplanar_copies_of_a_tilted_plane_see_no_acne():
    """The same tilted square three times: once as two triangles, once again
    (duplicates), once as a 7 x 7 grid whose vertices round differently to
    float32. A ray leaving one copy must not hit another: access exactly 1."""
    normal = (1.0, 2.0, 3.0)
    scene = mbao.Mesh(
        *merge(tilted(plane(2.0), normal), tilted(plane(2.0), normal), tilted(plane(2.0, divisions=7), normal))
    )
    n = np.asarray(normal) / np.linalg.norm(normal)
    camera = mbao.Camera(2.0 * n + [0.3, 0.1, 0.0], (0.0, 0.0, 0.0), vfov_deg=60.0)
    for estimator in ESTIMATORS:
        np.testing.assert_array_equal(covered_access(scene, camera, bounces=2, samples=8, estimator=estimator), 1.0)


@pytest.mark.filterwarnings("ignore:.*looks closed")  # closed on purpose, with an unlimited radius
def test_a_closed_box_with_duplicated_faces_and_a_light_in_its_ceiling_is_closed():
    """Every face twice and, like the Cornell light, a quad lying in the ceiling:
    exactly 0 everywhere inside; of two copies rays hit the first (an exact tie)."""
    vertices, indices = box((-1.0, -1.5, -2.0), (1.0, 1.5, 2.0))
    light = (
        [[-0.3, 1.5, -0.4], [0.3, 1.5, -0.4], [0.3, 1.5, 0.4], [-0.3, 1.5, 0.4]],
        quads_to_triangles([[0, 1, 2, 3]]),
    )
    scene = mbao.Mesh(*merge((vertices, indices), (vertices, indices), light))
    camera = mbao.Camera((0.2, -0.3, 0.1), (0.1, 1.5, 0.2), vfov_deg=100.0)
    for estimator in ESTIMATORS:
        result = mbao.render(scene, camera=camera, width=20, height=20, bounces=2, samples=4, estimator=estimator)
        assert result.mask.all()
        np.testing.assert_array_equal(result.ao, 0.0)
    _, triangle, _ = mbao.trace(scene, np.zeros((200, 3)), random_directions(np.random.default_rng(1), 200))
    assert np.all((triangle >= 0) & ((triangle < 12) | (triangle >= 24))), "ties go to the lower triangle id"


def test_duplicated_triangles_match_brute_force(rng, device):
    sphere = icosphere(1.0, (0.0, 0.0, 0.0), 2)
    vertices, indices = merge(sphere, sphere, tilted(plane(1.5, divisions=3), (0.2, 1.0, 0.1)))
    scene, oracle = mbao.Mesh(vertices, indices), ExactBruteForce(vertices, indices, device)
    count = 3000
    origins = rng.uniform(-2.0, 2.0, (count, 3))
    assert assert_matches_brute_force(scene, oracle, origins, random_directions(rng, count)).mean() > 0.15


# T-junctions -----------------------------------------------------------------------------------


@pytest.mark.parametrize("traversal", TRAVERSALS)
def test_no_ray_slips_through_a_t_junction(rng, traversal):
    """Rays aimed exactly at the T-vertices and at points of the long edges they
    lie on, from inside the closed box, all hit (with edge functions in float
    alone, 1-2% of those at a T-vertex and 7% of those at the edge escaped)."""
    vertices, indices, t_vertices, long_edges = t_junction_box()
    scene = mbao.Mesh(vertices, indices)
    count = 4000
    center = vertices[:8].mean(axis=0)
    origins = center + rng.uniform(-1.0, 1.0, (count, 3))
    (a0, b0), (a1, b1) = long_edges
    s = rng.random((count, 1))
    for targets in (
        vertices[rng.choice(t_vertices, count)],
        np.where(
            rng.random((count, 1)) < 0.5,
            vertices[a0] + s * (vertices[b0] - vertices[a0]),
            vertices[a1] + s * (vertices[b1] - vertices[a1]),
        ),
    ):
        for any_hit in (False, True):
            triangle = traced_triangles(scene, origins, targets, traversal=traversal, any_hit=any_hit)
            assert np.all(triangle >= 0), f"{np.sum(triangle < 0)} rays escaped"


@pytest.mark.filterwarnings("ignore:.*looks closed")  # closed on purpose, with an unlimited radius
def test_a_box_with_t_junctions_is_closed_everywhere():
    vertices, indices, _, _ = t_junction_box()
    scene = mbao.Mesh(vertices, indices)
    center = vertices[:8].mean(axis=0)
    camera = mbao.Camera(center, vertices[8], vfov_deg=90.0)  # looking at a T-vertex
    for estimator in ESTIMATORS:
        result = mbao.render(scene, camera=camera, width=16, height=16, bounces=2, samples=8, estimator=estimator)
        assert result.mask.all()
        np.testing.assert_array_equal(result.ao, 0.0)


def test_t_vertices_rounded_off_their_edge_leave_a_real_crack(rng):
    """The rule where a T-vertex does not lie on its long edge in float32 (here the
    box is turned, and the vertices rounded): the mesh has a crack, a sliver
    (long-edge end, T-vertex, other end) as wide as the rounding, and every ray
    that escapes passes through it."""
    vertices, indices, t_vertices, long_edges = t_junction_box()
    turn, _ = np.linalg.qr(np.random.default_rng(8).normal(size=(3, 3)))
    vertices = (vertices @ turn.T).astype(np.float32)
    scene = mbao.Mesh(vertices, indices)
    cracks = mbao.Mesh(vertices, [[a, t, b] for t, (a, b) in zip(t_vertices, long_edges)])
    count = 8000
    origins = (vertices[:8].mean(axis=0) + rng.uniform(-1.0, 1.0, (count, 3))).astype(np.float32)
    targets = vertices[rng.choice(t_vertices, count)]
    escaped = traced_triangles(scene, origins, targets) < 0
    assert escaped.any()  # there is a crack to find
    through_crack = traced_triangles(cracks, origins, targets) >= 0
    np.testing.assert_array_equal(escaped, escaped & through_crack)


# Many triangles in one leaf, deep trees ------------------------------------------------------------


def test_thousands_of_overlapping_triangles_match_brute_force(rng, device):
    """3000 copies of one triangle (no split can separate them) and 1500 random
    triangles overlapping in one plane (splits free a few of them at a time; the
    builder's reference budget keeps the tree small)."""
    copies = (np.array([[0.1, 0.2, 0.3], [0.9, 0.3, 0.5], [0.4, 0.8, 0.2]]), np.zeros((3000, 3), int) + [0, 1, 2])
    flat = np.concatenate([rng.random((1500, 3, 2)), np.full((1500, 3, 1), 0.5)], axis=2).reshape(-1, 3)
    vertices, indices = merge(copies, (flat, np.arange(4500).reshape(-1, 3)))
    scene, oracle = mbao.Mesh(vertices, indices), ExactBruteForce(vertices, indices, device)
    assert scene.build()["leaf_references"] <= 32 * len(indices)  # the builder's reference budget
    tree = scene.kd_tree()
    nodes = tree["nodes"][tree["node_rows"]]
    assert (nodes[(nodes[:, 0] & 3) == 3, 0] >> 2).max() >= 3000  # a leaf holds all copies
    count = 2000
    origins = rng.uniform(-0.5, 1.5, (count, 3))
    targets = rng.uniform(0.0, 1.0, (count, 3)) * [1.0, 1.0, 0.0] + [0.0, 0.0, 0.5]
    assert assert_matches_brute_force(scene, oracle, origins, targets - origins).mean() > 0.5
    assert_any_hit_matches_brute_force(scene, oracle, origins, targets - origins)


def test_a_tree_at_its_depth_limit_traces_exactly(rng, device):
    """A shrinking spiral makes the builder cut until its depth limit (8 + 1.3
    log2 N levels); every traversal still finds what brute force finds."""
    vertices, indices = shrinking_spiral(rng, 300)
    scene, oracle = mbao.Mesh(vertices, indices), ExactBruteForce(vertices, indices, device)
    assert scene.build()["max_depth"] == round(8 + 1.3 * math.log2(300))
    count = 3000
    targets = vertices[indices[rng.integers(0, 300, count)]].mean(axis=1)
    origins = targets + rng.normal(size=(count, 3)) * np.linalg.norm(targets, axis=1, keepdims=True)
    assert assert_matches_brute_force(scene, oracle, origins, targets - origins).mean() > 0.9
    assert_any_hit_matches_brute_force(scene, oracle, origins, targets - origins)


# Non-finite and odd input ----------------------------------------------------------------------------


QUAD = (np.array([[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [1.0, 1.0, 0.0]]), [[0, 1, 2], [1, 3, 2]])


@pytest.mark.parametrize("value", [math.nan, math.inf, -math.inf], ids=["nan", "inf", "-inf"])
def test_non_finite_vertices_and_normals_are_rejected_naming_the_index(value):
    """The rule: every vertex position and normal must be finite, used by a
    triangle or not; otherwise ValueError naming the mesh and the index."""
    vertices, indices = QUAD
    bad = vertices.copy()
    bad[3, 1] = value
    with pytest.raises(ValueError, match=r"^mesh: vertex 3 is not finite"):
        mbao.Mesh(bad, indices)
    normals = np.tile([0.0, 0.0, 1.0], (4, 1))
    normals[2, 0] = value
    with pytest.raises(ValueError, match=r"^mesh: normal 2 is not finite"):
        mbao.Mesh(vertices, indices, normals)
    unused = np.vstack([vertices, [value, 0.0, 0.0]])
    with pytest.raises(ValueError, match=r"^mesh: vertex 4 is not finite"):
        mbao.Mesh(unused, indices)


def test_values_beyond_float32_are_rejected_naming_the_row():
    """1e39 is finite in float64 but not in the float32 that mbao keeps: said as such, without numpy's overflow warning."""
    vertices, indices = QUAD
    bad = vertices.copy()
    bad[3, 1] = 1e39
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        with pytest.raises(ValueError, match=r"^vertices: row 3 holds .*1e\+39.*beyond the range of float32"):
            mbao.Mesh(bad, indices)
        normals = np.tile([0.0, 0.0, 1.0], (4, 1))
        normals[2, 0] = -1e39
        with pytest.raises(ValueError, match=r"^normals: row 2 holds .*beyond the range of float32"):
            mbao.Mesh(vertices, indices, normals)


def leaning_normals_scene(scale):
    """A plane under a small disk, whose vertex normals all lean 50 degrees, times `scale`."""
    vertices, indices = merge(plane(20.0), disk(0.5, 1.0, 32))
    alpha = math.radians(50.0)
    normals = np.tile([math.sin(alpha), math.cos(alpha), 0.0], (len(vertices), 1)) * scale
    return mbao.Mesh(vertices, indices, normals)


def test_normals_count_by_direction_whatever_their_length():
    """Normals 2^-100 or 2^100 long (their squared length under- or overflows
    float) give the same image as unit normals, bit for bit; they were taken for
    zero or infinite and replaced by the geometric normal."""
    camera = mbao.Camera((0.3, 1.0, 1.2), (0.0, 0.0, 0.0), vfov_deg=20.0)
    settings = dict(camera=camera, width=8, height=8, samples=64)
    unit = mbao.render(leaning_normals_scene(1.0), **settings).ao
    geometric = mbao.render(leaning_normals_scene(1.0), normals="geometric", **settings).ao
    assert np.abs(unit - geometric).mean() > 0.01  # the lean shows
    for scale in (2.0**-100, 2.0**100):
        np.testing.assert_array_equal(
            mbao.render(leaning_normals_scene(scale), **settings).ao, unit, err_msg=f"{scale}"
        )


def test_zero_normals_mean_geometric_normals():
    """Zero vertex normals mean "no normal here": the geometric normal is used."""
    mesh = merge(icosphere(1.0, (0.0, 1.0, 0.0), 2), plane(3.0, divisions=2))
    camera = mbao.Camera((2.0, 3.0, 4.0), (0.0, 0.8, 0.0), vfov_deg=60.0)
    settings = dict(camera=camera, width=16, height=16, bounces=2, samples=8)
    without = mbao.render(mbao.Mesh(*mesh), **settings).ao
    zero = mbao.render(mbao.Mesh(*mesh, np.zeros((len(mesh[0]), 3))), **settings).ao
    np.testing.assert_array_equal(zero, without)
