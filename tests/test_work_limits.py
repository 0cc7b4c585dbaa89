"""Work that would explode is refused before it starts, and long work can be
stopped: between tiles, by Ctrl-C or by the progress callback (issue 6)."""

import numpy as np
import pytest

import mbao
from interrupts import interrupt_after_the_first_tile


@pytest.fixture(scope="module")
def cornell():
    return mbao.cornell_box()


def branching_rays(width, height, samples, bounces, spp=1):
    """Camera rays plus r + r^2 + ... + r^b AO rays per camera sample: the most the branching estimator traces."""
    return width * height * spp * (1 + sum(samples**k for k in range(1, bounces + 1)))


def test_branching_work_beyond_the_default_limit_is_refused_and_the_path_estimator_suggested(cornell):
    rays = branching_rays(64, 64, samples=8, bounces=8)
    assert rays > mbao.DEFAULT_MAX_RAYS
    with pytest.raises(ValueError) as error:
        mbao.render(cornell, width=64, height=64, samples=8, bounces=8)
    message = str(error.value)
    assert f"would trace up to {rays} rays" in message
    assert f"more than max_rays={mbao.DEFAULT_MAX_RAYS}" in message
    assert 'estimator="path"' in message and "samples * bounces = 64" in message


def test_the_path_estimator_runs_what_branching_may_not(cornell):
    result = mbao.render(cornell, width=16, height=16, samples=8, bounces=8, estimator="path")
    assert result.stats["rays_primary"] + result.stats["rays_secondary"] <= 16 * 16 * (1 + 64)


def test_max_rays_is_the_exact_bound(cornell):
    settings = dict(width=16, height=16, samples=4, bounces=3)
    rays = branching_rays(16, 16, 4, 3)
    with pytest.raises(ValueError, match=f"would trace up to {rays} rays"):
        mbao.render(cornell, max_rays=rays - 1, **settings)
    result = mbao.render(cornell, max_rays=rays, **settings)
    assert result.stats["rays_primary"] + result.stats["rays_secondary"] <= rays


def test_a_limit_too_high_for_any_render_is_not_an_overflow(cornell):
    """r^b beyond 64 bits with a huge max_rays is refused by the per-pixel limit, not wrapped around."""
    with pytest.raises(ValueError, match="rays per pixel"):
        mbao.render(cornell, width=16, height=16, samples=2**20, bounces=16, max_rays=2**64 - 1)


@pytest.mark.parametrize(
    "value, error", [(0, ValueError), (-5, ValueError), (2**64, ValueError), (1.5, TypeError), ("many", TypeError)]
)
def test_bad_max_rays(cornell, value, error):
    with pytest.raises(error, match="max_rays"):
        mbao.render(cornell, width=8, height=8, max_rays=value)


def test_progress_is_called_after_every_tile(cornell):
    calls = []
    result = mbao.render(
        cornell, width=32, height=32, engine=mbao.Engine(tile_pixels=64), progress=lambda *a: calls.append(a)
    )
    tiles = result.stats["tiles"]
    assert tiles == 32 * 32 // 64
    assert calls == [(done, tiles) for done in range(1, tiles + 1)]


def test_progress_must_be_callable(cornell):
    with pytest.raises(TypeError, match="progress"):
        mbao.render(cornell, width=8, height=8, progress=5)


class Stop(Exception):
    pass


def test_an_exception_in_progress_stops_the_render_and_the_next_one_works(cornell):
    settings = dict(width=32, height=32, engine=mbao.Engine(tile_pixels=64), bounces=2)
    calls = []

    def stop_at_third_tile(done, total):
        calls.append(done)
        if done == 3:
            raise Stop

    with pytest.raises(Stop):
        mbao.render(cornell, progress=stop_at_third_tile, **settings)
    assert calls == [1, 2, 3]
    after = mbao.render(cornell, **settings)
    again = mbao.render(cornell, **settings)
    np.testing.assert_array_equal(after.ao, again.ao)


def test_ctrl_c_stops_the_render_between_tiles_and_the_next_one_works(cornell):
    """A real SIGINT, sent by another thread while a tile runs with the GIL
    released: only the render's own check between tiles can stop it early."""
    settings = dict(width=64, height=64, engine=mbao.Engine(tile_pixels=64), bounces=3, samples=8)
    tiles_done = interrupt_after_the_first_tile(lambda progress: mbao.render(cornell, progress=progress, **settings))
    total = 64 * 64 // 64
    assert set(tiles_done.values()) == {total}
    assert len(tiles_done) < total, "the render ran to its end before it saw the interrupt"
    small = dict(width=16, height=16, bounces=2)
    np.testing.assert_array_equal(mbao.render(cornell, **small).ao, mbao.render(cornell, **small).ao)
