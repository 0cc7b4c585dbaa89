"""Error against run time: each method rendered at increasing cost and compared with a reference."""

import itertools
import math
import time
from typing import Any, Iterable, Optional, Sequence

import numpy as np

from . import _checks, _core
from ._progress import progress_count, progress_reporter
from ._types import DeviceLike, Progress, SceneLike
from .gtao import gtao_multibounce
from .reference import Reference, reference_camera
from .render import render, render_sequence
from .scene import as_scene

# What each method name renders, beyond the reference's camera, size, rho and max_distance.
# "cost" is what grows along a method's curve: samples r for the ray tracers, directions for HBAO.
METHODS = {
    "hbao": dict(method="hbao"),
    "b1": dict(bounces=1),
    "b2 branching": dict(bounces=2, estimator="branching"),
    "b2 path": dict(bounces=2, estimator="path"),
    "b3 branching": dict(bounces=3, estimator="branching"),
    "b3 path": dict(bounces=3, estimator="path"),
    "hbao + gtao fit": dict(method="hbao", gtao=True),
    "b1 + gtao fit": dict(bounces=1, gtao=True),
    "b1 + denoise": dict(bounces=1, denoise=True),
    "b2 branching + denoise": dict(bounces=2, estimator="branching", denoise=True),
    "b2 path + denoise": dict(bounces=2, estimator="path", denoise=True),
    # Frames of a still camera accumulated (SPEC 7.4): with time budgets or frame counts only.
    "b1 + temporal": dict(bounces=1, temporal=True),
    "b1 + temporal + denoise": dict(bounces=1, temporal=True, denoise=True),
    "b2 branching + temporal": dict(bounces=2, estimator="branching", temporal=True),
    "b2 branching + temporal + denoise": dict(bounces=2, estimator="branching", temporal=True, denoise=True),
}

# The side of the blocks whose mean error block_rmse takes: noise averages out
# over a block's 64 pixels, a filter's blur does not.
BLOCK = 8

# The samples r of the frames that time budgets and frame counts average.
FRAME_SAMPLES = 4


def _least_cost(name):
    """Denoised and accumulated methods start at r = 2: with one direction a
    pixel has no variance to weigh by (SPEC 7.1)."""
    return 2 if METHODS[name].get("denoise") or METHODS[name].get("temporal") else 1


def convergence(
    scene: SceneLike,
    methods: Iterable[str],
    reference: Reference,
    *,
    sample_counts: Sequence[int] = (1, 2, 4, 8, 16),
    time_budgets: Optional[Sequence[float]] = None,
    frame_counts: Optional[Sequence[int]] = None,
    seed: int = 0,
    device: DeviceLike = None,
    progress: Progress = None,
    plot: bool = True,
    ax: Any = None,
    client: Any = None,
) -> Any:
    """Renders each method at increasing cost and measures its error against `reference`.

    methods: names from mbao.convergence.METHODS ("hbao", "b1", "b2 branching",
        "b2 path", "b3 branching", "b3 path", "hbao + gtao fit", "b1 + gtao fit",
        "b1 + denoise", "b2 branching + denoise", "b2 path + denoise", "b1 + temporal",
        "b1 + temporal + denoise", "b2 branching + temporal", "b2 branching + temporal + denoise").
        Each renders the reference's camera, size, rho and max_distance (HBAO's radius).
        The denoised ones (SPEC 7.3) skip sample counts below 2. The "+ temporal"
        ones are the frames of a still camera's sequence (SPEC 7.4; the filter,
        where named, runs on each accumulated frame), so they need time_budgets
        or frame_counts.
    scene: as for mbao.render, a path included (loaded once for the whole study).
    reference: an mbao.Reference (mbao.reference or Reference.load).
    sample_counts: the costs of one render: samples r for the ray tracers, directions for HBAO.
    time_budgets: instead, milliseconds: each method renders frames (r = 4, or
        HBAO's default directions) with new seeds until each budget is spent, so
        that methods are compared at equal time. Its image is the frames' mean,
        or the last frame of a "+ temporal" sequence.
    frame_counts: instead, numbers of frames, as time_budgets' but counted.

    Returns one row per (method, cost): method, cost (r, directions or frames),
    frame_ms (the frames' steady-state time; the fit's own time added), rmse and
    bias (mean signed error) over the covered pixels, block_rmse (the RMS over
    8 x 8 blocks of their covered pixels' mean error: noise averages out in a
    block, a blur's error does not), and noise_floor: the reference's own RMS
    standard error, below which no error can be resolved; with time_budgets also
    budget_ms (frame_ms is the time spent reaching it).
    A pandas DataFrame where pandas is installed, else a list of dicts. With plot,
    draws rmse against frame_ms on log-log axes (ax, or a new matplotlib figure).

    progress: as for render, over the renders (a row each): None, a bar on a
        terminal for a study longer than a few seconds; False, none; True, a
        bar; or a callable progress(rows_done, rows_total).
    client: a dask.distributed.Client renders each method's rows on a worker
        (the scene sent to each once), the rows in the methods' order. Their
        images are those rendered here; their times are the workers' devices',
        and workers that share a machine's cores slow each other's frames.
    """
    if not isinstance(reference, Reference):
        raise TypeError(f"reference must be an mbao.Reference, got {type(reference).__name__}")
    scene = as_scene(scene)
    methods = _method_names(methods)
    if time_budgets is not None and frame_counts is not None:
        raise ValueError("give time_budgets or frame_counts, not both")
    stops = _stops(time_budgets, frame_counts)
    for name in methods:
        if METHODS[name].get("temporal") and stops is None:
            raise ValueError(
                f"method {name!r} accumulates the frames of a sequence: give time_budgets (ms) or "
                f"frame_counts, not sample counts"
            )
    rows = []
    renders = (
        len(methods) * len(stops)
        if stops is not None
        else sum(len(_affordable(name, sample_counts)) for name in methods)
    )
    with progress_reporter(progress, "convergence", "render", renders) as report:
        rows_done = progress_count(report, renders)
        if client is None:
            for name in methods:
                rows += _method_rows(scene, name, reference, sample_counts, stops, seed, device, rows_done)
        else:
            for method_rows in _rows_on(client, scene, methods, reference, sample_counts, stops, seed):
                rows += method_rows
                rows_done.advance(len(method_rows))
    if plot:
        plot_convergence(rows, ax=ax)
    return _table(rows)


def _method_rows(scene, name, reference, sample_counts, stops, seed, device=None, rows_done=None):
    if stops is None:
        return _costs(scene, name, reference, sample_counts, seed, device, rows_done)
    return _frames(scene, name, reference, stops, seed, device, rows_done)


def _rows_on(client, scene, methods, reference, sample_counts, stops, seed):
    """Each method's rows, rendered on the cluster's workers, in the methods' order."""
    from ._cluster import results_of, scene_for_workers  # only studies on a cluster need Dask

    on_cluster = scene_for_workers(client, scene, broadcast=True)
    return results_of(
        client, ((_method_rows, on_cluster, name, reference, sample_counts, stops, seed) for name in methods)
    )


def _method_names(methods):
    if isinstance(methods, str):
        methods = [methods]
    methods = list(methods)
    for name in methods:
        _checks.choice("methods", name, tuple(METHODS))
    if not methods:
        raise ValueError("methods must name at least one method")
    return methods


def _render_settings(name, reference, cost):
    """render's settings for method `name` at `cost` on the reference's view, and whether the GTAO fit follows."""
    s = reference.settings
    settings = dict(METHODS[name])
    settings.pop("temporal", None)
    gtao = settings.pop("gtao", False)
    if settings.get("method") == "hbao":
        settings["hbao"] = _hbao(cost)
    else:
        settings["samples"] = cost
        settings["rho"] = s["rho"]
    return dict(settings, width=s["width"], height=s["height"], max_distance=s["max_distance"]), gtao


def _render_once(scene, name, reference, cost, seed, device):
    """(image, ms) of one render of method `name` at `cost`."""
    settings, gtao = _render_settings(name, reference, cost)
    result = render(scene, camera=reference_camera(reference), seed=seed, device=device, progress=False, **settings)
    image, ms = result.ao, result.stats["frame_ms"]
    if gtao:
        started = time.perf_counter()
        image = gtao_multibounce(image, reference.settings["rho"])
        ms += 1e3 * (time.perf_counter() - started)
    return image, ms


def _hbao(directions):
    return _core.HBAO(directions=directions)


def _affordable(name, costs):
    """The sample counts a method renders: those from its least cost on."""
    return [cost for cost in costs if _checks.integer("sample_counts", cost, 1) >= _least_cost(name)]


def _costs(scene, name, reference, costs, seed, device, rows_done):
    rows = []
    for cost in _affordable(name, costs):
        image, ms = _render_once(scene, name, reference, _checks.integer("sample_counts", cost, 1), seed, device)
        rows.append(_row(name, cost, ms, image, reference))
        _advance(rows_done)
    return rows


def _stops(time_budgets, frame_counts):
    """Where a method's frames stop for a row: ("budget_ms", ms) or ("frames", count), in order; None for sample counts."""
    if time_budgets is not None:
        return [("budget_ms", b) for b in sorted(_checks.real("time_budgets", b) for b in time_budgets)]
    if frame_counts is not None:
        return [("frames", n) for n in sorted(_checks.integer("frame_counts", n, 1) for n in frame_counts)]
    return None


def _frames(scene, name, reference, stops, seed, device, rows_done):
    """A row at each stop of the method's frames, each the image so far and the time spent on it."""
    frames = (_sequence if METHODS[name].get("temporal") else _averaged)(scene, name, reference, seed, device)
    rows, spent, count = [], 0.0, 0
    for kind, stop in stops:
        while count == 0 or (spent < stop if kind == "budget_ms" else count < stop):
            image, ms = next(frames)
            spent, count = spent + ms, count + 1
        row = _row(name, count, spent, image, reference)
        rows.append(dict(row, budget_ms=stop) if kind == "budget_ms" else row)
        _advance(rows_done)
    return rows


def _frame_cost(name):
    return _core.HBAO().directions if METHODS[name].get("method") == "hbao" else FRAME_SAMPLES


def _averaged(scene, name, reference, seed, device):
    """(mean image so far, ms) of renders with seeds seed, seed + 1, ..."""
    total = 0.0
    for passes in itertools.count(1):
        image, ms = _render_once(scene, name, reference, _frame_cost(name), seed + passes - 1, device)
        total = total + image.astype(np.float64)
        yield total / passes, ms


def _sequence(scene, name, reference, seed, device):
    """(frame, ms) of a still camera's sequence with temporal accumulation (seeds seed, seed + 1, ...)."""
    settings, _ = _render_settings(name, reference, _frame_cost(name))
    for result in render_sequence(
        scene,
        itertools.repeat(reference_camera(reference)),
        temporal=True,
        seed=seed,
        device=device,
        progress=False,
        **settings,
    ):
        yield result.ao, result.stats["frame_ms"]


def _row(name, cost, ms, image, reference):
    covered = reference.mask
    error = (image - reference.ao)[covered].astype(np.float64)
    noise = reference.standard_error[covered].astype(np.float64)
    return dict(
        method=name,
        cost=cost,
        frame_ms=ms,
        rmse=math.sqrt(np.mean(error**2)),
        bias=float(error.mean()),
        block_rmse=_block_rmse(image - reference.ao, covered),
        noise_floor=math.sqrt(np.mean(noise**2)),
    )


def _block_rmse(error, covered):
    """The RMS over BLOCK x BLOCK blocks (those at the right and bottom edges
    smaller) of each block's mean error over its covered pixels."""
    height, width = error.shape
    padded = (-height % BLOCK, -width % BLOCK)
    sums, counts = (
        np.pad(np.where(covered, values, 0.0).astype(np.float64), [(0, padded[0]), (0, padded[1])])
        .reshape((height + padded[0]) // BLOCK, BLOCK, (width + padded[1]) // BLOCK, BLOCK)
        .sum(axis=(1, 3))
        for values in (error, 1.0)
    )
    means = sums[counts > 0] / counts[counts > 0]
    return math.sqrt(np.mean(means**2))


def format_convergence(rows: Any) -> str:
    """The rows as a fixed-width text table."""
    rows = rows.to_dict("records") if hasattr(rows, "to_dict") else list(rows)
    budgets = "budget_ms" in rows[0]
    width = max(18, 2 + max(len(row["method"]) for row in rows))
    lines = [
        f"{'method':<{width}}{'budget ms' if budgets else '':>10}{'cost':>6}{'frame ms':>11}{'rmse':>9}"
        f"{'bias':>9}{'8x8 rmse':>10}"
    ]
    for row in rows:
        budget = f"{row['budget_ms']:>10g}" if budgets else " " * 10
        lines.append(
            f"{row['method']:<{width}}{budget}{row['cost']:>6}{row['frame_ms']:>11.2f}{row['rmse']:>9.4f}"
            f"{row['bias']:>+9.4f}{row['block_rmse']:>10.4f}"
        )
    lines.append(f"reference noise floor {rows[0]['noise_floor']:.4f}")
    return "\n".join(lines)


def _table(rows):
    try:
        import pandas
    except ImportError:
        return rows
    return pandas.DataFrame(rows)


_ERROR_LABELS = {"rmse": "RMSE against the reference", "block_rmse": "RMSE of 8 x 8 block means", "bias": "|mean bias|"}


def plot_convergence(rows: Any, ax: Any = None, title: Optional[str] = None, error: str = "rmse") -> Any:
    """An error ("rmse", "block_rmse", or "bias", drawn as its magnitude)
    against frame_ms, log-log, one line per method, the reference's noise floor dashed."""
    import matplotlib.pyplot as plt

    _checks.choice("error", error, tuple(_ERROR_LABELS))
    rows = rows.to_dict("records") if hasattr(rows, "to_dict") else list(rows)
    if ax is None:
        _, ax = plt.subplots(figsize=(6.4, 4.4))
    for name in dict.fromkeys(row["method"] for row in rows):
        mine = [row for row in rows if row["method"] == name]
        ax.loglog([r["frame_ms"] for r in mine], [abs(r[error]) for r in mine], "o-", label=name)
    ax.axhline(rows[0]["noise_floor"], color="gray", linestyle="--", label="reference noise")
    ax.set_xlabel("frame time [ms]")
    ax.set_ylabel(_ERROR_LABELS[error])
    ax.set_title(title or "error against time")
    ax.legend(fontsize="small")
    return ax.figure


def _advance(rows_done):
    if rows_done is not None:  # a worker's rows are counted where they arrive
        rows_done.advance()
