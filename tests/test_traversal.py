"""The kd-tree traversals against brute force: same closest hits, same
any-hit answers, on random and structured meshes, for random rays, rays that
start on split planes and rays parallel to the axes; and the same hits as
each other, bit for bit."""

import numpy as np
import pytest

import mbao
from meshes import box, box_grid, merge, plane, random_soup, sphere
from oracle import BruteForce

TRAVERSALS = ("pushdown", "restart", "short-stack", "stack", "lanes")


def split_planes(scene):
    """(axis, position) of every interior node of the scene's kd-tree."""
    tree = scene.kd_tree()
    nodes = tree["nodes"][tree["node_rows"]]
    interior = (nodes[:, 0] & 3) != 3
    return (nodes[interior, 0] & 3).astype(int), nodes[interior, 1].view(np.float32)


def random_directions(rng, n):
    d = rng.normal(size=(n, 3))
    return d / np.linalg.norm(d, axis=1, keepdims=True)


def axis_directions(rng, n):
    """±x, ±y, ±z: components exactly zero, the traversal's division by zero."""
    d = np.zeros((n, 3))
    d[np.arange(n), rng.integers(0, 3, n)] = rng.choice([-1.0, 1.0], n)
    return d


def points_in(rng, scene, n, margin=0.1):
    lo, hi = map(np.asarray, scene.bounds)
    extent = hi - lo
    return lo - margin * extent + (1 + 2 * margin) * extent * rng.random((n, 3))


def points_on_split_planes(rng, scene, n):
    axis, position = split_planes(scene)
    pick = rng.integers(0, len(axis), n)
    points = points_in(rng, scene, n, margin=0.0)
    points[np.arange(n), axis[pick]] = position[pick]
    return points, axis[pick]


def distance_tolerance(scene, origins, directions, t):
    """How far two correct float32 computations of a hit distance can differ: a
    few steps of the coordinates' magnitude, along the ray."""
    magnitude = np.abs(np.asarray(scene.bounds)).max() + np.abs(origins).max(axis=1)
    return 2.0**-18 * (magnitude / np.linalg.norm(directions, axis=1) + t)


def assert_matches_brute_force(scene, oracle, origins, directions, t_max=np.inf):
    """Closest hits agree with brute force, for every traversal, and the
    traversals agree with each other bit for bit."""
    origins = np.asarray(origins, np.float32)
    directions = np.asarray(directions, np.float32)
    expected_t, expected_triangle = oracle.closest(origins, directions, t_max)
    results = {name: mbao.trace(scene, origins, directions, t_max=t_max, traversal=name) for name in TRAVERSALS}
    for name, (t, triangle, barycentrics) in results.items():
        missed = expected_triangle < 0
        np.testing.assert_array_equal(triangle < 0, missed, err_msg=f"{name}: hit/miss differs from brute force")
        same = triangle == expected_triangle
        # A different triangle is right only at a tie: the ray hits it at the same distance.
        tied = oracle.distance_to(origins, directions, np.where(same, -1, triangle), t_max)
        hit = ~missed
        tolerance = distance_tolerance(scene, origins[hit], directions[hit], expected_t[hit])
        assert np.all(same[hit] | (np.abs(tied[hit] - expected_t[hit]) <= tolerance)), f"{name}: wrong triangle"
        assert np.all(np.abs(t[hit] - expected_t[hit]) <= tolerance), f"{name}: wrong distance"
        assert np.all(np.isinf(t[missed]))
        assert np.all(barycentrics[hit] >= 0) and np.all(barycentrics[hit].sum(axis=1) <= 1 + 1e-6)
    for name in TRAVERSALS[1:]:
        for a, b in zip(results[TRAVERSALS[0]], results[name]):
            np.testing.assert_array_equal(a, b, err_msg=f"{TRAVERSALS[0]} and {name} return different hits")
    return expected_triangle >= 0


def assert_any_hit_matches_brute_force(scene, oracle, origins, directions, t_max=np.inf):
    """Any-hit answers whether brute force finds a hit, and what it returns is a real hit."""
    origins = np.asarray(origins, np.float32)
    directions = np.asarray(directions, np.float32)
    t_max = np.broadcast_to(np.asarray(t_max, np.float32), len(origins))
    _, expected_triangle = oracle.closest(origins, directions, t_max)
    for name in TRAVERSALS:
        t, triangle, _ = mbao.trace(scene, origins, directions, t_max=t_max, any_hit=True, traversal=name)
        np.testing.assert_array_equal(triangle >= 0, expected_triangle >= 0, err_msg=f"{name}: any-hit differs")
        hit = triangle >= 0
        real = oracle.distance_to(origins[hit], directions[hit], triangle[hit], t_max[hit])
        tolerance = distance_tolerance(scene, origins[hit], directions[hit], t[hit])
        assert np.all(np.abs(real - t[hit]) <= tolerance), f"{name}: any-hit returned a non-hit"


def random_soup_scene(rng):
    return random_soup(rng, 3000)


def box_grid_scene(rng):
    return box_grid(4)


def cornell_scene(rng):
    scene = mbao.cornell_box()
    return scene.vertices, scene.indices


def sphere_and_plane_scene(rng):
    v, i, _ = sphere(1.0, (0.0, 1.0, 0.0))
    return merge((v, i), plane(3.0, y=0.0, divisions=7))


MESHES = [random_soup_scene, box_grid_scene, cornell_scene, sphere_and_plane_scene]


@pytest.fixture(params=MESHES, ids=lambda f: f.__name__)
def scene_and_oracle(request, rng, device):
    vertices, indices = request.param(rng)
    return mbao.Mesh(vertices, indices), BruteForce(vertices, indices, device)


def test_random_rays(scene_and_oracle, rng):
    scene, oracle = scene_and_oracle
    n = 4000
    hits = assert_matches_brute_force(scene, oracle, points_in(rng, scene, n), random_directions(rng, n))
    assert 0.2 < hits.mean()  # the rays do meet the geometry


def test_axis_parallel_rays(scene_and_oracle, rng):
    scene, oracle = scene_and_oracle
    n = 4000
    assert_matches_brute_force(scene, oracle, points_in(rng, scene, n), axis_directions(rng, n))


def test_rays_starting_on_split_planes(scene_and_oracle, rng):
    scene, oracle = scene_and_oracle
    n = 4000
    origins, axes = points_on_split_planes(rng, scene, n)
    assert_matches_brute_force(scene, oracle, origins, random_directions(rng, n))
    # Parallel to an axis, and in particular lying in the split plane itself.
    directions = axis_directions(rng, n)
    assert_matches_brute_force(scene, oracle, origins, directions)
    in_plane = np.zeros((n, 3))
    in_plane[np.arange(n), (axes + 1 + rng.integers(0, 2, n)) % 3] = rng.choice([-1.0, 1.0], n)
    assert_matches_brute_force(scene, oracle, origins, in_plane)


def test_rays_ending_before_the_geometry(scene_and_oracle, rng):
    scene, oracle = scene_and_oracle
    n = 4000
    lo, hi = map(np.asarray, scene.bounds)
    t_max = rng.random(n) * np.linalg.norm(hi - lo) * 0.5
    assert_matches_brute_force(scene, oracle, points_in(rng, scene, n), random_directions(rng, n), t_max)


def test_any_hit(scene_and_oracle, rng):
    scene, oracle = scene_and_oracle
    n = 4000
    origins, _ = points_on_split_planes(rng, scene, n)
    assert_any_hit_matches_brute_force(scene, oracle, origins, random_directions(rng, n))
    lo, hi = map(np.asarray, scene.bounds)
    t_max = rng.random(n) * np.linalg.norm(hi - lo) * 0.5
    assert_any_hit_matches_brute_force(scene, oracle, points_in(rng, scene, n), axis_directions(rng, n), t_max)


@pytest.mark.parametrize("traversal", TRAVERSALS)
def test_no_ray_leaves_a_closed_box(rng, traversal):
    """From inside a closed box every ray hits, also those aimed exactly at its
    edges and corners, where two or three triangles meet."""
    scene = mbao.Mesh(*box((-1.0, -2.0, -3.0), (4.0, 5.0, 6.0)))
    n = 5000
    origins = rng.uniform((-0.9, -1.9, -2.9), (3.9, 4.9, 5.9), (n, 3))
    corners = np.asarray(scene.vertices)[rng.integers(0, 8, n)]
    # Corners, and midpoints of two corners: edge midpoints and face centres among them.
    targets = np.concatenate([corners, 0.5 * (corners + np.asarray(scene.vertices)[rng.integers(0, 8, n)])])
    starts = np.concatenate([origins, origins])
    for any_hit in (False, True):
        for directions in (random_directions(rng, 2 * n), targets - starts):
            _, triangle, _ = mbao.trace(scene, starts, directions, any_hit=any_hit, traversal=traversal)
            assert np.all(triangle >= 0), f"{np.sum(triangle < 0)} rays escaped the closed box"


def test_what_the_traversals_count(rng):
    """Counting builds report, per ray, the nodes and leaves visited, the
    triangles tested and the restarts: the same leaves and tests for every
    traversal, fewer nodes with a stack, no restarts with a full one, and lanes
    walk the full stack's nodes."""
    scene = mbao.Mesh(*box_grid(4))
    n = 3000
    origins, directions = points_in(rng, scene, n), random_directions(rng, n)
    counts = {
        name: mbao.trace(scene, origins, directions, traversal=name, traversal_stats=True)[3] for name in TRAVERSALS
    }
    for name, c in counts.items():
        nodes, leaves, triangles, restarts = c.T.astype(np.int64)
        assert np.all(leaves <= nodes) and np.all(restarts < np.maximum(leaves, 1)), name
    for name in TRAVERSALS[1:]:
        np.testing.assert_array_equal(counts[name][:, 1:3], counts["pushdown"][:, 1:3], err_msg=name)
    assert not counts["stack"][:, 3].any()
    assert counts["stack"][:, 0].sum() < counts["pushdown"][:, 0].sum() <= counts["restart"][:, 0].sum()
    assert counts["short-stack"][:, 3].sum() < counts["pushdown"][:, 3].sum()
    np.testing.assert_array_equal(counts["lanes"], counts["stack"])


@pytest.mark.parametrize("count", [1, 17, 300_000])
def test_lanes_return_the_full_stacks_hits_whatever_the_batch(rng, count):
    """A work item walks up to 512 rays sixteen at a time, a lane taking the
    next ray when its own ends: one ray, a batch that leaves lanes empty, and
    one where every lane walks dozens of rays in turn all give the full
    stack's hits bit for bit."""
    scene = mbao.Mesh(*random_soup(rng, 3000))
    origins, directions = points_in(rng, scene, count), random_directions(rng, count)
    t_max = rng.random(count) * 2 * np.linalg.norm(np.subtract(*scene.bounds))
    for any_hit in (False, True):
        stack = mbao.trace(scene, origins, directions, t_max=t_max, any_hit=any_hit, traversal="stack")
        lanes = mbao.trace(scene, origins, directions, t_max=t_max, any_hit=any_hit, traversal="lanes")
        for a, b in zip(stack, lanes):
            np.testing.assert_array_equal(a, b, err_msg=f"any_hit={any_hit}")
    if count > 1:  # not vacuous: some rays hit and some miss
        assert (stack[1] >= 0).any() and (stack[1] < 0).any()
