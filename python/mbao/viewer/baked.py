"""The viewer's "baked" method: the ambient occlusion a glTF file stores
(mbao.load_bake) looked up at the camera's hits, which sets a bake beside live
ray-traced AO seen from the same viewpoint."""

import time

import numpy as np

from ..render import Result, gbuffer
from ..stored_bake import OPEN, VERTICES


def baked_occlusion(scene, bake, camera, width, height, device):
    """A mbao.Result of the stored occlusion at the hits of the camera rays
    through the pixel centres (mbao.gbuffer): the hit triangle's vertex values
    interpolated with the hit's barycentrics, or its material's occlusion
    texture sampled bilinearly (the sampler's wrap modes) at the interpolated
    UV. Pixels that miss: ao 1, coverage 0, as a render's. A triangle with
    nothing stored is open (ao 1), and counted in stats["unbaked_pixels"].
    bake: load_bake's for this scene. variance is None.

    stats: the G-buffer's (device, rays_primary, tree, ...), with frame_ms its
    time (gbuffer_ms) plus the lookup's (lookup_ms), method "baked", source
    (the bake's: "vertices" or "texture") and unbaked_pixels."""
    hits = gbuffer(scene, camera=camera, width=width, height=height, device=device)
    start = time.perf_counter()
    ao = np.ones((height, width), np.float32)
    pixels = np.flatnonzero(hits.mask)
    triangles = hits.triangle.ravel()[pixels]
    corners = scene.indices[triangles].astype(np.int64)
    weights = barycentrics(scene.vertices[corners], hits.position.reshape(-1, 3)[pixels])
    source = bake.triangle_source[triangles]
    values = np.ones(len(pixels), np.float32)
    here = source == VERTICES
    if here.any():
        values[here] = (bake.vertex_values[corners[here]] * weights[here]).sum(axis=1)
    for material in np.unique(source[source >= 0]).tolist():
        here = source == material
        uv = (bake.vertex_uvs[corners[here]] * weights[here][:, :, None]).sum(axis=1)
        values[here] = bake.textures[material].sample(uv)
    ao.flat[pixels] = values
    lookup_ms = (time.perf_counter() - start) * 1e3
    stats = dict(
        hits.stats,
        method="baked",
        source=bake.source,
        unbaked_pixels=int((source == OPEN).sum()),
        gbuffer_ms=hits.stats["frame_ms"],
        lookup_ms=lookup_ms,
        frame_ms=hits.stats["frame_ms"] + lookup_ms,
    )
    return Result(ao, hits.mask, stats, hits.mask.astype(np.float32))


def barycentrics(corners, points):
    """(K, 3) float64 weights of (K, 3) points on triangles with (K, 3, 3)
    corners: those of each point's projection onto its triangle's plane,
    clamped into the triangle (a hit lies on it but for rounding). A
    triangle without area weighs its corners equally."""
    a = corners[:, 0].astype(np.float64)
    e1, e2 = corners[:, 1] - a, corners[:, 2] - a
    d = points.astype(np.float64) - a
    d00, d01, d11 = (e1 * e1).sum(axis=1), (e1 * e2).sum(axis=1), (e2 * e2).sum(axis=1)
    d20, d21 = (d * e1).sum(axis=1), (d * e2).sum(axis=1)
    gram = d00 * d11 - d01 * d01
    flat = gram <= 1e-12 * d00 * d11  # collinear corners, up to rounding: no plane to project onto
    gram = np.where(flat, 1.0, gram)
    b1, b2 = (d11 * d20 - d01 * d21) / gram, (d00 * d21 - d01 * d20) / gram
    weights = np.clip(np.column_stack([1.0 - b1 - b2, b1, b2]), 0.0, None)
    weights /= weights.sum(axis=1, keepdims=True)
    weights[flat] = 1.0 / 3.0
    return weights
