"""The performance tables in README.md, docs/performance.md and docs/cluster.md, from bench/results/*.json.

    .venv/bin/python bench/report.py          # rewrites the tables in place
    .venv/bin/python bench/report.py --check  # exits 1, naming the table, where a committed one differs

bench/results/ holds one benchmark run per device class (mbao_bench --json; the
command that made each is in the file). A table sits in a Markdown file between
`<!-- report: KIND FILE -->` and `<!-- /report -->`, where FILE names a result
file without .json (or `all` for a table across the files) and KIND one of
TABLES below; everything between the two lines is this script's.
"""

import argparse
import json
import pathlib
import re
import statistics
import sys

REPO = pathlib.Path(__file__).resolve().parent.parent
RESULTS = REPO / "bench" / "results"
DOCUMENTS = [REPO / "README.md", REPO / "docs" / "performance.md", REPO / "docs" / "cluster.md"]

# The seed paper's Table 1 (RTX 2080 Ti, 512 x 512, r = 4): frame ms at b = 1 and 2.
PAPER_MS = {"cornell_box (built-in)": (1.5, 10.4), "sponza": (21.3, 147.5)}

BLOCK = re.compile(r"(<!-- report: (\w[\w-]*) ([\w.-]+) -->\n)(.*?)(<!-- /report -->)", re.S)


def load_results():
    runs = {}
    for path in sorted(RESULTS.glob("*.json")):
        if path.name != "latest.json":  # make bench's output, not committed
            runs[path.stem] = json.loads(path.read_text())
    return runs


def device_name(run):
    platform, _, name = run["device"].partition(": ")
    if platform == "Portable Computing Language":
        cpu = name.split("-")[-1]  # after PoCL's "pthread-<target>-"
        return "PoCL, " + " ".join(word for word in re.sub(r"\((R|TM)\)", "", cpu).split() if word != "Processor")
    return name


def ms(value):
    return f"{value:.1f}" if value >= 10 else f"{value:.2f}"


def table(header, rows):
    lines = [
        "| " + " | ".join(header) + " |",
        "|" + "|".join("---:" if h.endswith(("ms", "/s", "ratio")) else "---" for h in header) + "|",
    ]
    lines += ["| " + " | ".join(str(cell) for cell in row) + " |" for row in rows]
    return lines


def frame(result, bounces):
    return next(f for f in result["frames"] if f["bounces"] == bounces)


def unlimited(run):
    return [r for r in run["results"] if r["max_distance"] == "inf"]


def embree_ratio(run, scene, bounces):
    for row in run.get("embree", []):
        if row["scene"] == scene and row["bounces"] == bounces:
            return f"{row['rays_per_s_ratio']:.2f}"
    return ""


def summary(runs):
    """README: Table 1 at max_distance = inf, b = 1 and 2, on each device, beside the paper."""
    runs = {name: run for name, run in runs.items() if "results" in run}  # runs of other sections alone
    header = ["scene", "b"] + [f"{device_name(run)} ms" for run in runs.values()]
    with_embree = [name for name, run in runs.items() if run.get("embree")]
    header += [f"{device_name(runs[name])}: mbao / Embree rays/s" for name in with_embree]
    header += ["paper, RTX 2080 Ti ms"]
    first = next(iter(runs.values()))
    rows = []
    for result in unlimited(first):
        scene = result["scene"]
        for b in (1, 2):
            row = [scene, b]
            for run in runs.values():
                match = [r for r in unlimited(run) if r["scene"] == scene]
                row.append(ms(frame(match[0], b)["frame_ms"]) if match else "")
            row += [embree_ratio(runs[name], scene, b) for name in with_embree]
            row.append(PAPER_MS[scene][b - 1] if scene in PAPER_MS else "")
            rows.append(row)
    return table(header, rows)


def sources(runs):
    """Which device, day and command each result file comes from."""
    lines = []
    for name, run in runs.items():
        lines.append(
            f"* `bench/results/{name}.json`: {run['device']} ({run['device_version']}), "
            f"{run['date'][:10]}: `{run['command']}`"
        )
    return lines


def table1(run):
    """Table 1's workload, and HBAO beside it (the paper's SSAO column) where the run measured it."""
    with_hbao = all("hbao" in r for r in run["results"])
    header = ["scene", "triangles", "max_distance", "build ms", "b=1 ms", "b=2 ms", "b=1 Mrays/s", "b=2 Mrays/s"]
    header += ["HBAO ms", "of which G-buffer ms", "HBAO / b=1 ratio"] if with_hbao else []
    rows = []
    for r in run["results"]:
        f1, f2 = frame(r, 1), frame(r, 2)
        row = [
            r["scene"],
            r["triangles"],
            r["max_distance"],
            ms(r["build_ms"]),
            ms(f1["frame_ms"]),
            ms(f2["frame_ms"]),
            f"{f1['mrays_per_s']:.1f}",
            f"{f2['mrays_per_s']:.1f}",
        ]
        if with_hbao:
            hbao = r["hbao"]
            row += [ms(hbao["frame_ms"]), ms(hbao["gbuffer_ms"]), f"{hbao['frame_ms'] / f1['frame_ms']:.2f}"]
        rows.append(row)
    return table(header, rows)


def embree(run):
    header = ["scene", "b", "mbao ms", "Embree single rays ms", "Embree packets of 16 ms", "rays/s ratio"]
    rows = [
        [
            row["scene"],
            row["bounces"],
            ms(row["mbao"]["frame_ms"]),
            ms(row["embree_single_rays"]["frame_ms"]),
            ms(row["embree_packets16"]["frame_ms"]),
            f"{row['rays_per_s_ratio']:.2f}",
        ]
        for row in run["embree"]
    ]
    return table(header, rows)


def trees(run):
    header = ["scene", "nodes", "leaves (empty)", "depth", "triangles per leaf", "leaf references", "SAH cost", "MiB"]
    rows = []
    for r in run["results"]:
        t = r["tree"]
        if r["max_distance"] != "inf":
            continue
        rows.append(
            [
                r["scene"],
                t["nodes"],
                f"{t['leaves']} ({t['empty_leaves']})",
                t["max_depth"],
                f"{t['mean_triangles_per_leaf']:.2f}",
                t["leaf_references"],
                f"{t['sah_cost']:.1f}",
                f"{t['memory_bytes'] / 2**20:.1f}",
            ]
        )
    return table(header, rows)


def kd_build(run):
    header = [
        "scene",
        "tree",
        "build ms",
        "nodes",
        "leaf references",
        "SAH cost",
        "nodes per ray",
        "leaves per ray",
        "triangle tests per ray",
    ]
    rows = []
    for scene in run["kd_build"]:
        for t in scene["trees"]:
            s, p = t["stats"], t["per_ray"]
            rows.append(
                [
                    scene["scene"],
                    t["tree"],
                    ms(t["build_ms"]),
                    s["nodes"],
                    s["leaf_references"],
                    f"{s['sah_cost']:.2f}",
                    f"{p['nodes_per_ray']:.2f}",
                    f"{p['leaves_per_ray']:.2f}",
                    f"{p['triangles_per_ray']:.2f}",
                ]
            )
    return table(header, rows)


def traversals(run):
    header = [
        "scene",
        "traversal",
        "b=2 ms",
        "nodes per ray",
        "leaves per ray",
        "triangle tests per ray",
        "restarts per ray",
    ]
    rows = [
        [
            row["scene"],
            row["traversal"],
            ms(row["frames"]["frame_ms"]),
            f"{row['per_ray']['nodes_per_ray']:.1f}",
            f"{row['per_ray']['leaves_per_ray']:.1f}",
            f"{row['per_ray']['triangles_per_ray']:.1f}",
            f"{row['per_ray']['restarts_per_ray']:.2f}",
        ]
        for row in run["traversals"]
    ]
    return table(header, rows)


def profile(run):
    """Each frame's commands (kernels, fills, read-backs) by device time and the device's idle time before each,
    from OpenCL's profiling events, and what they leave of its wall time: means over the same frames. A run from
    before the idle times were kept (and read-backs and fills timed) shows the commands' device times alone."""
    with_idle = all("idle_before_ms_per_frame" in c for row in run["profile"] for c in row["frames"]["commands"])

    def idle(command):
        return command["idle_before_ms_per_frame"] if with_idle else 0.0

    def shown(command):
        device = f"`{command['command']}` {command['device_ms_per_frame']:.2f}"
        return f"{device} ({idle(command):.2f})" if with_idle else device

    rest = (
        "the host before the first command and after the last ms"
        if with_idle
        else "the rest (launches, waits; read-backs where not listed) ms"
    )
    commands = (
        "commands, device ms per frame (the device idle before each, ms)"
        if with_idle
        else "commands, device ms per frame"
    )
    rows = []
    for row in run["profile"]:
        frame_ms = statistics.fmean(row["frames"]["frame_ms_all"])
        spent = sum(c["device_ms_per_frame"] + idle(c) for c in row["frames"]["commands"])
        rows.append(
            [
                row["scene"],
                row["frame"],
                ms(frame_ms),
                ", ".join(shown(c) for c in row["frames"]["commands"]),
                ms(frame_ms - spent),
            ]
        )
    return table(["scene", "frame", "frame ms", commands, rest], rows)


def organisation(run):
    header = [
        "scene",
        "max_distance",
        "b",
        "work group",
        "megakernel ms",
        "wavefront ms",
        "wavefront / megakernel ratio",
        "same image",
    ]
    rows = [
        [
            row["scene"],
            row["max_distance"],
            row["bounces"],
            row["work_group_size"],
            ms(row["megakernel_ms"]),
            ms(row["wavefront_ms"]),
            f"{row['wavefront_over_megakernel']:.2f}",
            "yes" if row["same_image"] else "NO",
        ]
        for row in run["organisation"]
    ]
    return table(header, rows)


def bake(run):
    header = [
        "scene",
        "max_distance",
        "estimator",
        "render Mrays/s",
        "render AO Mrays/s",
        "vertex estimates",
        "vertex bake Mrays/s",
        "texture bake Mrays/s",
        "render AO / vertex ratio",
        "render AO / texture ratio",
        "texture bake ms",
        "UVs and layout ms",
        "tracing ms",
        "dilation ms",
        "generated UVs: texels covered",
    ]
    rows = []
    for row in run["bake"]:
        render, vertex = row["render"]["ao_mrays_per_s"], row["vertex_bake"]["mrays_per_s"]
        cells = [
            row["scene"],
            row["max_distance"],
            row["estimator"],
            f"{row['render']['mrays_per_s']:.1f}",
            f"{render:.1f}",
            row["vertex_bake"]["samples"],
            f"{vertex:.1f}",
        ]
        t = row.get("texture_bake")
        if t is None:  # the texture bake runs with the bakes' default estimator only
            cells += ["", f"{render / vertex:.2f}", "", "", "", "", "", ""]
        else:
            covered = t.get("texels_covered")  # runs before outline packing did not record it
            cells += [
                f"{t['mrays_per_s']:.1f}",
                f"{render / vertex:.2f}",
                f"{render / t['mrays_per_s']:.2f}",
                ms(t["total_ms"]),
                ms(t["uv_ms"]),
                ms(t["frame_ms"]),
                ms(t["dilation_ms"]),
                "" if covered is None else f"{covered:.2f}",
            ]
        rows.append(cells)
    return table(header, rows)


def uv_coverage(run):
    """Generated UVs by texture side, padding 4: the mean over materials of the fraction of texels covered, and charts."""
    header, rows = ["scene"], []
    for row in run["bake"]:
        t = row.get("texture_bake")
        if t is None or "uv_coverage" not in row:  # runs before smaller sides were measured
            continue
        sides = row["uv_coverage"] + [{"side": t["side"], "texels_covered": t["texels_covered"], "charts": t["charts"]}]
        header = ["scene"] + [f"{s['side']}²: texels covered (charts)" for s in sides]
        rows.append([row["scene"]] + [f"{s['texels_covered']:.2f} ({s['charts']})" for s in sides])
    return table(header, rows)


def scale(run):
    """mbao_bench --sections scale: build, frame and peak memory as the generated scene grows, beside Embree."""
    header = [
        "triangles",
        "mbao build ms",
        "Embree build ms",
        "build ratio",
        "Embree build ms, not robust",
        "build ratio, not robust",
        "frame ms",
        "peak bytes per triangle, built",
        "peak MiB, rendered",
        "peak bytes per triangle, rendered",
    ]
    rows = []
    for row in run["scale"]:
        embree = "rounds" in row  # build times and ratios: the medians of the rounds
        rows.append(
            [row["triangles"], ms(row["rounds_build_ms" if embree else "build_ms"])]
            + (
                [
                    ms(row["embree_build_ms"]),
                    f"{row['build_ratio']:.2f}",
                    ms(row["embree_not_robust_build_ms"]),
                    f"{row['build_ratio_not_robust']:.2f}",
                ]
                if embree
                else ["", "", "", ""]
            )
            + [
                ms(row["frame_ms"]),
                f"{row['build_peak_bytes_per_triangle']:.0f}",
                f"{row['peak_rss_kb'] / 1024:.0f}",
                f"{row['peak_bytes_per_triangle']:.0f}",
            ]
        )
    return table(header, rows)


def denoise(run):
    """bench/denoise.py's rows: each image's error against the reference, and the time spent on its frames."""
    header = ["scene", "b", "method", "frames", "all frames ms", "RMSE", "mean bias", "8x8 block RMSE"]
    rows = [
        [
            result["scene"],
            result["bounces"],
            row["method"],
            row["cost"],
            ms(row["frame_ms"]),
            f"{row['rmse']:.3f}",
            f"{row['bias']:+.4f}",
            f"{row['block_rmse']:.3f}",
        ]
        for result in run["denoise"]
        for row in result["rows"]
    ]
    return table(header, rows)


def denoise_summary(run):
    """README: raw, denoised, and 16 frames accumulated, with the filter's share of a frame."""
    header = [
        "scene",
        "b",
        "raw RMSE",
        "denoised RMSE",
        "16 frames RMSE",
        "16 frames + denoise RMSE",
        "denoising / frame ratio",
        "reference noise",
    ]
    rows = []
    for result in run["denoise"]:
        rmse = {
            (row["method"].split(" + ", 1)[1] if " + " in row["method"] else "raw", row["cost"]): row["rmse"]
            for row in result["rows"]
        }
        cost = result["denoise"]
        rows.append(
            [result["scene"], result["bounces"]]
            + [f"{rmse[key]:.3f}" for key in (("raw", 1), ("denoise", 1), ("temporal", 16), ("temporal + denoise", 16))]
            + [f"{cost['denoise_ms'] / cost['frame_ms']:.2f}", f"{result['rows'][0]['noise_floor']:.3f}"]
        )
    return table(header, rows)


def cluster(run):
    """bench/cluster.py: a reference here and on LocalClusters of this machine's cores, medians of the rounds."""
    header = [
        "workers",
        "here s",
        "cluster s",
        "cluster / here",
        "bytes per pass, from workers",
        "bytes per pass, to workers",
    ]
    rows = [
        [
            row["workers"],
            f"{statistics.median(row['here_seconds']):.1f}",
            f"{statistics.median(row['seconds']):.1f}",
            f"{row['over_here']:.2f}",
            f"{row['bytes_per_pass_from_workers']:,.0f}",
            f"{row['bytes_per_pass_to_workers']:,.0f}",
        ]
        for row in run["cluster"]
    ]
    return table(header, rows)


def viewer(run):
    """bench/viewer.py: the live view in headless Chromium, each figure beside its target, met or not."""
    targets, scenes, still = run["targets"], run["viewer"]["motion"], run["viewer"]["still"]

    def judged(text, met):
        return f"{text}, {'met' if met else 'not met'}"

    def latency(figures, median, p90):
        return judged(f"{figures[median]:.0f} ({figures[p90]:.0f})", figures[median] <= targets["input_to_frame_ms"])

    def fps(scene):
        return judged(f"{scene['drag']['fps']:.1f}", scene["drag"]["fps"] >= targets["drag_fps"])

    def size(scene):
        return f"{scene['drag']['median_width']:.0f} px, {ms(scene['drag']['median_frame_ms'])} ms"

    def still_only(text):
        return lambda scene: text if scene["scene"] == still["scene"] else ""

    reached, last = still["seconds_to_target"], still["frames"][-1]
    until = (
        judged(f"{reached:.2f}", reached <= targets["rmse_within_s"])
        if reached is not None
        else f"not within {still['seconds']:g} s, not met"
    )
    at_end = judged(f"{still['rmse_at_end']:.3f} ({last['frames']} frames)", still["rmse_at_end"] <= targets["rmse"])
    measures = [
        ("frames/s while dragging", f">= {targets['drag_fps']}", fps),
        ("while dragging, a frame's median width and frame_ms", "", size),
        (
            "input to frame, single moves: median (90th percentile) ms",
            f"<= {targets['input_to_frame_ms']}",
            lambda scene: latency(scene["input_to_frame"], "median_ms", "p90_ms"),
        ),
        (
            "input to frame while dragging: median (90th percentile) ms",
            f"<= {targets['input_to_frame_ms']}",
            lambda scene: latency(scene["drag"], "latency_median_ms", "latency_p90_ms"),
        ),
        (f"still view: s until RMSE <= {targets['rmse']}", f"<= {targets['rmse_within_s']}", still_only(until)),
        (f"still view: RMSE at {still['seconds']:g} s", f"<= {targets['rmse']}", still_only(at_end)),
        ("still view: the reference's own RMS standard error", "", still_only(f"{still['reference_noise']:.4f}")),
    ]
    rows = [[measure, target] + [cell(scene) for scene in scenes] for measure, target, cell in measures]
    return table(["measure", "target"] + [scene["scene"] for scene in scenes], rows)


def blender(run):
    """bench/blender/run.py: Cycles' AO bake and mbao's add-on in one Blender, at one RMS standard error."""
    cycles, b1, b2 = run["cycles"], run["mbao_b1"], run["mbao_b2"]
    # Cycles counts no rays: one per sample per texel it bakes, the compared ones (their centres on a triangle).
    cycles_mrays = cycles["samples"] * run["compared_texels"] / cycles["seconds"] / 1e6
    rows = [
        [
            "Cycles, bake type AO",
            1,
            cycles["samples"],
            f"{cycles['rms_standard_error']:.4f}",
            f"{cycles['seconds']:.1f}",
            "",
            f"{cycles_mrays:.1f}",
            f"{cycles['mean']:.3f}",
        ],
        [
            "mbao add-on",
            1,
            b1["samples"],
            f"{b1['rms_standard_error']:.4f}",
            f"{b1['seconds']:.1f}",
            f"{b1['tracing_seconds']:.1f}",
            f"{b1['mrays_per_s']:.1f}",
            f"{b1['mean']:.3f}",
        ],
        [
            "mbao add-on",
            2,
            b2["samples"],
            f"{b2['rms_standard_error']:.4f}",
            f"{b2['seconds']:.1f}",
            "",
            "",
            f"{b2['mean']:.3f}",
        ],
    ]
    d = run["b1_difference"]
    header = ["baker", "b", "samples", "RMS standard error", "s", "tracing s", "Mrays/s", "mean"]
    return table(header, rows) + [
        "",
        f"{run['scene']}, {run['triangles']} triangles, {run['size']} x {run['size']}, padding "
        f"{run['padding']}, AO distance {run['distance']:g}, Blender {run['blender']}, {run['cores']} cores of "
        f"{run['cpu']}; mbao on {device_name(run)}. Cycles' error falls as samples^-{cycles['error_order']:.2f}; "
        f"its rays are one per sample per texel it bakes. At b = 1, mbao - Cycles over the "
        f"{run['compared_texels']:,} texels both estimate: mean {d['mean']:+.4f} (RMS {d['rms']:.4f}); "
        f"z = difference / its standard error: mean {d['mean_z']:+.2f}, RMS {d['rms_z']:.2f}, "
        f"|z| > 4 for {d['beyond_4_sigma']:.1%} of the texels.",
    ]


TABLES = {
    "table1": table1,
    "embree": embree,
    "trees": trees,
    "kd-build": kd_build,
    "traversals": traversals,
    "profile": profile,
    "organisation": organisation,
    "bake": bake,
    "uv-coverage": uv_coverage,
    "denoise": denoise,
    "denoise-summary": denoise_summary,
    "scale": scale,
    "cluster": cluster,
    "viewer": viewer,
    "blender": blender,
}
ACROSS_FILES = {"summary": summary, "sources": sources}


def render(kind, file, runs):
    if file == "all":
        if kind not in ACROSS_FILES:
            raise SystemExit(f"report: no table '{kind}' across files; known: {', '.join(ACROSS_FILES)}")
        lines = ACROSS_FILES[kind](runs)
    else:
        if file not in runs:
            raise SystemExit(f"report: no bench/results/{file}.json; there are: {', '.join(runs)}")
        if kind not in TABLES:
            raise SystemExit(f"report: no table '{kind}'; known: {', '.join(TABLES)}")
        lines = TABLES[kind](runs[file])
    return "\n".join(lines) + "\n"


def regenerate(text, runs):
    """The text with every report block rewritten; [(kind, file)] of the blocks that changed."""
    changed = []

    def fill(match):
        opening, kind, file, old, closing = match.groups()
        new = render(kind, file, runs)
        if new != old:
            changed.append((kind, file))
        return opening + new + closing

    return BLOCK.sub(fill, text), changed


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--check", action="store_true", help="change nothing; exit 1 where a table is out of date")
    args = parser.parse_args()
    runs = load_results()
    stale = []
    for path in DOCUMENTS:
        text, changed = regenerate(path.read_text(), runs)
        stale += [f"{path.relative_to(REPO)}: {kind} {file}" for kind, file in changed]
        if changed and not args.check:
            path.write_text(text)
    if args.check and stale:
        print("out of date (run bench/report.py):\n  " + "\n  ".join(stale), file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
