"""A pixel's variance (SPEC 7.1): the spread of its own samples, an unbiased
estimate of how much its value varies from seed to seed. Statistical checks
allow 4 standard errors, computed from the data's own spread."""

import math

import numpy as np
import pytest

import mbao
from meshes import plane

SIZE = 32


def render(**settings):
    settings = dict(dict(width=SIZE, height=SIZE, bounces=2, variance=True), **settings)
    return mbao.render(mbao.cornell_box(), **settings)


def test_one_bounce_is_the_spread_of_the_escapes():
    """At b = 1 each of the r directions is 1 (it escapes) or 0, so a pixel
    whose value is e / r has s^2 = (e - e^2 / r) / (r - 1), and variance s^2 / r."""
    r = 8
    result = render(bounces=1, samples=r)
    escapes = result.ao.astype(np.float64) * r
    assert np.allclose(escapes, np.round(escapes), atol=1e-4)
    expected = (escapes - escapes**2 / r) / (r - 1) / r
    np.testing.assert_allclose(result.variance, expected, atol=1e-6)
    assert (expected > 0).sum() > 100  # not vacuous


@pytest.mark.parametrize(
    "settings",
    [
        dict(estimator="branching", samples=4),
        dict(estimator="path", samples=4),
        dict(estimator="path", samples=1, spp=4),  # the spread of jittered camera samples
    ],
    ids=["branching", "path", "camera-samples"],
)
def test_the_variance_matches_the_spread_across_seeds(settings):
    """Over K seeds, each pixel's mean estimated variance m and the sample
    variance s^2 of its values both estimate the same variance: d = m - s^2 has
    mean 0, and the pixels are independent, so sum(d) / sqrt(sum(d^2)) is within 4."""
    seeds = 48
    renders = [render(seed=seed, **settings) for seed in range(seeds)]
    values = np.stack([r.ao for r in renders]).astype(np.float64)
    estimated = np.stack([r.variance for r in renders]).astype(np.float64)
    d = (estimated.mean(axis=0) - values.var(axis=0, ddof=1)).ravel()
    varied = d != 0
    assert varied.sum() > 500
    z = d[varied].sum() / math.sqrt((d[varied] ** 2).sum())
    assert abs(z) <= 4.0, z


@pytest.mark.parametrize("organisation", ["megakernel", "wavefront"])
def test_asking_for_the_variance_leaves_the_image_as_it_is(organisation):
    engine = mbao.Engine(organisation=organisation)
    with_variance = render(seed=3, engine=engine)
    without = mbao.render(mbao.cornell_box(), width=SIZE, height=SIZE, bounces=2, seed=3, engine=engine)
    np.testing.assert_array_equal(with_variance.ao, without.ao)
    assert without.variance is None


def test_open_surfaces_and_misses_have_no_variance():
    """A lone plane: every ray escapes, every value is exactly 1."""
    vertices, indices = plane(1.0)
    camera = mbao.Camera((0.0, 2.0, 1.0), (0.0, 0.0, 0.0), vfov_deg=60.0)
    result = mbao.render(mbao.Mesh(vertices, indices), camera=camera, width=SIZE, height=SIZE, bounces=2, variance=True)
    assert result.mask.any() and not result.mask.all()
    np.testing.assert_array_equal(result.variance, 0.0)


@pytest.mark.parametrize(
    "settings, message",
    [
        (dict(samples=1), "variance needs two samples"),
        (dict(method="hbao", bounces=1, max_distance=100.0), "HBAO has none"),
    ],
)
def test_a_variance_without_a_spread_is_refused(settings, message):
    with pytest.raises(ValueError, match=message):
        render(**settings)
