"""HBAO's frame against a ray-traced b = 1 frame of the same scene, radius and size, interleaved.

Issue 42's measure of screen-space cost: HBAO (8 directions x 6 steps, G-buffer included) over the
ray-traced frame (b = 1, r = 4), frame by frame in one process, as the median of the pairs' ratios
with its quartiles, beside the median frame times and HBAO's G-buffer share. A scene is a directory
with scene.glb and camera.json, and a radius in world units:

    .venv/bin/python bench/hbao_share.py ../shared/scenes/cornell_box:140 ../shared/scenes/sponza:300
"""

import argparse
import os
import statistics

import mbao


def share(folder, radius, size, pairs):
    scene = mbao.load(os.path.join(folder, "scene.glb"))
    camera = mbao.Camera.load(os.path.join(folder, "camera.json"))
    common = dict(camera=camera, width=size, height=size, max_distance=radius)
    hbao_frame = dict(common, method="hbao")
    traced_frame = dict(common, bounces=1, samples=4)
    mbao.render(scene, **hbao_frame)  # kernels built, tree built
    mbao.render(scene, **traced_frame)
    hbao, traced = [], []
    for _ in range(pairs):
        hbao.append(mbao.render(scene, **hbao_frame).stats)
        traced.append(mbao.render(scene, **traced_frame).stats)
    ratios = [h["frame_ms"] / t["frame_ms"] for h, t in zip(hbao, traced)]
    q1, median, q3 = statistics.quantiles(ratios, n=4)
    print(
        f"{os.path.basename(os.path.normpath(folder))}, radius {radius:g}: "
        f"HBAO {statistics.median(h['frame_ms'] for h in hbao):.1f} ms "
        f"(G-buffer {statistics.median(h['gbuffer_ms'] for h in hbao):.1f} ms), "
        f"b = 1 {statistics.median(t['frame_ms'] for t in traced):.1f} ms, "
        f"HBAO / b = 1 {median:.3f} [{q1:.3f}-{q3:.3f}] over {pairs} pairs on {hbao[0]['device']}",
        flush=True,
    )


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("scenes", nargs="+", metavar="DIR:RADIUS")
    parser.add_argument("--size", type=int, default=512, help="image width and height")
    parser.add_argument("--pairs", type=int, default=11)
    args = parser.parse_args()
    for item in args.scenes:
        folder, _, radius = item.rpartition(":")
        if not folder:
            parser.error(f"{item}: give DIR:RADIUS")
        share(folder, float(radius), args.size, args.pairs)


if __name__ == "__main__":
    main()
