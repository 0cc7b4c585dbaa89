"""Baking per vertex (SPEC 6): closed-form answers, the front side, honest
standard errors and determinism. Statistical checks allow 4 standard errors of
the estimator, computed from its own variance."""

import inspect
import json
import math
import warnings

import numpy as np
import pytest

import mbao
from analytic import assert_within_standard_errors, polygon_occlusion
from gltf_writer import GltfBuilder
from interrupts import interrupt_after_the_first_tile
from meshes import box, box_grid, disk, icosphere, merge, plane


def bake(vertices, indices, **settings):
    settings.setdefault("progress", False)
    return mbao.bake(mbao.Mesh(vertices, indices), **settings)


@pytest.mark.parametrize("bounces", [1, 2, 3])
def test_a_plane_bakes_to_one(bounces):
    """Nothing occludes a lone plane: every vertex is exactly 1 with no spread."""
    result = bake(*plane(3.0, divisions=4), bounces=bounces, samples=32)
    np.testing.assert_array_equal(result.values, 1.0)
    np.testing.assert_array_equal(result.standard_error, 0.0)


@pytest.mark.filterwarnings("ignore:.*looks closed")
@pytest.mark.parametrize("bounces, rho", [(1, 1.0), (2, 1.0), (3, 0.5)])
def test_the_inside_of_a_closed_box_bakes_to_zero(bounces, rho):
    """Triangles that face into a closed box are baked on that side: every ray
    hits a wall, so every vertex is exactly 0, whatever the bounces."""
    result = bake(*box((-1.0, -1.5, -2.0), (1.0, 1.5, 2.0)), bounces=bounces, rho=rho, samples=64)
    np.testing.assert_array_equal(result.values, 0.0)
    np.testing.assert_array_equal(result.standard_error, 0.0)


@pytest.mark.filterwarnings("ignore:.*looks closed")
@pytest.mark.parametrize("bounces", [1, 2])
def test_the_front_side_is_the_windings(bounces):
    """The same closed surfaces wound the other way face out, where every ray
    escapes: 1 exactly (SPEC 6.1). Shading normals that point in are turned
    to the front side too."""
    vertices, indices = box((-1.0, -1.5, -2.0), (1.0, 1.5, 2.0))
    np.testing.assert_array_equal(bake(vertices, indices[:, ::-1], bounces=bounces, samples=64).values, 1.0)
    vertices, indices = icosphere(2.0, (1.0, -1.0, 0.5), subdivisions=2)
    inward_normals = -(vertices - (1.0, -1.0, 0.5))
    scene = mbao.Mesh(vertices, indices, inward_normals)
    outside = mbao.bake(scene, bounces=bounces, samples=64, normals="geometric", progress=False)
    np.testing.assert_array_equal(outside.values, 1.0)
    inside = bake(vertices, indices[:, ::-1], bounces=bounces, samples=64)
    np.testing.assert_array_equal(inside.values, 0.0)


def hat_weighted_mean(function, centre, rim):
    """Integral of phi * f over the fan of triangles (centre, rim[k], rim[k+1]),
    divided by the integral of phi, phi the centre's hat function: a 2-D
    Gauss-Legendre rule on each triangle (collapsed square), exact to far
    below the tolerances here for a smooth f."""
    nodes, weights = np.polynomial.legendre.leggauss(12)
    s, w = (nodes + 1) / 2, weights / 2
    total = weight = 0.0
    for a, b in zip(rim, np.roll(rim, -1, axis=0)):
        area = 0.5 * np.linalg.norm(np.cross(a - centre, b - centre))
        for si, wi in zip(s, w):
            for tj, wj in zip(s, w):
                # (u, v) = (si, (1 - si) tj) covers the triangle with Jacobian (1 - si).
                u, v = si, (1.0 - si) * tj
                phi = 1.0 - u - v
                point = centre + u * (a - centre) + v * (b - centre)
                dw = wi * wj * (1.0 - si) * 2.0 * area
                total += dw * phi * function(point)
                weight += dw * phi
    return total / weight


def test_a_floor_under_a_parallel_disk():
    """A floor vertex under a parallel disk (b = 1): its value is the hat-weighted
    mean over its one-ring of 1 - F, F the disk's form factor (Lambert's
    polygon formula), which at the ring's centre is h^2 / (h^2 + R^2)."""
    height, radius, ring = 1.0, 0.8, 0.05
    angles = np.linspace(0.0, 2.0 * np.pi, 12, endpoint=False)
    circle = np.column_stack([np.cos(angles), np.zeros(12), np.sin(angles)])
    floor = np.vstack([[0.0, 0.0, 0.0], ring * circle, 10.0 * circle])
    fan = [[0, 1 + (k + 1) % 12, 1 + k] for k in range(12)]  # facing up
    band = [[1 + k, 1 + (k + 1) % 12, 13 + (k + 1) % 12] for k in range(12)]
    band += [[1 + k, 13 + (k + 1) % 12, 13 + k] for k in range(12)]
    disk_vertices, disk_indices = disk(radius, height, 64)
    vertices, indices = merge((floor, fan + band), (disk_vertices, disk_indices))
    samples = 20000
    result = bake(vertices, indices, bounces=1, samples=samples, directions=1)

    polygon = disk_vertices[1:]
    expected = hat_weighted_mean(lambda p: 1.0 - polygon_occlusion(p, (0.0, 1.0, 0.0), polygon), floor[0], floor[1:13])
    at_centre = 1.0 - polygon_occlusion(np.zeros(3), (0.0, 1.0, 0.0), polygon)
    assert abs(at_centre - height**2 / (height**2 + radius**2)) < 2e-3  # the 64-gon is nearly the circle
    # With one direction, each estimate is 0 or 1 with mean `expected`: a Bernoulli variable.
    assert_within_standard_errors(float(result.values[0]), expected, samples)
    assert result.standard_error[0] == pytest.approx(math.sqrt(expected * (1 - expected) / samples), rel=0.05)


def outward_box_grid():
    vertices, indices = box_grid(3)
    return vertices, indices[:, ::-1]


def test_standard_errors_are_honest():
    """Two bakes under different seeds differ by about their standard errors:
    the mean of z^2 = (a - b)^2 / (se_a^2 + se_b^2) over the vertices is 1
    within 4 of its own standard errors, sqrt(2 / n) for n vertices."""
    vertices, indices = outward_box_grid()
    a = bake(vertices, indices, bounces=2, samples=128, seed=1)
    b = bake(vertices, indices, bounces=2, samples=128, seed=2)
    spread = a.standard_error.astype(float) ** 2 + b.standard_error.astype(float) ** 2
    varied = spread > 0
    assert varied.sum() > 150
    z2 = (a.values[varied].astype(float) - b.values[varied]) ** 2 / spread[varied]
    assert abs(z2.mean() - 1.0) <= 4.0 * math.sqrt(2.0 / varied.sum()), z2.mean()


def test_both_estimators_bake_the_same_values():
    """The path and the branching estimator have one expectation (SPEC 2): their
    bakes differ by about their standard errors, z^2 as above."""
    vertices, indices = outward_box_grid()
    path = bake(vertices, indices, bounces=2, samples=64, estimator="path", seed=1)
    branching = bake(vertices, indices, bounces=2, samples=16, estimator="branching", directions=3, seed=2)
    spread = path.standard_error.astype(float) ** 2 + branching.standard_error.astype(float) ** 2
    varied = spread > 0
    assert varied.sum() > 150
    z2 = (path.values[varied].astype(float) - branching.values[varied]) ** 2 / spread[varied]
    assert abs(z2.mean() - 1.0) <= 4.0 * math.sqrt(2.0 / varied.sum()), z2.mean()


ENGINES = [
    ("path", mbao.Engine(traversal="stack", organisation="megakernel")),
    ("branching", mbao.Engine(traversal="stack", organisation="megakernel")),
    ("branching", mbao.Engine(traversal="lanes")),
    ("branching", mbao.Engine(traversal="short-stack", organisation="wavefront", tile_pixels=7)),
]


@pytest.mark.parametrize(
    "estimator, engine", ENGINES, ids=["path-megakernel", "branching-megakernel", "lanes", "short-stack-tiles"]
)
def test_a_bake_is_a_function_of_the_seed_and_settings(estimator, engine):
    """The same seed gives the same bits whatever the walk, the organisation or
    the tiles; another seed gives other values (SPEC 6.6)."""
    vertices, indices = outward_box_grid()
    reference = bake(vertices, indices, bounces=2, samples=16, estimator=estimator, seed=5)
    again = bake(vertices, indices, bounces=2, samples=16, estimator=estimator, seed=5, engine=engine)
    np.testing.assert_array_equal(again.values, reference.values)
    np.testing.assert_array_equal(again.standard_error, reference.standard_error)
    other = bake(vertices, indices, bounces=2, samples=16, estimator=estimator, seed=6)
    assert not np.array_equal(other.values, reference.values)


def test_vertices_without_surface_are_open():
    """A vertex that no triangle uses, or only a triangle of zero area, has no
    surface to average over: 1, with standard error 0."""
    vertices, indices = box((-1.0, -1.0, -1.0), (1.0, 1.0, 1.0))
    vertices = np.vstack([vertices, [[5.0, 5.0, 5.0], [0.0, 0.0, 0.0], [0.5, 0.0, 0.0]]])
    indices = np.vstack([indices, [[9, 10, 9]]])  # a degenerate triangle
    result = bake(vertices, indices, bounces=1, samples=16)
    np.testing.assert_array_equal(result.values[:8], 0.0)
    np.testing.assert_array_equal(result.values[8:], 1.0)
    np.testing.assert_array_equal(result.standard_error[8:], 0.0)


@pytest.mark.filterwarnings("ignore:.*looks closed")
def test_triangles_not_baked_still_occlude():
    """SPEC 6: a floor inside a closed box, baked alone. The box's walls still
    stop every ray (the floor is 0), but its vertices are baked over none of
    their triangles: 1, with standard error 0, and no ray traced for them."""
    floor, floor_indices = plane(0.5, divisions=2)
    vertices, indices = merge((floor, floor_indices), box((-1.0, -1.0, -1.0), (1.0, 1.0, 1.0)))
    floor_triangles = np.arange(len(floor_indices))
    alone = bake(vertices, indices, bounces=2, samples=16, triangles=floor_triangles)
    np.testing.assert_array_equal(alone.values[: len(floor)], 0.0)
    np.testing.assert_array_equal(alone.values[len(floor) :], 1.0)
    np.testing.assert_array_equal(alone.standard_error[len(floor) :], 0.0)
    everything = bake(vertices, indices, bounces=2, samples=16)
    np.testing.assert_array_equal(everything.values, 0.0)
    assert alone.stats["rays_secondary"] * len(vertices) == everything.stats["rays_secondary"] * len(floor)


@pytest.mark.parametrize(
    "triangles, message",
    [
        ([], "triangles must be a non-empty list of triangle indices"),
        ([0.5], "triangles must be a non-empty list of triangle indices"),
        ([[0, 1]], "triangles must be a non-empty list"),
        ([2], r"triangles: 2 is not a triangle of the scene, whose triangles are 0 to 1"),
        ([-1], r"triangles: -1 is not a triangle"),
    ],
)
def test_bad_triangles_are_named(triangles, message):
    with pytest.raises(ValueError, match=message):
        bake(*plane(1.0), samples=2, triangles=triangles)


def test_a_bake_counts_its_rays_and_refuses_too_many():
    vertices, indices = outward_box_grid()
    result = bake(vertices, indices, bounces=2, samples=16, directions=3, progress=None)  # None: no bar
    assert result.stats["rays_primary"] == 0
    assert 0 < result.stats["rays_secondary"] <= len(vertices) * 16 * 3 * 2  # r paths of b segments each
    with pytest.raises(ValueError, match="max_rays"):
        bake(vertices, indices, bounces=2, samples=16, max_rays=1000)


@pytest.mark.parametrize(
    "arguments, message",
    [
        (dict(samples=1), r"samples must be in \[2, 65536\]"),
        (dict(samples=1 << 17), r"samples must be in \[2, 65536\]"),
        (dict(target="faces"), "target must be one of 'vertices'"),
        (dict(directions=0), r"directions must be in \[1, 1048576\]"),
        (dict(estimator="paths"), "estimator"),
        (dict(estimator="branching", bounces=17), "bounces"),
        (dict(bounces=0), "bounces"),
        (dict(rho=1.5), "rho"),
        (dict(max_distance=-1.0), "max_distance"),
    ],
)
def test_bad_arguments_name_themselves(arguments, message):
    with pytest.raises(ValueError, match=message):
        bake(*plane(1.0), **arguments)


def floor_under_a_ceiling():
    """A floor (its first 9 vertices) facing up, 1 below a far wider ceiling."""
    return merge(plane(1.0, 0.0, divisions=2), plane(50.0, 1.0))


def radius_of(result):
    return result.stats["max_distance"], result.stats["max_distance_source"]


def test_a_bake_takes_its_radius_by_renders_rule(tmp_path):
    """SPEC 1: the radius given wins, inf included; else the one a camera
    suggests, the camera given for it or else the scene's own; else inf.
    Within 0.5 of the floor nothing is hit: 1 exactly; without a radius the
    ceiling covers nearly all of the floor's sky."""
    vertices, indices = floor_under_a_ceiling()
    scene = mbao.Mesh(vertices, indices)
    camera = mbao.Camera([0, 0.5, 5], [0, 0.5, 0], max_distance=0.5)
    (tmp_path / "camera.json").write_text(
        json.dumps({"eye": [0, 0.5, 5], "target": [0, 0.5, 0], "up": [0, 1, 0], "vfov_deg": 60, "max_distance": 0.5})
    )
    b = GltfBuilder()
    b.add_scene(
        [
            b.add_node(mesh=b.add_mesh([b.primitive(vertices, indices)])),
            b.add_node(camera=b.add_perspective_camera(0.9, extras={"max_distance": 0.5}), translation=(0, 0.5, 5)),
        ]
    )
    with_camera = b.write(tmp_path / "with_camera.glb")

    limited = [
        mbao.bake(scene, samples=16, max_distance=0.5, progress=False),
        mbao.bake(scene, samples=16, camera=camera, progress=False),
        mbao.bake(scene, samples=16, camera=tmp_path / "camera.json", progress=False),
        mbao.bake(with_camera, samples=16, progress=False),
    ]
    assert [radius_of(r) for r in limited] == [(0.5, "settings")] + [(0.5, "camera")] * 3
    for result in limited:
        np.testing.assert_array_equal(result.values[:9], 1.0)

    unlimited = [
        mbao.bake(scene, samples=16, progress=False),
        mbao.bake(with_camera, samples=16, max_distance=math.inf, progress=False),
    ]
    assert [radius_of(r) for r in unlimited] == [(math.inf, "none"), (math.inf, "settings")]
    for result in unlimited:
        assert result.values[:9].max() < 0.1


def test_a_closed_scene_baked_without_a_radius_warns_as_a_render_does():
    vertices, indices = box((-1.0, -1.5, -2.0), (1.0, 1.5, 2.0))
    grid = mbao.Mesh(*merge(*[(v + (4.0 * k, 0.0, 0.0), i) for k, (v, i) in enumerate([(vertices, indices)] * 16)]))
    with pytest.warns(
        UserWarning, match="of the vertices are below 0.01 with max_distance=inf: the scene looks closed"
    ):
        mbao.bake(grid, samples=4, progress=False)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        mbao.bake(grid, samples=4, max_distance=0.5, progress=False)


def test_a_bake_refuses_camera_frame_which_suggests_no_radius():
    with pytest.raises(ValueError, match='camera="frame" suggests no radius'):
        bake(*plane(1.0), camera="frame")


def test_bake_and_render_default_to_the_same_bounces():
    """SPEC 1: b is 1 unless asked for, on the command line too."""
    from mbao.cli import _parser

    defaults = {
        inspect.signature(mbao.bake).parameters["bounces"].default,
        inspect.signature(mbao.render).parameters["bounces"].default,
        _parser().parse_args(["bake", "in.glb", "-o", "out.glb"]).bounces,
        _parser().parse_args(["render"]).bounces,
    }
    assert defaults == {1}


def test_the_bakes_settings_are_its_table_and_the_renders_in_mbao_bake_and_on_the_command_line():
    """The bake's own settings (SPEC 6's table) and those it shares with a
    render take one default in mbao.bake and in `python -m mbao bake`, and
    its docstring lists the table's with their ranges."""
    from mbao.cli import _parser
    from mbao.settings import BAKE_SETTINGS, RENDER

    parameters = inspect.signature(mbao.bake).parameters
    options = vars(_parser().parse_args(["bake", "in.glb", "-o", "out.glb"]))
    for name, spec in BAKE_SETTINGS.items():
        assert parameters[name].default == options[name] == spec["default"], name
        assert f"{name}: {spec['doc'][:30]}" in " ".join(mbao.bake.__doc__.split()), name
    for name in ("bounces", "rho", "seed"):
        assert parameters[name].default == options[name] == RENDER[name]["default"], name
    assert BAKE_SETTINGS["estimator"]["choices"] == RENDER["estimator"]["choices"]
    assert BAKE_SETTINGS["directions"]["range"] == RENDER["samples"]["range"]  # r, drawn as a render draws it


def test_a_bake_takes_a_scene_path(tmp_path):
    with pytest.raises(mbao.LoadError, match="missing.glb"):
        mbao.bake(tmp_path / "missing.glb", progress=False)


def test_ctrl_c_stops_a_bake_between_tiles_and_the_next_one_works():
    """A real SIGINT while a tile runs with the GIL released (as
    test_work_limits.py does for renders): the bake stops after the tile in
    flight, and the bakes after it work, bit for bit alike."""
    vertices, indices = outward_box_grid()
    settings = dict(bounces=3, samples=256, engine=mbao.Engine(tile_pixels=8))
    tiles_done = interrupt_after_the_first_tile(lambda progress: bake(vertices, indices, progress=progress, **settings))
    total = next(iter(tiles_done.values()))
    assert len(tiles_done) < total, "the bake ran to its end before it saw the interrupt"
    small = dict(bounces=2, samples=8)
    np.testing.assert_array_equal(bake(vertices, indices, **small).values, bake(vertices, indices, **small).values)
