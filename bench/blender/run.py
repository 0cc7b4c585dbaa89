"""Cycles' AO bake against mbao's Blender add-on (cycles_vs_mbao.py), in a
Blender whose user folder is a temporary one holding the add-on:

    .venv/bin/python bench/blender/run.py [--scene ../shared/scenes/damaged_helmet/scene.glb]

writes bench/results/pocl-blender.json; `bench/report.py` makes its table.
"""

import argparse
import datetime
import json
import os
import pathlib
import subprocess
import sys
import tempfile

HERE = pathlib.Path(__file__).resolve().parent
REPO = HERE.parents[1]


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--scene", default=str(REPO.parent / "shared/scenes/damaged_helmet/scene.glb"))
    parser.add_argument("--size", type=int, default=1024)
    parser.add_argument("--padding", type=int, default=4)
    parser.add_argument("--distance", type=float, default=0.5, help="the AO radius (the helmet's camera.json's)")
    parser.add_argument("--mbao-samples", type=int, default=64)
    parser.add_argument("--json", default=str(REPO / "bench/results/pocl-blender.json"))
    args = parser.parse_args()
    with tempfile.TemporaryDirectory(prefix="mbao-bench-blender-") as home:
        environment = dict(os.environ, BLENDER_USER_SCRIPTS=f"{home}/scripts", BLENDER_USER_CONFIG=f"{home}/config")
        subprocess.run([sys.executable, "-m", "mbao", "blender", "--install"], env=environment, check=True)
        subprocess.run(
            [
                "blender",
                "-b",
                "--python-exit-code",
                "1",
                "--python",
                str(HERE / "cycles_vs_mbao.py"),
                "--",
                args.scene,
                str(args.size),
                str(args.padding),
                str(args.distance),
                str(args.mbao_samples),
                args.json,
            ],
            env=environment,
            check=True,
        )
    result = json.loads(pathlib.Path(args.json).read_text())
    result.update(
        date=datetime.datetime.now(datetime.timezone.utc).isoformat(),
        command=" ".join([".venv/bin/python bench/blender/run.py"] + sys.argv[1:]),
    )
    pathlib.Path(args.json).write_text(json.dumps(result, indent=2) + "\n")


if __name__ == "__main__":
    main()
