"""The two estimators of SPEC 2 on the Cornell box: same expected value, L_b
non-decreasing in b, bounded by [0, 1], and images that depend on the seed
and the settings alone, not on how the work is cut up."""

import math

import numpy as np
import pytest

import mbao
from meshes import merge, plane, random_soup

ESTIMATORS = ("branching", "path")


@pytest.fixture(scope="module")
def cornell():
    return mbao.cornell_box()


def render_seeds(scene, seeds, **settings):
    return np.stack([mbao.render(scene, seed=seed, **settings).ao for seed in seeds])


@pytest.mark.parametrize("bounces", [2, 3])
def test_branching_and_path_have_the_same_expectation(cornell, bounces):
    """The difference of the image means lies within 4 standard errors, the
    standard error taken from the per-pixel variance over independent seeds."""
    settings = dict(width=16, height=16, bounces=bounces, samples=4, rho=0.8)
    runs = 12
    branching = render_seeds(cornell, range(runs), estimator="branching", **settings)
    path = render_seeds(cornell, range(1000, 1000 + runs), estimator="path", **settings)
    pixels = branching.shape[1] * branching.shape[2]
    difference = branching.mean() - path.mean()
    variance = (branching.var(axis=0, ddof=1).sum() + path.var(axis=0, ddof=1).sum()) / runs / pixels**2
    assert abs(difference) <= 4.0 * np.sqrt(variance), f"{difference} vs standard error {np.sqrt(variance)}"
    # Estimates that differ in nothing are no test: the estimators must have noise.
    assert variance > 0


@pytest.mark.parametrize(
    "estimator, rho, rounding",
    [("branching", 1.0, 0.0), ("branching", 0.6, 0.0), ("path", 1.0, 0.0), ("path", 0.6, 1e-6)],
)
def test_more_bounces_never_lower_the_access(cornell, estimator, rho, rounding):
    """L_b <= L_(b+1): a hit adds rho * L_(b-1) >= 0. With the same seed both
    estimators draw the same directions for the bounces both images have, so it
    holds pixel by pixel; exactly where the sums are exact (escapes counted per
    bounce, or rho = 1), else up to float rounding."""
    images = [
        mbao.render(cornell, width=24, height=24, bounces=b, samples=3, rho=rho, estimator=estimator, seed=9).ao
        for b in (1, 2, 3, 4)
    ]
    for lower, higher in zip(images, images[1:]):
        assert np.all(higher >= lower - rounding)
        assert np.mean(higher) > np.mean(lower)  # in the closed box, bounces add light
    for image in images:
        assert image.min() >= 0.0 and image.max() <= 1.0


@pytest.mark.parametrize("estimator", ESTIMATORS)
def test_black_surfaces_stop_at_the_first_hit(cornell, estimator):
    """With rho = 0 a hit contributes nothing: every b gives the b = 1 image."""
    one = mbao.render(cornell, width=16, height=16, bounces=1, samples=4, estimator=estimator, seed=4)
    three = mbao.render(cornell, width=16, height=16, bounces=3, samples=4, rho=0.0, estimator=estimator, seed=4)
    np.testing.assert_array_equal(one.ao, three.ao)
    assert three.stats["rays_secondary"] == one.stats["rays_secondary"]


def test_rays_per_camera_sample_are_those_of_spec_2(device):
    """Inside a closed box every ray hits: branching traces r + r^2 + ... + r^b
    rays per camera sample, path r * b."""
    from meshes import box

    scene = mbao.Mesh(*box((-1, -1, -1), (1, 1, 1)))
    camera = mbao.Camera((0.1, 0.2, 0.0), (0.0, 0.0, 1.0), vfov_deg=90.0)
    samples, bounces, spp = 3, 3, 2
    common = dict(camera=camera, width=5, height=4, samples=samples, bounces=bounces, spp=spp, normals="geometric")
    branching = mbao.render(scene, estimator="branching", **common).stats
    path = mbao.render(scene, estimator="path", **common).stats
    camera_samples = 5 * 4 * spp
    assert branching["rays_primary"] == path["rays_primary"] == camera_samples
    assert branching["rays_secondary"] == camera_samples * (3 + 9 + 27)
    assert path["rays_secondary"] == camera_samples * 3 * 3


@pytest.mark.parametrize("estimator", ESTIMATORS)
def test_images_do_not_depend_on_tiling_or_work_group_size(cornell, estimator):
    # 37 x 21: whole 16 x 16 blocks of the pixel order and blocks cut by both edges.
    settings = dict(width=37, height=21, bounces=2, samples=3, spp=2, estimator=estimator, seed=77)
    reference = mbao.render(cornell, **settings)
    for tile_pixels, work_group_size in ((1, None), (7, 1), (64, 16), (391, 128), (None, 3)):
        engine = mbao.Engine(tile_pixels=tile_pixels, work_group_size=work_group_size)
        other = mbao.render(cornell, engine=engine, **settings)
        np.testing.assert_array_equal(other.ao, reference.ao)
        np.testing.assert_array_equal(other.mask, reference.mask)
        assert other.stats["rays_secondary"] == reference.stats["rays_secondary"]
    assert mbao.render(cornell, engine=mbao.Engine(tile_pixels=1), **settings).stats["tiles"] == 37 * 21


def test_the_seed_alone_decides_the_noise(cornell):
    a = mbao.render(cornell, width=16, height=16, seed=1).ao
    np.testing.assert_array_equal(a, mbao.render(cornell, width=16, height=16, seed=1).ao)
    assert not np.array_equal(a, mbao.render(cornell, width=16, height=16, seed=2).ao)
    # All 64 bits of the seed count.
    assert not np.array_equal(a, mbao.render(cornell, width=16, height=16, seed=1 + 2**40).ao)


@pytest.mark.parametrize("traversal", ["pushdown", "restart", "short-stack", "stack", "lanes"])
def test_traversals_render_the_same_image(cornell, traversal):
    settings = dict(width=20, height=20, bounces=2, samples=4, seed=5)
    np.testing.assert_array_equal(
        mbao.render(cornell, engine=mbao.Engine(traversal=traversal), **settings).ao,
        mbao.render(cornell, **settings).ao,
    )


@pytest.mark.parametrize("samples", [1, 3, 4, 6, 8])
def test_lanes_draw_the_megakernels_directions_whatever_r(cornell, samples):
    """The lanes' stream draws a surface's AO directions four at a time on
    vectors, the rest one by one; the megakernel draws them one by one. An
    image hardly shows a last-bit difference in a direction: those are
    compared in tests/cpp/test_sampling.cpp."""
    settings = dict(width=16, height=16, bounces=2, samples=samples, seed=11)
    lanes = mbao.render(cornell, engine=mbao.Engine(traversal="lanes"), **settings)
    assert lanes.stats["traversal_mode"] == "lanes"
    megakernel = mbao.render(cornell, engine=mbao.Engine(organisation="megakernel"), **settings)
    np.testing.assert_array_equal(lanes.ao, megakernel.ao)


def test_the_wavefront_renders_the_megakernels_image(cornell):
    """The C++ tests compare them on more scenes; this is the Python path."""
    settings = dict(width=24, height=24, bounces=3, samples=3, rho=0.8, seed=9)
    wavefront = mbao.render(cornell, engine=mbao.Engine(organisation="wavefront"), **settings)
    megakernel = mbao.render(cornell, engine=mbao.Engine(organisation="megakernel"), **settings)
    np.testing.assert_array_equal(wavefront.ao, megakernel.ao)
    assert wavefront.stats["rays_secondary"] == megakernel.stats["rays_secondary"]


def test_auto_traversal_is_the_full_stack_on_cpus_and_the_short_stack_elsewhere(cornell):
    device = mbao.devices()[0]
    settings = dict(width=8, height=8, device=device)
    expected = "stack" if device.type == "CPU" else "short-stack"  # the Cornell box's tree is 6 deep
    assert mbao.render(cornell, **settings).stats["traversal_mode"] == expected
    assert (
        mbao.render(cornell, engine=mbao.Engine(traversal="restart"), **settings).stats["traversal_mode"] == "restart"
    )


def test_auto_traversal_is_lanes_on_cpus_for_deep_trees_where_the_wavefront_runs(rng):
    device = mbao.devices()[0]
    deep = mbao.Mesh(*random_soup(rng, 3000))
    settings = dict(width=8, height=8, bounces=2, device=device)
    result = mbao.render(deep, **settings)
    assert result.stats["tree"]["max_depth"] >= 16
    on_cpu = device.type == "CPU"
    assert result.stats["traversal_mode"] == ("lanes" if on_cpu else "short-stack")
    assert result.stats["organisation"] == "wavefront"
    # The path estimator and the megakernel walk one ray per work item.
    for other in (dict(estimator="path"), dict(engine=mbao.Engine(organisation="megakernel"))):
        assert mbao.render(deep, **other, **settings).stats["traversal_mode"] == ("stack" if on_cpu else "short-stack")


def test_auto_organisation_is_the_wavefront_on_gpus_and_the_megakernel_elsewhere(cornell):
    device = mbao.devices()[0]
    settings = dict(width=8, height=8, bounces=2, device=device)
    expected = "wavefront" if device.type == "GPU" else "megakernel"
    assert mbao.render(cornell, **settings).stats["organisation"] == expected
    assert mbao.render(cornell, estimator="path", **settings).stats["organisation"] == "megakernel"
    wavefront = mbao.Engine(organisation="wavefront")
    assert mbao.render(cornell, engine=wavefront, **settings).stats["organisation"] == "wavefront"


def test_stats_name_the_kernels_the_frame_launched(cornell):
    """In launch order: the camera rays, then the organisation's AO kernels."""
    settings = dict(width=8, height=8, bounces=2, engine=mbao.Engine(traversal="stack", organisation="megakernel"))
    assert mbao.render(cornell, **settings).stats["kernels"] == ["trace_camera_rays", "ao_branching"]
    assert mbao.render(cornell, estimator="path", **settings).stats["kernels"] == ["trace_camera_rays", "ao_path"]
    wavefront = dict(settings, engine=mbao.Engine(traversal="stack", organisation="wavefront"))
    assert mbao.render(cornell, **wavefront).stats["kernels"] == [
        "trace_camera_rays",
        "wavefront_first_bounce",
        "wavefront_bounce",
        "wavefront_finish",
    ]
    lanes = dict(settings, engine=mbao.Engine(traversal="lanes", organisation="wavefront"))
    assert mbao.render(cornell, **lanes).stats["kernels"] == [
        "trace_camera_packets",
        "stream_bounce_rays",
        "trace_rays_in_lanes",
        "stream_bounce_hits",
        "wavefront_finish",
    ]


def test_camera_samples_average_over_the_pixel():
    """spp > 1 jitters the camera rays uniformly over the pixel and averages
    (a box filter). Seen from straight above, a half-plane x <= 0 under a far
    wider ceiling at height H, within a radius d > H, has L_1 = c = (H / d)^2
    everywhere (the directions within d of the ceiling are those with
    cos theta >= H / d, of cosine weight 1 - (H / d)^2), and misses count 1: a
    pixel covering a fraction f of the half-plane has mean 1 - f (1 - c).
    Pixels along the edge are partly covered. The camera looks down from below
    the ceiling."""
    ceiling, radius, r, spp = 3.0, 4.5, 16, 64
    c = (ceiling / radius) ** 2
    half_plane = np.array([[-50.0, 0.0, -50.0], [0.0, 0.0, -50.0], [0.0, 0.0, 50.0], [-50.0, 0.0, 50.0]])
    vertices, indices = merge((half_plane, [[0, 1, 2], [0, 2, 3]]), plane(100.0, ceiling))
    scene = mbao.Mesh(vertices, indices)
    width, height, depth, vfov = 16, 6, 2.0, 60.0
    camera = mbao.Camera((0.3, depth, 0.1), (0.3, 0.0, 0.1), up=(0.0, 0.0, -1.0), vfov_deg=vfov)
    result = mbao.render(
        scene, camera=camera, width=width, height=height, samples=r, spp=spp, seed=11, max_distance=radius
    )

    # SPEC 3.1: right = normalize(cross(forward, up)) = +x here, so image column
    # x covers world x in 0.3 + depth * tan(vfov / 2) * aspect * [u(x), u(x + 1)].
    half_width = depth * math.tan(math.radians(vfov) / 2.0) * width / height
    left = 0.3 + half_width * (np.arange(width) / width * 2.0 - 1.0)
    right = 0.3 + half_width * ((np.arange(width) + 1.0) / width * 2.0 - 1.0)
    covered = np.clip(-left / (right - left), 0.0, 1.0)  # the fraction of the column with x <= 0
    assert 0.0 < covered.max() - covered[covered < 1.0].max() < 1.0  # one column is partly covered
    expected = np.tile(1.0 - covered * (1.0 - c), (height, 1))

    # Per camera sample: hit with probability f, then the mean of r Bernoulli(c).
    f = np.tile(covered, (height, 1))
    second_moment = 1.0 - 2.0 * f * (1.0 - c) + f * ((1.0 - c) ** 2 + c * (1.0 - c) / r)
    variance = (second_moment - expected**2) / spp
    assert abs(result.ao.mean() - expected.mean()) <= 4.0 * math.sqrt(variance.sum()) / expected.size
    np.testing.assert_array_equal(result.mask, np.tile(covered > 0.0, (height, 1)))
