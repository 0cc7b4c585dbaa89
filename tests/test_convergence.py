"""mbao.convergence: error against time for each method (issue 5)."""

import math

import matplotlib
import numpy as np
import pytest

import mbao

matplotlib.use("Agg")

SIZE = dict(width=24, height=24)


@pytest.fixture(scope="module")
def cornell():
    return mbao.cornell_box()


@pytest.fixture(scope="module")
def reference(cornell):
    return mbao.reference(cornell, bounces=2, max_distance=300.0, target_error=0.02, samples=32, progress=False, **SIZE)


def rows(table):
    return table.to_dict("records") if hasattr(table, "to_dict") else table


@pytest.fixture(scope="module")
def study(cornell, reference):
    methods = ["hbao", "b1", "b2 branching", "b2 path", "b1 + gtao fit"]
    return rows(mbao.convergence(cornell, methods, reference, sample_counts=(1, 8), progress=False, plot=False))


def covered(reference):
    return int(reference.mask.sum())


def test_one_row_per_method_and_cost(study):
    assert [(r["method"], r["cost"]) for r in study] == [
        (m, c) for m in ["hbao", "b1", "b2 branching", "b2 path", "b1 + gtao fit"] for c in (1, 8)
    ]
    for row in study:
        assert row["frame_ms"] > 0 and row["rmse"] >= abs(row["bias"]) >= 0


def test_noise_floor_is_the_references_rms_standard_error(study, reference):
    expected = math.sqrt(np.mean(reference.standard_error[reference.mask].astype(np.float64) ** 2))
    assert all(row["noise_floor"] == pytest.approx(expected) for row in study)


@pytest.mark.parametrize("method", ["b2 branching", "b2 path"])
def test_unbiased_estimators_have_no_bias_beyond_their_noise(study, reference, method):
    """Per-pixel errors are independent; their spread is at most the rmse, so
    the mean error's standard error is at most rmse / sqrt(pixels)."""
    for row in (r for r in study if r["method"] == method):
        assert abs(row["bias"]) <= 4 * row["rmse"] / math.sqrt(covered(reference))


@pytest.mark.parametrize("method", ["b2 branching", "b2 path"])
def test_more_samples_means_less_error(study, method):
    few, many = (r["rmse"] for r in study if r["method"] == method)
    assert many < few


def test_one_bounce_is_darker_than_two(study, reference):
    """With rho = 1, L_1 <= L_2 everywhere (SPEC 1): b1's error is a negative bias, well beyond its noise."""
    for row in (r for r in study if r["method"] == "b1"):
        assert row["bias"] < -4 * row["rmse"] / math.sqrt(covered(reference))


def test_equal_time_budgets_average_more_passes_for_more_time(cornell, reference):
    table = rows(
        mbao.convergence(cornell, ["b2 path"], reference, time_budgets=(1.0, 50.0), progress=False, plot=False)
    )
    short, long = table
    assert short["cost"] >= 1 and long["cost"] > short["cost"]
    assert long["frame_ms"] >= 50.0 and long["rmse"] < short["rmse"]


def test_plot_draws_one_line_per_method_and_the_noise_floor(cornell, reference):
    import matplotlib.pyplot as plt

    figure, ax = plt.subplots()
    mbao.convergence(cornell, ["b1", "hbao"], reference, sample_counts=(1, 2), progress=False, ax=ax)
    assert ax.get_xscale() == "log" and ax.get_yscale() == "log"
    assert [line.get_label() for line in ax.get_lines()] == ["b1", "hbao", "reference noise"]
    plt.close(figure)


def test_bad_convergence_arguments(cornell, reference):
    with pytest.raises(ValueError, match="methods must be one of"):
        mbao.convergence(cornell, ["b7"], reference, progress=False, plot=False)
    with pytest.raises(TypeError, match="mbao.Reference"):
        mbao.convergence(cornell, ["b1"], reference.ao, progress=False, plot=False)
    with pytest.raises(ValueError, match="at least one"):
        mbao.convergence(cornell, [], reference, progress=False, plot=False)


def test_hbao_needs_a_reference_with_a_finite_radius(cornell):
    unlimited = mbao.reference(cornell, target_error=0.2, samples=4, progress=False, width=8, height=8)
    with pytest.raises(ValueError, match="finite max_distance"):
        mbao.convergence(cornell, ["hbao"], unlimited, progress=False, plot=False)


def test_format_convergence_lists_every_row_and_the_noise_floor(study):
    text = mbao.format_convergence(study)
    lines = text.splitlines()
    assert len(lines) == 1 + len(study) + 1
    assert all(line.startswith(row["method"]) for line, row in zip(lines[1:], study))
    assert lines[-1] == f"reference noise floor {study[0]['noise_floor']:.4f}"


def test_denoised_methods_start_at_two_directions_and_cut_the_error(cornell, reference):
    """A denoised method skips r = 1 (no variance to weigh by, SPEC 7.1), and
    at r = 2 its error is below the raw method's at the same r."""
    table = rows(
        mbao.convergence(
            cornell,
            ["b2 branching", "b2 branching + denoise"],
            reference,
            sample_counts=(1, 2),
            progress=False,
            plot=False,
        )
    )
    assert [(r["method"], r["cost"]) for r in table] == [
        ("b2 branching", 1),
        ("b2 branching", 2),
        ("b2 branching + denoise", 2),
    ]
    assert table[2]["rmse"] < table[1]["rmse"]


def test_a_still_cameras_accumulated_frames_are_the_averaged_ones(cornell, reference):
    """Up to N frames, temporal accumulation of a still camera is the running
    mean (SPEC 7.4): the same rows as averaging renders with the same seeds."""
    table = rows(
        mbao.convergence(
            cornell,
            ["b2 branching", "b2 branching + temporal"],
            reference,
            frame_counts=(1, 3),
            progress=False,
            plot=False,
        )
    )
    assert [(r["method"], r["cost"]) for r in table] == [
        ("b2 branching", 1),
        ("b2 branching", 3),
        ("b2 branching + temporal", 1),
        ("b2 branching + temporal", 3),
    ]
    for averaged, accumulated in zip(table[:2], table[2:]):
        assert accumulated["rmse"] == pytest.approx(averaged["rmse"], abs=1e-6)
        assert accumulated["block_rmse"] == pytest.approx(averaged["block_rmse"], abs=1e-6)


def test_temporal_methods_need_frames_or_budgets(cornell, reference):
    with pytest.raises(ValueError, match="accumulates the frames of a sequence: give time_budgets"):
        mbao.convergence(cornell, ["b1 + temporal"], reference, progress=False, plot=False)
    with pytest.raises(ValueError, match="time_budgets or frame_counts, not both"):
        mbao.convergence(cornell, ["b1"], reference, time_budgets=(1.0,), frame_counts=(1,), progress=False, plot=False)


def test_block_error_keeps_a_shift_and_averages_out_alternating_noise():
    from mbao.convergence import _block_rmse

    covered = np.ones((20, 12), bool)  # blocks at the edges smaller
    assert _block_rmse(np.full((20, 12), 0.25), covered) == pytest.approx(0.25)
    checkerboard = 0.3 * (-1.0) ** np.add.outer(np.arange(20), np.arange(12))
    assert _block_rmse(checkerboard, covered) == pytest.approx(0.0, abs=1e-12)
    covered[:8, :8] = False  # an empty block is left out, not counted as no error
    assert _block_rmse(np.full((20, 12), 0.25), covered) == pytest.approx(0.25)


def test_plot_draws_the_bias_as_its_magnitude_and_names_its_errors(study):
    import matplotlib.pyplot as plt

    figure, ax = plt.subplots()
    mbao.plot_convergence(study, ax=ax, error="bias")
    line = ax.get_lines()[0]
    np.testing.assert_allclose(line.get_ydata(), [abs(r["bias"]) for r in study if r["method"] == line.get_label()])
    assert ax.get_ylabel() == "|mean bias|"
    plt.close(figure)
    with pytest.raises(ValueError, match="error must be one of"):
        mbao.plot_convergence(study, error="mse")


def test_a_progress_widget_that_cannot_be_made_falls_back_to_text(monkeypatch, capsys):
    """Debian's ipywidgets 6 lacks what tqdm's widget bar sets; the bar is then text."""
    import tqdm.auto

    from mbao._progress import progress_reporter

    def widget_bar(**arguments):
        raise AttributeError("'FloatProgress' object has no attribute 'style'")

    monkeypatch.setattr(tqdm.auto, "tqdm", widget_bar)
    with progress_reporter(True, "study", "render", 3) as report:
        report(1, 3)
    assert "1/3" in capsys.readouterr().err


def test_a_study_on_a_cluster_has_the_local_errors(cornell, reference, study, dask_client):
    """Each method's rows come from a worker: the same images, so the same
    errors, in the methods' order; only the times are the workers'."""
    methods = ["hbao", "b1", "b2 branching", "b2 path", "b1 + gtao fit"]
    on_cluster = rows(
        mbao.convergence(
            cornell, methods, reference, sample_counts=(1, 8), progress=False, plot=False, client=dask_client
        )
    )
    timeless = [{k: v for k, v in row.items() if k != "frame_ms"} for row in study]
    assert [{k: v for k, v in row.items() if k != "frame_ms"} for row in on_cluster] == timeless
    assert all(row["frame_ms"] > 0 for row in on_cluster)
