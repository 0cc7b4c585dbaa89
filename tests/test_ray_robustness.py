"""Rays at the edge of what float can tell apart: axis-parallel directions
with +0 and -0 components, grazing directions, origins on split planes, on
edges and on vertices, each against brute force in double precision with all
four traversals; closed meshes seen from inside that must stay closed, and
open surfaces that must see no acne, at several scales. The answers are
exact: the oracle's hits, access exactly 0 or exactly 1."""

import numpy as np
import pytest

import mbao
from exact_oracle import ExactBruteForce
from meshes import box, box_grid, frame, icosphere, merge, plane, tilted
from test_traversal import (
    TRAVERSALS,
    assert_any_hit_matches_brute_force,
    assert_matches_brute_force,
    distance_tolerance,
    points_in,
    points_on_split_planes,
    random_directions,
)

ESTIMATORS = ("branching", "path")


def through_origin(scene, triangles, origins, tolerance):
    """Whether each triangle passes within `tolerance` of its ray's origin."""
    corners = np.asarray(scene.vertices, float)[np.asarray(scene.indices)[triangles]]
    e1, e2, p = corners[:, 1] - corners[:, 0], corners[:, 2] - corners[:, 0], origins - corners[:, 0]
    normal = np.cross(e1, e2)
    normal /= np.linalg.norm(normal, axis=1, keepdims=True)
    # Barycentrics of the origin's projection on the triangle's plane.
    d11, d12, d22 = (e1 * e1).sum(1), (e1 * e2).sum(1), (e2 * e2).sum(1)
    p1, p2 = (p * e1).sum(1), (p * e2).sum(1)
    det = d11 * d22 - d12 * d12
    b1, b2 = (d22 * p1 - d12 * p2) / det, (d11 * p2 - d12 * p1) / det
    inside = (b1 >= -1e-6) & (b2 >= -1e-6) & (b1 + b2 <= 1 + 1e-6)
    return inside & (np.abs((p * normal).sum(1)) <= tolerance)


def assert_matches_exact_oracle(scene, oracle, origins, directions, slack=1.0):
    """Closest hits agree with brute force in double, for every traversal, and the
    traversals with each other bit for bit. Distances agree to `slack` times the
    rounding of the coordinates (grazing rays: 1 / the angle). The one rule
    beyond that: a ray that starts on a triangle, within rounding, may report it
    at a distance within rounding of 0 or not (the renderer's rays start off
    surfaces): where the two differ, the nearer answer is such a hit."""
    origins = np.asarray(origins, np.float32)
    directions = np.asarray(directions, np.float32)
    expected_t, expected_triangle = oracle.closest(origins, directions)
    results = {name: mbao.trace(scene, origins, directions, traversal=name) for name in TRAVERSALS}
    for name, (t, triangle, _) in results.items():
        both = (triangle >= 0) & (expected_triangle >= 0)
        nearest = np.fmin(t, expected_t)
        tolerance = slack * distance_tolerance(scene, origins, directions, np.where(np.isfinite(nearest), nearest, 0.0))
        # A different triangle is right at a tie: the ray hits it at the same distance.
        tied = oracle.distance_to(origins, directions, np.where(triangle == expected_triangle, -1, triangle))
        with np.errstate(invalid="ignore"):  # inf - inf where both miss
            same = (triangle == expected_triangle) | (both & (np.abs(tied - expected_t) <= tolerance))
            agree = same & (~both | (np.abs(t - expected_t) <= tolerance))
        nearer = np.where(t <= expected_t, triangle, expected_triangle)
        at_origin = np.zeros(len(agree), bool)
        at_origin[~agree] = (nearest[~agree] <= tolerance[~agree]) & through_origin(
            scene, nearer[~agree], origins[~agree].astype(float), tolerance[~agree]
        )
        assert np.all(agree | at_origin), f"{name}: {np.sum(~(agree | at_origin))} rays differ from brute force"
    for name in TRAVERSALS[1:]:
        for a, b in zip(results[TRAVERSALS[0]], results[name]):
            np.testing.assert_array_equal(a, b, err_msg=f"{TRAVERSALS[0]} and {name} return different hits")
    return expected_triangle >= 0


def grid_and_sphere():
    return merge(box_grid(3), icosphere(0.8, (1.3, 1.3, 1.3), 2))


@pytest.fixture(scope="module")
def scene_and_oracle(device):
    vertices, indices = grid_and_sphere()
    return mbao.Mesh(vertices, indices), ExactBruteForce(vertices, indices, device)


def signed_axis_directions(rng, n):
    """±x, ±y, ±z whose zero components are +0 or -0 at random: 1 / d is then
    +inf or -inf, and (split - o) / d NaN where the origin lies on the split."""
    d = np.zeros((n, 3), np.float32)
    d[np.arange(n), rng.integers(0, 3, n)] = rng.choice([-1.0, 1.0], n)
    negative_zero = (d == 0) & (rng.random((n, 3)) < 0.5)
    d[negative_zero] = -0.0
    assert np.signbit(d[d == 0]).any() and not np.signbit(d[d == 0]).all()
    return d


def test_axis_parallel_rays_with_signed_zeros(scene_and_oracle, rng):
    scene, oracle = scene_and_oracle
    n = 4000
    for origins in (points_in(rng, scene, n), points_on_split_planes(rng, scene, n)[0]):
        directions = signed_axis_directions(rng, n)
        assert assert_matches_brute_force(scene, oracle, origins, directions).mean() > 0.2
        assert_any_hit_matches_brute_force(scene, oracle, origins, directions)


def test_rays_in_split_planes_with_signed_zeros(scene_and_oracle, rng):
    """Rays lying in a split plane, their component across it +0 or -0."""
    scene, oracle = scene_and_oracle
    n = 4000
    origins, axes = points_on_split_planes(rng, scene, n)
    directions = random_directions(rng, n).astype(np.float32)
    directions[np.arange(n), axes] = np.where(rng.random(n) < 0.5, 0.0, -0.0)
    assert assert_matches_brute_force(scene, oracle, origins, directions).mean() > 0.2
    assert_any_hit_matches_brute_force(scene, oracle, origins, directions)


def test_rays_from_vertices_and_edges(scene_and_oracle, rng):
    """Origins exactly on vertices, and on the axis-parallel edges of the boxes
    (two coordinates of the edge's, any third between its ends): the triangles
    through the origin are at t = 0, not hit; everything else is."""
    scene, oracle = scene_and_oracle
    vertices = np.asarray(scene.vertices)
    n = 4000
    corners = vertices[rng.integers(0, len(vertices), n)]
    grid = vertices[: 8 * 27]  # the boxes' corners (box_grid(3) comes first)
    edge_start = grid[rng.integers(0, len(grid), n)]
    along = rng.integers(0, 3, n)
    edge_points = edge_start.copy()
    edge_points[np.arange(n), along] += (
        np.where(edge_start[np.arange(n), along] % 1.0 == 0.0, 1.0, -1.0) * 0.6 * rng.random(n).astype(np.float32)
    )
    for origins in (corners, edge_points):
        for directions in (random_directions(rng, n), signed_axis_directions(rng, n)):
            assert assert_matches_exact_oracle(scene, oracle, origins, directions).mean() > 0.2


@pytest.mark.parametrize("normal", [(0.0, 1.0, 0.0), (1.0, 2.0, 3.0)], ids=["axis-plane", "tilted-plane"])
def test_grazing_rays(rng, device, normal):
    """Rays that meet a tessellated plane at angles down to 10^-8 radians, from
    origins that far above or below it, so that they hit within it (rays lying
    in a plane, within its rounding, hit or miss it at random: not asked here)."""
    vertices, indices = tilted(plane(2.0, divisions=9), normal)
    scene, oracle = mbao.Mesh(vertices, indices), ExactBruteForce(vertices, indices, device)
    u, w, n_hat = frame(normal)
    n = 3000
    for angle in (1e-2, 1e-4, 1e-6, 1e-8):
        side = rng.choice([-1.0, 1.0], (n, 1))
        origins = rng.uniform(-1.5, 1.5, (n, 1)) * u + rng.uniform(-1.5, 1.5, (n, 1)) * w
        origins = origins + side * angle * rng.uniform(0.1, 1.5, (n, 1)) * n_hat
        phi = rng.uniform(0.0, 2.0 * np.pi, (n, 1))
        directions = np.cos(phi) * u + np.sin(phi) * w - side * angle * n_hat
        hits = assert_matches_exact_oracle(scene, oracle, origins, directions, slack=1.0 / angle)
        assert hits.mean() > 0.5, f"angle {angle}: the rays must meet the plane"


# Closed meshes from inside: exactly 0 -----------------------------------------------------------


CLOSED = {
    "box": (box((-1.0, -1.5, -2.0), (1.0, 1.5, 2.0)), (0.2, -0.3, 0.1), (0.5, 0.4, 1.0)),
    "sphere": (icosphere(1.3, (0.2, 0.1, -0.3), 3), (0.5, 0.0, 0.0), (1.0, 0.6, -0.9)),
}


@pytest.mark.filterwarnings("ignore:.*looks closed")  # closed on purpose, with an unlimited radius
@pytest.mark.parametrize("traversal", TRAVERSALS)
@pytest.mark.parametrize("name", CLOSED)
def test_closed_meshes_do_not_leak(name, traversal):
    """From inside a closed mesh every ray of every bounce hits: access exactly 0,
    for b = 1, 2, 3, both estimators, every traversal (lanes run the branching
    estimator only)."""
    mesh, eye, target = CLOSED[name]
    scene = mbao.Mesh(*mesh)
    camera = mbao.Camera(eye, target, vfov_deg=100.0)
    for estimator in ("branching",) if traversal == "lanes" else ESTIMATORS:
        for bounces in (1, 2, 3):
            result = mbao.render(
                scene,
                camera=camera,
                width=16,
                height=16,
                bounces=bounces,
                samples=4,
                estimator=estimator,
                engine=mbao.Engine(traversal=traversal),
            )
            assert result.mask.all()
            np.testing.assert_array_equal(result.ao, 0.0, err_msg=f"{estimator}, b = {bounces}")


@pytest.mark.filterwarnings("ignore:.*looks closed")  # closed on purpose, with an unlimited radius
def test_a_thin_closed_slab_does_not_leak():
    """A closed box 2 x 2 and 10^-4 thick (its coordinates about 1): rays leave a
    surface 2^-15 of its largest coordinate off it (surface.h), 0.3 of this slab's
    thickness, and still start inside it. (At 3 10^-5 thick they start outside:
    that thickness is the limit.)"""
    thickness = 1e-4
    scene = mbao.Mesh(*box((-1.0, 0.3 - thickness / 2, -1.0), (1.0, 0.3 + thickness / 2, 1.0)))
    camera = mbao.Camera((0.05, 0.3, 0.02), (0.5, 0.3 - thickness / 4, 0.3), vfov_deg=60.0)
    result = mbao.render(scene, camera=camera, width=16, height=16, bounces=2, samples=8)
    assert result.mask.all()
    np.testing.assert_array_equal(result.ao, 0.0)


# Open surfaces alone: exactly 1 -----------------------------------------------------------------


@pytest.mark.parametrize("scale", [1e-3, 1.0, 1e3])
def test_no_acne_on_flat_surfaces(scale):
    """A large plane alone, axis-parallel and tilted (its float32 vertices then lie
    off the plane by rounding), coarse and finely tessellated: every ray leaving
    it escapes, access exactly 1."""
    for normal in ((0.0, 1.0, 0.0), (1.0, 2.0, 3.0)):
        n = np.asarray(normal) / np.linalg.norm(normal)
        for divisions in (1, 16):
            vertices, indices = tilted(plane(50.0 * scale, divisions=divisions), normal)
            scene = mbao.Mesh(vertices, indices)
            camera = mbao.Camera(scale * (2.0 * n + [0.4, 0.2, 0.1]), (0.0, 0.0, 0.0), vfov_deg=70.0)
            for estimator in ESTIMATORS:
                result = mbao.render(
                    scene, camera=camera, width=32, height=32, bounces=2, samples=8, estimator=estimator
                )
                assert result.mask.all()
                np.testing.assert_array_equal(
                    result.ao, 1.0, err_msg=f"normal {normal}, {divisions} divisions, {estimator}"
                )


@pytest.mark.parametrize("scale", [1e-3, 1.0, 1e3])
def test_no_acne_on_a_convex_sphere(scale):
    """Outside a convex tessellated sphere (an icosphere: no coplanar neighbours,
    so still convex in float32), every ray leaving it escapes: access exactly 1,
    uniform, at 20 to 5120 triangles."""
    center = scale * np.array([0.3, -0.2, 0.1])
    for subdivisions in (0, 2, 4):
        scene = mbao.Mesh(*icosphere(scale, center, subdivisions))
        camera = mbao.Camera(center + scale * np.array([0.0, 1.0, 3.0]), center, vfov_deg=45.0)
        for estimator in ESTIMATORS:
            for bounces in (1, 3):
                result = mbao.render(
                    scene, camera=camera, width=32, height=32, bounces=bounces, samples=8, estimator=estimator
                )
                assert result.mask.sum() > 200
                np.testing.assert_array_equal(
                    result.ao[result.mask], 1.0, err_msg=f"{subdivisions}, {estimator}, b = {bounces}"
                )


@pytest.mark.parametrize("scale", [1e-15, 1e15])
def test_the_triangle_test_works_from_ten_to_the_minus_15_to_ten_to_the_15(scale, rng):
    """Distances are computed from barycentrics, not from the cube of the corners'
    distances that Woop et al. form, which under- or overflows float beyond about
    10^-13 and 10^12 (a sphere there was fully occluded, or missed, and a closed
    box leaked): rays at a sphere of radius `scale` hit it where geometry says."""
    vertices, indices = icosphere(scale, (0.0, 0.0, 0.0), 3)
    scene = mbao.Mesh(vertices, indices)
    n = 2000
    directions = random_directions(rng, n)
    t, triangle, _ = mbao.trace(scene, -3.0 * scale * directions, directions)
    assert np.all(triangle >= 0)
    # The tessellation lies between the circumscribed sphere and, at 1280
    # triangles, one 0.4% smaller.
    np.testing.assert_array_less(2.0 * scale * (1 - 1e-6), t)
    np.testing.assert_array_less(t, 2.0 * scale * 1.004)
    _, inside, _ = mbao.trace(scene, np.zeros((n, 3)), directions)
    assert np.all(inside >= 0)


def test_what_is_not_a_ray_misses():
    """The rule for rays that are not rays: a zero, NaN or infinite direction, or
    a NaN or infinite origin, misses everything, in every traversal (and returns)."""
    scene = mbao.Mesh(*box((-1.0, -1.0, -1.0), (1.0, 1.0, 1.0)))
    nan, inf = np.nan, np.inf
    origins = [[0, 0, 0], [0, 0, 0], [0, 0, 0], [nan, 0, 0], [inf, 0, 0], [0, -inf, 0]]
    directions = [[0, 0, 0], [nan, 1, 0], [inf, 0, 0], [1, 0, 0], [1, 0, 0], [0, 1, 0]]
    for traversal in TRAVERSALS:
        for any_hit in (False, True):
            t, triangle, _ = mbao.trace(scene, origins, directions, traversal=traversal, any_hit=any_hit)
            assert np.all(triangle == -1) and np.all(np.isinf(t))
