"""HBAO, the screen-space baseline (SPEC 4; issue 5): what it must see, what it
must not, and how its settings move it. HBAO approximates AO; these tests check
its geometry and its monotonic responses, not closeness to the ray-traced value
(the convergence study reports that)."""

import numpy as np
import pytest

import hbao_oracle
import mbao
from conftest import shared_scene
from meshes import merge, plane

SIZE = 48


def render_hbao(scene, camera, radius, **hbao):
    return mbao.render(
        scene, camera=camera, width=SIZE, height=SIZE, method="hbao", max_distance=radius, hbao=mbao.HBAO(**hbao)
    )


@pytest.fixture(scope="module")
def cornell():
    return mbao.cornell_box()


@pytest.mark.parametrize("eye", [(0.0, 0.0, 5.0), (0.0, 3.0, 4.0)], ids=["facing", "tilted 37 degrees"])
def test_a_plane_alone_is_open(eye):
    """Every sample lies in the pixel's tangent plane: no horizon rises above the angle bias."""
    vertices, indices = plane(4.0, divisions=4)
    wall = mbao.Mesh(vertices[:, [0, 2, 1]], indices)  # the plane z = 0, facing +z
    camera = mbao.Camera(eye, (0, 0, 0), (0, 1, 0), 40.0)
    result = render_hbao(wall, camera, radius=1.0)
    assert result.mask.all()
    np.testing.assert_array_equal(result.ao, 1.0)


def test_an_inside_corner_is_occluded_near_its_crease_only():
    floor_vertices, floor_indices = plane(2.0, y=0.0, divisions=4)
    wall_vertices, wall_indices = plane(2.0, y=0.0, divisions=4)
    wall_vertices = wall_vertices[:, [0, 2, 1]] - [0, -2.0, 2.0]  # z = -2, from y = 0 up to 4
    corner = mbao.Mesh(*merge((floor_vertices, floor_indices), (wall_vertices, wall_indices)))
    camera = mbao.Camera((0, 2.0, 4.0), (0, 0.5, -2.0), (0, 1, 0), 50.0)
    radius = 0.5
    result = render_hbao(corner, camera, radius)
    hits = traced_points(corner, camera)
    distance_to_crease = np.hypot(hits[..., 1], hits[..., 2] + 2.0)
    near, far = distance_to_crease < 0.2 * radius, distance_to_crease > 1.5 * radius
    assert near.sum() > 10 and far.sum() > 100
    assert result.ao[near].max() < 1.0
    np.testing.assert_array_equal(result.ao[far & result.mask], 1.0)


def traced_points(scene, camera):
    """World positions of the camera rays' hits through the pixel centres (SPEC 3.1)."""
    forward = np.subtract(camera.target, camera.eye)
    forward /= np.linalg.norm(forward)
    right = np.cross(forward, camera.up)
    right /= np.linalg.norm(right)
    up = np.cross(right, forward)
    tan_half = np.tan(np.radians(camera.vfov_deg) / 2)
    centres = (np.arange(SIZE) + 0.5) / SIZE * 2 - 1
    u, v = np.meshgrid(centres, -centres)
    directions = forward + (u * tan_half)[..., None] * right + (v * tan_half)[..., None] * up
    directions = directions.reshape(-1, 3)
    t, _, _ = mbao.trace(scene, np.tile(camera.eye, (len(directions), 1)), directions)
    return (np.asarray(camera.eye) + t[:, None] * directions).reshape(SIZE, SIZE, 3)


SHARED = ["cornell_box", "bunny", "sibenik", "sponza", "damaged_helmet"]
ORACLE_SIZE = 64


def shared_hbao(name, seed):
    """HBAO's image of a shared scene with its camera and radius, the G-buffer it read, and the camera."""
    folder = shared_scene(name)
    scene, camera = mbao.load(folder / "scene.glb"), mbao.Camera.load(folder / "camera.json")
    result = mbao.render(scene, camera=camera, width=ORACLE_SIZE, height=ORACLE_SIZE, method="hbao", seed=seed)
    return result, mbao.gbuffer(scene, camera=camera, width=ORACLE_SIZE, height=ORACLE_SIZE), camera


@pytest.mark.parametrize("name", SHARED)
def test_the_kernel_draws_the_oracles_image(name):
    """The kernel and tests/hbao_oracle.py (SPEC 4 in double precision, reading
    the G-buffer's points and normals as they are) draw the same jitter, so
    their images differ only where rounding moves a sample across a pixel's
    edge or a horizon comparison: the kernel rebuilds points from depth, in
    floats, with directions within 5e-7 of sin and cos (mbao/unit_circle.h)."""
    result, g, camera = shared_hbao(name, seed=5)
    oracle = hbao_oracle.hbao(g, camera, result.stats["max_distance"], seed=5)
    moved = np.abs(result.ao - oracle) > 1e-4
    assert moved.sum() <= 0.002 * moved.size, f"{moved.sum()} pixels off the oracle"
    np.testing.assert_allclose(result.ao[~moved], oracle[~moved], atol=1e-4)


@pytest.mark.parametrize("name", ["cornell_box", "sponza"])
def test_over_seeds_the_kernel_averages_to_the_oracles_expectation(name):
    """HBAO with random jitter is an estimator: 16 seeds of the kernel and 16
    other seeds of the oracle estimate each pixel's expectation, and pixels'
    jitters are independent. Where the seeds spread, each pixel's difference
    of means over its estimated standard error is a t of 2 x 16 - 2 = 30
    degrees of freedom, whose square has mean 30/28 and variance
    2 30^2 29 / (28^2 26); their sum over the pixels is held to 4 of its
    standard deviations above its mean. Where no seed spreads (open surfaces)
    the two agree to rounding."""
    runs = 16
    kernel_runs, oracle_runs = [], []
    for k in range(runs):
        result, g, camera = shared_hbao(name, seed=k)
        kernel_runs.append(result.ao)
        oracle_runs.append(hbao_oracle.hbao(g, camera, result.stats["max_distance"], seed=1000 + k))
    kernel_runs, oracle_runs = np.array(kernel_runs, dtype=np.float64), np.array(oracle_runs)
    variance = (kernel_runs.var(axis=0, ddof=1) + oracle_runs.var(axis=0, ddof=1)) / runs
    difference = kernel_runs.mean(axis=0) - oracle_runs.mean(axis=0)
    spread = variance > 1e-10
    n, dof = spread.sum(), 2 * runs - 2
    assert n > 100
    t2_mean, t2_variance = dof / (dof - 2), 2 * dof**2 * (dof - 1) / ((dof - 2) ** 2 * (dof - 4))
    t2_sum = np.sum(difference[spread] ** 2 / variance[spread])
    assert t2_sum <= n * t2_mean + 4 * np.sqrt(n * t2_variance), f"sum of t^2 {t2_sum:.0f} over {n} pixels"
    np.testing.assert_allclose(difference[~spread], 0.0, atol=1e-4)


def test_coverage_is_the_ray_traced_coverage(cornell):
    camera = mbao.Camera((278, 273, -800), (400, 300, 0), (0, 1, 0), 60.0)  # sees past the box's edge
    hbao = render_hbao(cornell, camera, radius=100.0)
    traced = mbao.render(cornell, camera=camera, width=SIZE, height=SIZE, max_distance=100.0)
    assert not hbao.mask.all()
    np.testing.assert_array_equal(hbao.mask, traced.mask)
    np.testing.assert_array_equal(hbao.ao[~hbao.mask], 1.0)


def test_the_image_is_a_function_of_the_seed(cornell):
    camera = cornell.camera
    first = mbao.render(cornell, camera=camera, width=SIZE, height=SIZE, method="hbao", max_distance=100.0, seed=3)
    again = mbao.render(cornell, camera=camera, width=SIZE, height=SIZE, method="hbao", max_distance=100.0, seed=3)
    other = mbao.render(cornell, camera=camera, width=SIZE, height=SIZE, method="hbao", max_distance=100.0, seed=4)
    np.testing.assert_array_equal(first.ao, again.ao)
    assert not np.array_equal(first.ao, other.ao)


def test_falloff_only_weakens_occlusion(cornell):
    """W(r) <= 1 weighs the same horizon rises: per pixel, access with falloff >= without."""
    without = render_hbao(cornell, cornell.camera, 150.0, falloff=0.0)
    with_falloff = render_hbao(cornell, cornell.camera, 150.0, falloff=1.0)
    assert np.all(with_falloff.ao >= without.ao)
    assert with_falloff.ao.mean() > without.ao.mean()


def test_a_larger_angle_bias_only_weakens_occlusion(cornell):
    """Without falloff a direction's occlusion is its highest horizon minus the
    biased tangent: a higher start can only lower it."""
    images = [render_hbao(cornell, cornell.camera, 150.0, falloff=0.0, angle_bias_deg=bias).ao for bias in (0, 10, 30)]
    assert np.all(images[1] >= images[0]) and np.all(images[2] >= images[1])
    assert images[2].mean() > images[0].mean()


def test_more_radius_finds_more_occluders(cornell):
    means = [render_hbao(cornell, cornell.camera, radius).ao.mean() for radius in (20.0, 80.0, 300.0)]
    assert means[0] > means[1] > means[2]


def test_stats_describe_an_hbao_frame(cornell):
    result = render_hbao(cornell, cornell.camera, 100.0)
    assert result.stats["rays_primary"] == SIZE * SIZE and result.stats["rays_secondary"] == 0
    assert result.stats["frame_ms"] > 0
    # The scene's few kB, and per pixel the four G-buffer planes HBAO reads (depth, shading normal), its
    # AO and its coverage: no room for a fifth plane.
    per_pixel = 4 * 4 + 4 + 1
    assert SIZE * SIZE * per_pixel < result.stats["memory_bytes"] < SIZE * SIZE * (per_pixel + 4)
    assert result.stats["organisation"] is None  # the kernel organisations are the ray-traced method's
    assert result.stats["kernels"] in (["trace_camera_rays"], ["trace_camera_packets"])  # and hbao.cl's pass


@pytest.mark.parametrize(
    "arguments, message",
    [
        (dict(bounces=2), r"one bounce.*gtao_multibounce"),
        (dict(max_distance=float("inf")), r"finite max_distance"),
        (dict(spp=2), r"spp"),
        (dict(engine=mbao.Engine(organisation="wavefront")), r"organisation"),
    ],
)
def test_bad_hbao_settings(cornell, arguments, message):
    settings = dict(width=8, height=8, method="hbao", max_distance=100.0)
    settings.update(arguments)
    with pytest.raises(ValueError, match=message):
        mbao.render(cornell, **settings)


@pytest.mark.parametrize(
    "arguments, message",
    [
        (dict(directions=0), r"directions.*\[1, 64\]"),
        (dict(steps=65), r"steps.*\[1, 64\]"),
        (dict(angle_bias_deg=90), r"angle_bias_deg.*\[0, 90\)"),
        (dict(falloff=1.5), r"falloff.*\[0, 1\]"),
    ],
)
def test_an_hbao_out_of_range_is_refused_where_it_is_made(arguments, message):
    """As Denoise and Temporal are: the error points at the line that made it, not at a later render."""
    with pytest.raises(ValueError, match=message):
        mbao.HBAO(**arguments)


def test_hbao_settings_must_be_an_hbao(cornell):
    with pytest.raises(TypeError, match="mbao.HBAO"):
        mbao.render(cornell, width=8, height=8, method="hbao", max_distance=100.0, hbao=dict(directions=4))
    with pytest.raises(ValueError, match="method"):
        mbao.render(cornell, width=8, height=8, method="ssao")
