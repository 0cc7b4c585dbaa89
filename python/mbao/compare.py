"""`python -m mbao compare`: the seed paper's Figure 2 for a scene, and its error-against-time study."""

import csv
import math
import pathlib

import numpy as np

from . import _core
from .convergence import convergence, format_convergence, plot_convergence
from .reference import reference
from .render import render

STUDY_METHODS = ["hbao", "b1", "b2 branching", "b2 path", "b1 + gtao fit", "hbao + gtao fit", "b2 branching + denoise"]


_RADIUS_SOURCES = {"settings": "--max-distance", "camera": "camera.json", "scene": "a quarter of the scene's diagonal"}


def ao_radius(scene, camera, max_distance):
    """(radius, where it came from): HBAO's radius by SPEC 1's rule, which every method of the comparison takes."""
    radius, source = _core.ao_radius(scene, camera, max_distance, "hbao")
    return radius, _RADIUS_SOURCES[source]


def short_name(scene):
    """The scene's name for a title: a loaded file's name without its folders, or the folder's name where the
    file is a generic scene.glb (the shared scenes' layout)."""
    path = pathlib.PurePath(scene.name)
    return path.parent.name if path.stem == "scene" and path.parent.name else path.stem


def figure2(scene, camera, radius, *, width, height, samples, rho, seed, device):
    """HBAO | 1 bounce | 2 bounces | 2 bounces minus 1 bounce, as one matplotlib figure."""
    import matplotlib.pyplot as plt

    common = dict(camera=camera, width=width, height=height, max_distance=radius, seed=seed, device=device)
    images = [
        ("HBAO", render(scene, method="hbao", **common)),
        ("1 bounce", render(scene, bounces=1, samples=samples, rho=rho, **common)),
        ("2 bounces", render(scene, bounces=2, samples=samples, rho=rho, **common)),
    ]
    # Four panels of one size, the difference's colour bar in a narrow fifth column.
    figure, axes = plt.subplots(
        1, 5, figsize=(16.6, 4.4 * height / width + 0.4), gridspec_kw=dict(width_ratios=[1, 1, 1, 1, 0.06])
    )
    for ax, (title, result) in zip(axes, images):
        ax.imshow(result.ao, cmap="gray", vmin=0.0, vmax=1.0)
        ax.set_title(f"{title} ({result.stats['frame_ms']:.1f} ms)")
    difference = images[2][1].ao - images[1][1].ao
    limit = max(float(np.abs(difference).max()), 1e-6)
    shown = axes[3].imshow(difference, cmap="coolwarm", vmin=-limit, vmax=limit)
    axes[3].set_title("2 bounces - 1 bounce")
    figure.colorbar(shown, cax=axes[4])
    for ax in axes[:4]:
        ax.set_axis_off()
    figure.suptitle(f"{short_name(scene)}, {width}x{height}, r = {samples}, radius {radius:g}")
    figure.tight_layout()
    return figure


def write_table(path, rows):
    rows = rows.to_dict("records") if hasattr(rows, "to_dict") else rows
    with open(path, "w", newline="") as file:
        writer = csv.DictWriter(file, fieldnames=list(rows[0]))
        writer.writeheader()
        writer.writerows(rows)
    return rows


def run(scene, camera, args, device, client=None):
    """Writes <output>_figure2.png, <output>_error_vs_time.png and .csv; returns the table's rows."""
    import matplotlib

    matplotlib.use("Agg")
    radius, source = ao_radius(scene, camera, args.max_distance)
    if not math.isfinite(radius):
        raise ValueError("--max-distance must be finite: it is HBAO's radius")
    print(f"radius       {radius:g} ({source})")
    size, progress = dict(width=args.width, height=args.height), False if args.quiet else None
    figure2(scene, camera, radius, samples=args.samples, rho=args.rho, seed=args.seed, device=device, **size).savefig(
        f"{args.output}_figure2.png", dpi=100
    )
    converged = reference(
        scene,
        camera=camera,
        bounces=2,
        rho=args.rho,
        max_distance=radius,
        target_error=args.target_error,
        device=device,
        progress=progress,
        client=client,
        **size,
    )
    table = convergence(
        scene,
        STUDY_METHODS,
        converged,
        sample_counts=args.sample_counts,
        seed=args.seed,
        device=device,
        progress=progress,
        plot=False,
        client=client,
    )
    figure = plot_convergence(table, title=f"{short_name(scene)}, {args.width}x{args.height}, 2-bounce reference")
    figure.savefig(f"{args.output}_error_vs_time.png", dpi=100)
    rows = write_table(f"{args.output}_error_vs_time.csv", table)
    print(
        f"reference    {converged.settings['passes']} passes of {converged.settings['samples']} paths, "
        f"{converged.settings['seconds']:.1f} s"
    )
    print(format_convergence(rows))
    print(f"wrote        {args.output}_figure2.png, {args.output}_error_vs_time.png, {args.output}_error_vs_time.csv")
    return rows
