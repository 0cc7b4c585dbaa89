"""Converged references and the GTAO multi-bounce fit (issue 5)."""

import math

import numpy as np
import pytest

import mbao

SETTINGS = dict(width=24, height=24, bounces=2, max_distance=300.0)


@pytest.fixture(scope="module")
def cornell():
    return mbao.cornell_box()


@pytest.fixture(scope="module")
def converged(cornell):
    return mbao.reference(cornell, target_error=0.02, samples=32, progress=False, **SETTINGS)


def test_every_covered_pixel_reaches_the_target_error(converged):
    assert converged.settings["converged"]
    assert converged.settings["passes"] >= 8
    assert converged.standard_error[converged.mask].max() <= 0.02
    assert converged.ao.dtype == np.float32 and converged.ao.shape == (24, 24)


def test_reference_agrees_with_the_branching_estimator(cornell, converged):
    """Both estimate the same L_b (SPEC 2). Per pixel, the difference of two
    independent estimates has variance se_ref^2 + se_branching^2; averaged over
    the covered pixels (independent random numbers per pixel), the mean
    difference has a standard error sqrt(sum of those) / n."""
    image = mbao.render(cornell, camera=mbao.reference_camera(converged), samples=16, seed=1, **SETTINGS)
    passes = [
        mbao.render(cornell, camera=mbao.reference_camera(converged), samples=16, seed=2 + k, **SETTINGS).ao
        for k in range(4)
    ]
    branching_variance = np.var(passes, axis=0, ddof=1)  # per-pixel variance of one branching image
    mask = converged.mask
    difference = (image.ao - converged.ao)[mask].astype(np.float64)
    standard_error = math.sqrt(np.sum(converged.standard_error[mask] ** 2 + branching_variance[mask])) / mask.sum()
    assert abs(difference.mean()) <= 4 * standard_error


def test_save_and_load_keep_the_images_and_the_settings(tmp_path, converged):
    converged.save(tmp_path / "ref.exr")
    loaded = mbao.Reference.load(tmp_path / "ref.exr")
    np.testing.assert_array_equal(loaded.ao, converged.ao)
    np.testing.assert_array_equal(loaded.standard_error, converged.standard_error)
    np.testing.assert_array_equal(loaded.mask, converged.mask)
    assert loaded.settings == converged.settings
    assert loaded.settings["bounces"] == 2 and loaded.settings["scene"] == "cornell_box"


def test_a_plain_image_is_not_a_reference(tmp_path):
    mbao.save_image(tmp_path / "plain.exr", np.zeros((4, 4), np.float32))
    with pytest.raises(mbao.LoadError, match=r"plain\.exr.*not an mbao reference"):
        mbao.Reference.load(tmp_path / "plain.exr")


def test_reference_is_saved_as_exr_only(tmp_path, converged):
    with pytest.raises(ValueError, match=r"\.exr"):
        converged.save(tmp_path / "ref.png")


def test_unreachable_target_stops_at_max_passes_with_a_warning(cornell):
    with pytest.warns(UserWarning, match="after 3 passes"):
        result = mbao.reference(
            cornell, target_error=1e-9, min_passes=2, max_passes=3, progress=False, width=8, height=8, samples=4
        )
    assert result.settings["passes"] == 3 and not result.settings["converged"]


def test_progress_bar_can_be_turned_off(cornell, capsys):
    mbao.reference(cornell, target_error=0.5, width=8, height=8, samples=4, progress=False)
    captured = capsys.readouterr()
    assert captured.out == "" and captured.err == ""


def test_progress_bar_reports_passes(cornell, capsys):
    result = mbao.reference(cornell, target_error=0.5, width=8, height=8, samples=4, progress=True)
    assert f"{result.settings['passes']}/" in capsys.readouterr().err


@pytest.mark.parametrize(
    "arguments, error, message",
    [
        (dict(target_error=0), ValueError, "target_error"),
        (dict(target_error=-1), ValueError, "target_error"),
        (dict(min_passes=1), ValueError, "min_passes"),
        (dict(min_passes=8, max_passes=4), ValueError, "max_passes"),
        (dict(progress="yes"), TypeError, "progress"),
        (dict(width=0), ValueError, "width"),
    ],
)
def test_bad_reference_arguments(cornell, arguments, error, message):
    with pytest.raises(error, match=message):
        mbao.reference(cornell, **arguments)


# -- GTAO multi-bounce fit ---------------------------------------------------------------


def test_gtao_fit_is_jimenez_et_als_cubic():
    x = np.linspace(0, 1, 11)
    for rho in (0.0, 0.3, 0.8, 1.0):
        a, b, c = 2.0404 * rho - 0.3324, -4.7951 * rho + 0.6417, 2.7552 * rho + 0.6903
        expected = np.maximum(x, a * x**3 + b * x**2 + c * x)
        np.testing.assert_allclose(mbao.gtao_multibounce(x, rho), expected, rtol=1e-6)


def test_gtao_fit_never_darkens_and_keeps_open_surfaces_open():
    x = np.linspace(0, 1, 101)
    for rho in (0.0, 0.5, 1.0):
        assert np.all(mbao.gtao_multibounce(x, rho) >= x.astype(np.float32))
    # The fit's coefficients sum to ~1 at rho = 1: a fully open point stays at 1 (to the fit's 4 digits).
    assert mbao.gtao_multibounce(1.0, 1.0) == pytest.approx(1.0, abs=1e-3)


def test_gtao_fit_broadcasts_albedo_per_pixel():
    x = np.full((3, 4), 0.5)
    rho = np.linspace(0, 1, 4)
    out = mbao.gtao_multibounce(x, rho)
    assert out.shape == (3, 4) and out.dtype == np.float32
    np.testing.assert_allclose(out[0], [mbao.gtao_multibounce(0.5, r) for r in rho], rtol=1e-6)


@pytest.mark.parametrize(
    "x, rho, error",
    [
        (1.5, 0.5, ValueError),
        (0.5, -0.1, ValueError),
        (np.nan, 0.5, ValueError),
        (0.5, True, TypeError),
        ("a", 0.5, TypeError),
    ],
)
def test_gtao_fit_refuses_values_outside_the_unit_interval(x, rho, error):
    with pytest.raises(error):
        mbao.gtao_multibounce(x, rho)


# -- on a Dask cluster ------------------------------------------------------------------

FIXED_PASSES = dict(width=16, height=16, bounces=2, samples=8, min_passes=20, max_passes=20, progress=False)


def assert_same_reference(a, b):
    np.testing.assert_array_equal(a.ao, b.ao)
    np.testing.assert_array_equal(a.standard_error, b.standard_error)
    np.testing.assert_array_equal(a.mask, b.mask)
    assert a.settings["passes"] == b.settings["passes"]


@pytest.mark.filterwarnings("ignore:reference. after")
def test_a_reference_on_a_cluster_is_the_local_one_bit_for_bit(cornell, dask_client):
    # 20 passes: chunks of 8, 8 and 4, combined in that order on either side.
    assert_same_reference(
        mbao.reference(cornell, client=dask_client, **FIXED_PASSES), mbao.reference(cornell, **FIXED_PASSES)
    )


def test_a_reference_on_a_cluster_stops_where_the_local_one_does(cornell, dask_client):
    settings = dict(width=16, height=16, bounces=2, samples=8, target_error=0.03, progress=False)
    here = mbao.reference(cornell, **settings)
    assert here.settings["converged"] and here.settings["passes"] > 8  # more than one chunk
    assert_same_reference(mbao.reference(cornell, client=dask_client, **settings), here)


@pytest.mark.filterwarnings("ignore:reference. after")
def test_a_worker_killed_midway_costs_time_not_the_result(cornell, dask_client):
    import os
    import signal
    import threading
    import time

    settings = dict(width=64, height=64, bounces=2, samples=16, min_passes=64, max_passes=64, progress=False)
    outcome = {}
    run = threading.Thread(target=lambda: outcome.update(ref=mbao.reference(cornell, client=dask_client, **settings)))
    workers = dask_client.run(os.getpid)  # address: process id
    run.start()
    deadline = time.monotonic() + 60
    busy = []
    while not busy:  # the workers that hold a chunk
        assert time.monotonic() < deadline, "no chunk reached a worker"
        time.sleep(0.01)
        busy = [address for address, chunks in dask_client.processing().items() if chunks]
    alive_at_kill = run.is_alive()
    os.kill(workers[busy[0]], signal.SIGKILL)
    run.join(timeout=240)
    assert alive_at_kill and not run.is_alive(), "the kill must land while the reference runs"
    assert_same_reference(outcome["ref"], mbao.reference(cornell, **settings))
    dask_client.wait_for_workers(2, timeout=60)  # the nanny's new worker, for the tests after


@pytest.mark.filterwarnings("ignore:reference. after")
def test_the_client_keeps_running_sums_not_the_passes(cornell, dask_client):
    import tracemalloc

    # The client's own machinery takes 3-4 MB whatever the passes (measured at
    # 64 to 1024 passes of 64 x 64): the image is large enough for the passes,
    # kept, to take several times that.
    passes, side = 512, 128
    tracemalloc.start()
    try:
        mbao.reference(
            cornell,
            width=side,
            height=side,
            bounces=1,
            samples=1,
            min_passes=passes,
            max_passes=passes,
            progress=False,
            client=dask_client,
        )
        _, peak = tracemalloc.get_traced_memory()
    finally:
        tracemalloc.stop()
    every_pass = passes * side * side * 4  # what keeping each pass's float32 image would take
    assert peak < every_pass / 4, f"client peak {peak} bytes; every pass would be {every_pass}"
