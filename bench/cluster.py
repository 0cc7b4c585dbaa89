"""A reference here and on a Dask cluster of this machine's cores (issue 41): overhead, transfers, scaling.

From the repository root, after `make build`:
    .venv/bin/python bench/cluster.py --json bench/results/pocl-cluster.json
then `.venv/bin/python bench/report.py` puts its table into README.md and docs/performance.md.

A 64-pass reference (mbao.reference, min_passes = max_passes = 64) of Sponza at 256 x 256, b = 2, 32 paths
a pass, 300-unit radius, rendered here and on LocalClusters of 1 and 2 worker processes (one thread each)
on the same cores, in turns: here, 1 worker, 2 workers, repeated --rounds times. Each run starts from the
loaded scene with no tree, so each builds its trees (here one, on the cluster one per worker), and each
cluster is started before its clock starts. Every cluster run is checked to give the local image, bit for
bit. Bytes per pass: what the workers send back (each chunk's pickled moments) and what the client sends
them (the pickled scene, once per worker), over the passes.
"""

import argparse
import datetime
import json
import os
import pathlib
import pickle
import statistics
import sys
import time

import numpy as np

import mbao
from mbao.reference import _PASSES_PER_CHUNK, _chunk

REPO = pathlib.Path(__file__).resolve().parent.parent
SPONZA = REPO.parent / "shared" / "scenes" / "sponza"

PASSES = 64
SETTINGS = dict(
    width=256,
    height=256,
    bounces=2,
    samples=32,
    max_distance=300.0,
    min_passes=PASSES,
    max_passes=PASSES,
    progress=False,
)
WORKERS = (1, 2)


def timed_reference(client=None):
    """(seconds, Reference) of one reference on a freshly loaded scene."""
    scene = mbao.load(SPONZA / "scene.glb")
    camera = mbao.Camera.load(SPONZA / "camera.json")
    started = time.perf_counter()
    converged = mbao.reference(scene, camera=camera, client=client, **SETTINGS)
    return time.perf_counter() - started, converged


def bytes_per_pass(workers):
    """(from the workers, to the workers) per pass: the chunks' pickled moments, and the scene once per worker."""
    scene = mbao.load(SPONZA / "scene.glb")
    settings = dict(
        camera=mbao.Camera.load(SPONZA / "camera.json"),
        estimator="path",
        **{k: SETTINGS[k] for k in ("width", "height", "bounces", "samples", "max_distance")},
    )
    chunk = len(pickle.dumps(_chunk(scene, settings, 0, _PASSES_PER_CHUNK), protocol=pickle.HIGHEST_PROTOCOL))
    chunks = -(-PASSES // _PASSES_PER_CHUNK)
    scene_bytes = len(pickle.dumps(scene, protocol=pickle.HIGHEST_PROTOCOL))
    return chunk * chunks / PASSES, scene_bytes * workers / PASSES


def main():
    from distributed import Client, LocalCluster

    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--json", required=True, help="where to write the results")
    parser.add_argument("--rounds", type=int, default=3, help="turns of here, 1 worker, 2 workers")
    args = parser.parse_args()
    seconds = {"here": [], **{f"{n} workers": [] for n in WORKERS}}
    for _ in range(args.rounds):
        here, local = timed_reference()
        seconds["here"].append(here)
        for n in WORKERS:
            with LocalCluster(
                n_workers=n, threads_per_worker=1, processes=True, dashboard_address=None
            ) as cluster, Client(cluster) as client:
                taken, distributed = timed_reference(client)
            np.testing.assert_array_equal(distributed.ao, local.ao)
            np.testing.assert_array_equal(distributed.standard_error, local.standard_error)
            seconds[f"{n} workers"].append(taken)
    rows = []
    for n in WORKERS:
        ratios = [c / h for c, h in zip(seconds[f"{n} workers"], seconds["here"])]
        back, out = bytes_per_pass(n)
        rows.append(
            {
                "workers": n,
                "seconds": seconds[f"{n} workers"],
                "here_seconds": seconds["here"],
                "over_here": statistics.median(ratios),
                "over_here_all": ratios,
                "bytes_per_pass_from_workers": back,
                "bytes_per_pass_to_workers": out,
            }
        )
    device = mbao.render(mbao.cornell_box(), width=1, height=1).stats["device"]  # as mbao_bench names it
    version = next(d.version for d in mbao.devices() if device.endswith(d.name))
    run = {
        "command": "bench/cluster.py " + " ".join(sys.argv[1:]),
        "device": device,
        "device_version": version,
        "date": datetime.date.today().isoformat(),
        "cores": os.cpu_count(),
        "passes": PASSES,
        "settings": {k: v for k, v in SETTINGS.items() if k != "progress"},
        "cluster": rows,
    }
    pathlib.Path(args.json).write_text(json.dumps(run, indent=1) + "\n")
    print(json.dumps(rows, indent=1))
    print(f"wrote {os.path.relpath(args.json)}")


if __name__ == "__main__":
    main()
