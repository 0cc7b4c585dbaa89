"""Frame time of two builds of mbao, as interleaved pairs.

A machine's speed drifts by the hour, so two builds are compared frame by frame:
two worker processes, one importing the mbao package at --old and one the package
at --new, render the same frame in turn (the order swapping every pair), and the
ratio new / old is the median of the pairs' ratios, with its quartiles. The two
images are compared first, by hash, and the traversal counts of each are printed.

Make the old build in a worktree of the commit before, e.g.
    git worktree add /tmp/before HEAD~1 && cd /tmp/before
    cmake -S . -B build -DCMAKE_BUILD_TYPE=Release -DMBAO_PYTHON_INPLACE=ON \
      -DMBAO_BUILD_TESTS=OFF -DMBAO_BUILD_BENCH=OFF && make -C build -j2
then, from this checkout after `make -C build`:
    .venv/bin/python bench/compare_builds.py --old /tmp/before/python --new python \
      --scene ../shared/scenes/sponza --bounces 1 --size 512 --pairs 8
(--method hbao compares HBAO frames, with the radius `python -m mbao compare` picks.)
One build with two traversals compares as two builds do, e.g. lanes against the full stack:
    .venv/bin/python bench/compare_builds.py --old python --new python --old-traversal stack \
      --new-traversal lanes --scene ../shared/scenes/sponza --bounces 1 --size 512 --pairs 8
--old-env and --new-env set an environment variable for one worker, e.g. POCL_AFFINITY=1.
"""

import argparse
import hashlib
import math
import os
import subprocess
import sys

import numpy as np


def worker(args):
    import mbao
    from mbao.compare import ao_radius

    scene = mbao.load(os.path.join(args.scene, "scene.glb"))
    camera = mbao.Camera.load(os.path.join(args.scene, "camera.json"))

    # HBAO's radius as `python -m mbao compare` picks it; the ray-traced frames unlimited, as in every build.
    options_for_method = {"max_distance": ao_radius(scene, camera, None)[0] if args.method == "hbao" else math.inf}

    def render(size, traversal_stats=False):
        engine = dict(traversal=args.traversal, traversal_stats=traversal_stats)
        # Builds from before mbao.Engine took the engine settings as keywords of render().
        engine = {"engine": mbao.Engine(**engine)} if hasattr(mbao, "Engine") else engine
        return mbao.render(
            scene,
            camera=camera,
            width=size,
            height=size,
            bounces=args.bounces,
            method=args.method,
            **options_for_method,
            **engine,
        )

    image = render(args.size).ao  # also the warm-up frame
    print(hashlib.sha1(image.tobytes()).hexdigest(), flush=True)
    for command in sys.stdin:
        if command.strip() == "counts":
            counts = render(64, traversal_stats=True).stats.get("traversal")  # builds before HBAO counted had none
            print(
                " ".join(f"{name}={value:.2f}" for name, value in counts.items()) if counts else "not counted",
                flush=True,
            )
        else:
            print(render(args.size).stats["frame_ms"], flush=True)


class Worker:
    def __init__(self, package, traversal, variables, args):
        command = [
            sys.executable,
            os.path.abspath(__file__),
            "--worker",
            "--scene",
            args.scene,
            "--bounces",
            str(args.bounces),
            "--size",
            str(args.size),
            "--traversal",
            traversal,
            "--method",
            args.method,
        ]
        environment = dict(os.environ, PYTHONPATH=os.path.abspath(package))
        environment.update(variable.split("=", 1) for variable in variables)
        self.process = subprocess.Popen(
            command, stdin=subprocess.PIPE, stdout=subprocess.PIPE, text=True, env=environment
        )
        self.image_hash = self._read()

    def _read(self):
        line = self.process.stdout.readline()
        if not line:
            raise SystemExit(f"a worker failed (exit code {self.process.wait()})")
        return line.strip()

    def ask(self, command):
        self.process.stdin.write(command + "\n")
        self.process.stdin.flush()
        return self._read()

    def close(self):
        self.process.stdin.close()
        self.process.wait()


def compare(args):
    old = Worker(args.old, args.old_traversal or args.traversal, args.old_env, args)
    new = Worker(args.new, args.new_traversal or args.traversal, args.new_env, args)
    print("images identical:", old.image_hash == new.image_hash)
    print("old counts:", old.ask("counts"))
    print("new counts:", new.ask("counts"))
    ratios = []
    for pair in range(args.pairs):
        times = {}
        for worker_ in (old, new) if pair % 2 == 0 else (new, old):
            times[worker_] = float(worker_.ask("frame"))
        ratios.append(times[new] / times[old])
        print(f"old {times[old]:.1f} ms, new {times[new]:.1f} ms, new / old {ratios[-1]:.3f}", flush=True)
    old.close()
    new.close()
    q1, median, q3 = np.percentile(ratios, [25, 50, 75])
    print(f"new / old: {median:.3f} [{q1:.3f}-{q3:.3f}] over {args.pairs} pairs")


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--old", help="directory holding the old build's mbao package")
    parser.add_argument("--new", help="directory holding the new build's mbao package")
    parser.add_argument("--scene", required=True, help="directory with scene.glb and camera.json")
    parser.add_argument("--bounces", type=int, default=1)
    parser.add_argument("--size", type=int, default=512, help="image width and height")
    parser.add_argument("--pairs", type=int, default=8)
    parser.add_argument("--traversal", default="auto")
    parser.add_argument(
        "--old-env",
        action="append",
        default=[],
        metavar="NAME=VALUE",
        help="an environment variable for the old worker only (repeatable)",
    )
    parser.add_argument(
        "--new-env",
        action="append",
        default=[],
        metavar="NAME=VALUE",
        help="an environment variable for the new worker only (repeatable)",
    )
    parser.add_argument("--old-traversal", help="the old worker's traversal (default: --traversal)")
    parser.add_argument("--new-traversal", help="the new worker's traversal (default: --traversal)")
    parser.add_argument("--method", default="raytraced", choices=["raytraced", "hbao"])
    parser.add_argument("--worker", action="store_true", help=argparse.SUPPRESS)
    args = parser.parse_args()
    if args.worker:
        worker(args)
    elif not (args.old and args.new):
        parser.error("--old and --new are required")
    else:
        compare(args)


if __name__ == "__main__":
    main()
