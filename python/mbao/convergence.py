"""Error against run time: each method rendered at increasing cost and compared with a reference."""

import math
import time

import numpy as np

from . import _checks, _core
from ._progress import progress_bar
from .gtao import gtao_multibounce
from .reference import Reference, reference_camera
from .render import render
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
}


def _least_cost(name):
    """Denoised methods start at r = 2: with one direction a pixel has no
    variance for the filter to weigh by (SPEC 7.1)."""
    return 2 if METHODS[name].get("denoise") else 1


def convergence(scene, methods, reference, *, sample_counts=(1, 2, 4, 8, 16), time_budgets=None, seed=0,
                device=None, progress=True, plot=True, ax=None):
    """Renders each method at increasing cost and measures its error against `reference`.

    methods: names from mbao.convergence.METHODS ("hbao", "b1", "b2 branching",
        "b2 path", "b3 branching", "b3 path", "hbao + gtao fit", "b1 + gtao fit",
        "b1 + denoise", "b2 branching + denoise", "b2 path + denoise").
        Each renders the reference's camera, size, rho and max_distance (HBAO's radius).
        The denoised ones (SPEC 7.3) skip sample counts below 2.
    scene: as for mbao.render, a path included (loaded once for the whole study).
    reference: an mbao.Reference (mbao.reference or Reference.load).
    sample_counts: the costs of one render: samples r for the ray tracers, directions for HBAO.
    time_budgets: instead, milliseconds: each method averages renders at its
        first sample count, with new seeds, until each budget is spent, so that
        methods are compared at equal time.

    Returns one row per (method, cost): method, cost (r, directions or passes),
    frame_ms (the frames' steady-state time; the fit's own time added), rmse and
    bias (mean signed error) over the covered pixels, and noise_floor: the
    reference's own RMS standard error, below which no error can be resolved;
    with time_budgets also budget_ms (frame_ms is the time spent reaching it).
    A pandas DataFrame where pandas is installed, else a list of dicts. With plot,
    draws rmse against frame_ms on log-log axes (ax, or a new matplotlib figure).
    """
    if not isinstance(reference, Reference):
        raise TypeError(f"reference must be an mbao.Reference, got {type(reference).__name__}")
    scene = as_scene(scene)
    methods = _method_names(methods)
    rows = []
    renders = (len(methods) * len(time_budgets) if time_budgets is not None
               else sum(len(_affordable(name, sample_counts)) for name in methods))
    with progress_bar(_checks.boolean("progress", progress), renders, "convergence", "render") as bar:
        for name in methods:
            measure = _budgets if time_budgets is not None else _costs
            rows += measure(scene, name, reference, time_budgets or sample_counts, seed, device, bar)
    if plot:
        plot_convergence(rows, ax=ax)
    return _table(rows)


def _method_names(methods):
    if isinstance(methods, str):
        methods = [methods]
    methods = list(methods)
    for name in methods:
        _checks.choice("methods", name, tuple(METHODS))
    if not methods:
        raise ValueError("methods must name at least one method")
    return methods


def _render_once(scene, name, reference, cost, seed, device):
    """(image, ms) of one render of method `name` at `cost`."""
    s = reference.settings
    settings = dict(METHODS[name])
    gtao = settings.pop("gtao", False)
    if settings.get("method") == "hbao":
        settings["hbao"] = _hbao(cost)
    else:
        settings["samples"] = cost
        settings["rho"] = s["rho"]
    result = render(scene, camera=reference_camera(reference), width=s["width"], height=s["height"],
                    max_distance=s["max_distance"], seed=seed, device=device, **settings)
    image, ms = result.ao, result.stats["frame_ms"]
    if gtao:
        started = time.perf_counter()
        image = gtao_multibounce(image, s["rho"])
        ms += 1e3 * (time.perf_counter() - started)
    return image, ms


def _hbao(directions):
    return _core.HBAO(directions=directions)


def _affordable(name, costs):
    """The sample counts a method renders: those from its least cost on."""
    return [cost for cost in costs if _checks.integer("sample_counts", cost, 1) >= _least_cost(name)]


def _costs(scene, name, reference, costs, seed, device, bar):
    rows = []
    for cost in _affordable(name, costs):
        image, ms = _render_once(scene, name, reference, _checks.integer("sample_counts", cost, 1), seed, device)
        rows.append(_row(name, cost, ms, image, reference))
        _advance(bar)
    return rows


def _budgets(scene, name, reference, budgets, seed, device, bar):
    """Passes at HBAO's default directions or r = 4, averaged until each budget is spent."""
    cost = _core.HBAO().directions if METHODS[name].get("method") == "hbao" else 4
    rows, total, spent, passes = [], 0.0, 0.0, 0
    for budget in sorted(_checks.real("time_budgets", b) for b in budgets):
        while spent < budget or passes == 0:
            image, ms = _render_once(scene, name, reference, cost, seed + passes, device)
            total, spent, passes = total + image.astype(np.float64), spent + ms, passes + 1
        rows.append(dict(_row(name, passes, spent, total / passes, reference), budget_ms=budget))
        _advance(bar)
    return rows


def _row(name, cost, ms, image, reference):
    covered = reference.mask
    error = (image - reference.ao)[covered].astype(np.float64)
    noise = reference.standard_error[covered].astype(np.float64)
    return dict(method=name, cost=cost, frame_ms=ms, rmse=math.sqrt(np.mean(error**2)), bias=float(error.mean()),
                noise_floor=math.sqrt(np.mean(noise**2)))


def format_convergence(rows):
    """The rows as a fixed-width text table."""
    rows = rows.to_dict("records") if hasattr(rows, "to_dict") else list(rows)
    budgets = "budget_ms" in rows[0]
    lines = [f"{'method':<18}{'budget ms' if budgets else '':>10}{'cost':>6}{'frame ms':>11}{'rmse':>9}{'bias':>9}"]
    for row in rows:
        budget = f"{row['budget_ms']:>10g}" if budgets else " " * 10
        lines.append(f"{row['method']:<18}{budget}{row['cost']:>6}{row['frame_ms']:>11.2f}{row['rmse']:>9.4f}"
                     f"{row['bias']:>+9.4f}")
    lines.append(f"reference noise floor {rows[0]['noise_floor']:.4f}")
    return "\n".join(lines)


def _table(rows):
    try:
        import pandas
    except ImportError:
        return rows
    return pandas.DataFrame(rows)


def plot_convergence(rows, ax=None, title=None):
    """rmse against frame_ms, log-log, one line per method, the reference's noise floor dashed."""
    import matplotlib.pyplot as plt

    rows = rows.to_dict("records") if hasattr(rows, "to_dict") else list(rows)
    if ax is None:
        _, ax = plt.subplots(figsize=(6.4, 4.4))
    for name in dict.fromkeys(row["method"] for row in rows):
        mine = [row for row in rows if row["method"] == name]
        ax.loglog([r["frame_ms"] for r in mine], [r["rmse"] for r in mine], "o-", label=name)
    ax.axhline(rows[0]["noise_floor"], color="gray", linestyle="--", label="reference noise")
    ax.set_xlabel("frame time [ms]")
    ax.set_ylabel("RMSE against the reference")
    ax.set_title(title or "error against time")
    ax.legend(fontsize="small")
    return ax.figure


def _advance(bar):
    if bar is not None:
        bar.update(1)
