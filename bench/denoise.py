"""Error against time of the raw, denoised and accumulated images (issue 39), against converged references.

From the repository root, after `make build`:
    .venv/bin/python bench/denoise.py --json bench/results/pocl-denoise.json
then `.venv/bin/python bench/report.py` puts its table into README.md and docs/performance.md.

For the Cornell box at b = 2 and Sponza at b = 1 with a 300-unit radius (512 x 512, r = 4, one camera sample
through each pixel centre), mbao.convergence measures, against a pixel-centre reference (mbao.reference,
cached as EXR under --cache): the raw image and the denoised one (one frame), and a still camera's sequence
with temporal accumulation, without and with the filter (frames 1, 4 and 16). Its rows give each one's
time, RMSE, mean bias and error in 8 x 8 blocks. The filter's share of a frame is the median of 5 renders'
stats["denoise_ms"] over frame_ms, after one to build the kernels.
"""

import argparse
import datetime
import json
import os
import pathlib
import statistics
import sys

import mbao
from mbao.convergence import FRAME_SAMPLES

REPO = pathlib.Path(__file__).resolve().parent.parent
SHARED = REPO.parent / "shared" / "scenes"

SIZE = 512
FRAMES = (1, 4, 16)
# name, scene, bounces, radius (None: the camera's), methods' prefix
SETUPS = [
    ("cornell_box", None, 2, None, "b2 branching"),
    ("sponza", SHARED / "sponza", 1, 300.0, "b1"),
]


def reference(name, scene, camera, bounces, radius, target_error, cache):
    """The converged image, read from the cache where a matching one is there."""
    path = pathlib.Path(cache) / f"{name}_b{bounces}_{SIZE}_{target_error:g}.exr"
    if path.exists():
        return mbao.Reference.load(path)
    converged = mbao.reference(
        scene, camera=camera, width=SIZE, height=SIZE, bounces=bounces, max_distance=radius, target_error=target_error
    )
    path.parent.mkdir(parents=True, exist_ok=True)
    converged.save(path)
    return converged


def denoise_share(scene, camera, bounces, radius):
    """Median denoise_ms and frame_ms of 5 denoised renders, after one that builds the kernels."""
    renders = [
        mbao.render(
            scene, camera=camera, width=SIZE, height=SIZE, bounces=bounces, max_distance=radius, denoise=True, seed=k
        ).stats
        for k in range(6)
    ][1:]
    return {
        "denoise_ms": statistics.median(s["denoise_ms"] for s in renders),
        "frame_ms": statistics.median(s["frame_ms"] for s in renders),
    }


def measure(setup, target_error, cache):
    name, folder, bounces, radius, prefix = setup
    scene = mbao.load(folder / "scene.glb") if folder else mbao.cornell_box()
    camera = mbao.Camera.load(folder / "camera.json") if folder else None
    converged = reference(name, scene, camera, bounces, radius, target_error, cache)
    single = mbao.convergence(scene, [prefix, prefix + " + denoise"], converged, frame_counts=(1,), plot=False)
    sequences = mbao.convergence(
        scene, [prefix + " + temporal", prefix + " + temporal + denoise"], converged, frame_counts=FRAMES, plot=False
    )
    rows = [
        dict(row)
        for table in (single, sequences)
        for row in (table.to_dict("records") if hasattr(table, "to_dict") else table)
    ]
    return {
        "scene": name,
        "bounces": bounces,
        "max_distance": radius if radius is not None else "camera",
        "size": SIZE,
        "samples": FRAME_SAMPLES,
        "rows": rows,
        "reference": converged.settings,
        "denoise": denoise_share(scene, camera, bounces, radius),
    }


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--json", required=True, help="where to write the results")
    parser.add_argument("--cache", default="out/references", help="where the references are kept")
    parser.add_argument("--target-error", type=float, default=0.01, help="the references' standard error per pixel")
    args = parser.parse_args()
    results = [measure(setup, args.target_error, args.cache) for setup in SETUPS]
    device = mbao.render(mbao.cornell_box(), width=1, height=1).stats["device"]  # as mbao_bench names it
    version = next(d.version for d in mbao.devices() if device.endswith(d.name))
    run = {
        "command": "bench/denoise.py " + " ".join(sys.argv[1:]),
        "device": device,
        "device_version": version,
        "date": datetime.date.today().isoformat(),
        "denoise": results,
    }
    pathlib.Path(args.json).write_text(json.dumps(run, indent=1) + "\n")
    print(f"wrote {os.path.relpath(args.json)}")


if __name__ == "__main__":
    main()
