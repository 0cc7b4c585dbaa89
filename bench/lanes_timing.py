"""Traced time of mbao.trace with traversal "lanes" against the full stack, on one build.

From the repository root, after `make -C build`:
    .venv/bin/python bench/lanes_timing.py [--closest] [--camera]
The rays: Sponza's camera rays at 512 x 512 and, from each hit, 4 cosine-distributed AO rays leaving just
off the surface (1,022,120 rays). Each round traces them with either traversal, in turn, and takes off the
time of as many rays that miss the scene's box (the call's own cost).
"""

import argparse
import os
import time

import numpy as np

import mbao

SCENE = os.path.join(os.path.dirname(__file__), "..", "..", "shared", "scenes", "sponza")


def camera_rays(camera, size):
    eye = np.array(camera.eye, np.float32)
    forward = np.array(camera.target, np.float32) - eye
    forward /= np.linalg.norm(forward)
    right = np.cross(forward, np.array(camera.up, np.float32))
    right /= np.linalg.norm(right)
    up = np.cross(right, forward)
    half = np.tan(np.radians(camera.vfov_deg) / 2)
    ys, xs = np.mgrid[0:size, 0:size]
    sx = ((xs + 0.5) / size * 2 - 1) * half
    sy = (1 - (ys + 0.5) / size * 2) * half
    dirs = forward[None] + sx.reshape(-1, 1) * right[None] + sy.reshape(-1, 1) * up[None]
    return np.ascontiguousarray(np.broadcast_to(eye, dirs.shape), np.float32), dirs.astype(np.float32)


def ao_rays(scene, origins, dirs, per_hit=4, seed=1):
    t, triangle, _ = mbao.trace(scene, origins, dirs)
    hit = triangle >= 0
    points = origins[hit] + dirs[hit] * t[hit, None]
    corners = np.asarray(scene.vertices)[np.asarray(scene.indices)[triangle[hit]]]
    normals = np.cross(corners[:, 1] - corners[:, 0], corners[:, 2] - corners[:, 0])
    normals /= np.linalg.norm(normals, axis=1)[:, None]
    normals = np.where((np.sum(normals * dirs[hit], 1) > 0)[:, None], -normals, normals)
    points = points + normals * 1e-3 * np.abs(points).max(1)[:, None]
    points, normals = np.repeat(points, per_hit, 0), np.repeat(normals, per_hit, 0)
    rng = np.random.default_rng(seed)
    u1, u2 = rng.random(len(points)), rng.random(len(points))
    helper = np.where(np.abs(normals[:, 0:1]) > 0.5, np.array([[0, 1, 0]]), np.array([[1, 0, 0]]))
    tangent = np.cross(normals, helper)
    tangent /= np.linalg.norm(tangent, axis=1)[:, None]
    bitangent = np.cross(normals, tangent)
    r, phi = np.sqrt(u1), 2 * np.pi * u2
    dirs = (
        tangent * (r * np.cos(phi))[:, None]
        + bitangent * (r * np.sin(phi))[:, None]
        + normals * np.sqrt(1 - u1)[:, None]
    )
    return points.astype(np.float32), dirs.astype(np.float32)


def traced(scene, origins, dirs, lanes, any_hit):
    start = time.perf_counter()
    result = mbao.trace(scene, origins, dirs, any_hit=any_hit, traversal="lanes" if lanes else "stack")
    return time.perf_counter() - start, result


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--closest", action="store_true", help="closest hit instead of any hit")
    parser.add_argument("--camera", action="store_true", help="the camera rays instead of the AO rays")
    parser.add_argument("--rounds", type=int, default=8)
    args = parser.parse_args()

    scene = mbao.load(os.path.join(SCENE, "scene.glb"))
    origins, dirs = camera_rays(mbao.Camera.load(os.path.join(SCENE, "camera.json")), 512)
    if not args.camera:
        origins, dirs = ao_rays(scene, origins, dirs)
    any_hit = not args.closest
    stack, lanes = (traced(scene, origins, dirs, w, any_hit)[1] for w in (False, True))
    print(f"{len(origins)} rays; hits identical:", all(np.array_equal(a, b) for a, b in zip(stack, lanes)))

    outside = np.full_like(origins, 1e6)
    away = np.tile(np.array([[1, 0, 0]], np.float32), (len(origins), 1))
    ratios = []
    for round_ in range(args.rounds):
        times = {}
        for w in (False, True) if round_ % 2 == 0 else (True, False):
            times[w] = traced(scene, origins, dirs, w, any_hit)[0] - traced(scene, outside, away, w, any_hit)[0]
        ratios.append(times[True] / times[False])
        print(f"stack {times[False] * 1e3:.0f} ms, lanes {times[True] * 1e3:.0f} ms, lanes / stack {ratios[-1]:.3f}")
    q1, median, q3 = np.percentile(ratios, [25, 50, 75])
    print(f"lanes / stack traced time: {median:.3f} [{q1:.3f}-{q3:.3f}] over {args.rounds} rounds")


if __name__ == "__main__":
    main()
