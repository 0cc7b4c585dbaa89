"""Rendering and ray queries."""

import dataclasses
import math

import numpy as np

from . import _checks, _core
from .devices import resolve

ESTIMATORS = ("branching", "path")
NORMAL_MODES = ("shading", "geometric")
TRAVERSALS = ("auto", "pushdown", "restart", "short-stack", "stack", "lanes")
ORGANISATIONS = ("auto", "megakernel", "wavefront")
METHODS = ("raytraced", "hbao")


@dataclasses.dataclass(frozen=True)
class Result:
    """A rendered image.

    ao: (height, width) float32, the b-bounce access (1 = open), row 0 at the top;
        pixels whose camera rays all missed are 1.
    mask: (height, width) bool, True where any camera sample hit geometry.
    stats: build_ms, tree_reused, kernel_build_ms, kernel_cache ("memory", "disk"
        or "compiled"), kernel_options, traversal_mode, organisation, plan (why
        "auto" chose the kernel variant it did, a line per choice), upload_ms,
        frame_ms, rays_primary, rays_secondary, memory_bytes, tiles, device, tree.
    """

    ao: np.ndarray
    mask: np.ndarray
    stats: dict

    def __repr__(self):
        h, w = self.ao.shape
        return f"<mbao.Result {w}x{h}, frame {self.stats['frame_ms']:.1f} ms on {self.stats['device']}>"


def _check_scene(scene):
    if not isinstance(scene, _core.Scene):
        raise TypeError(f"scene must be an mbao.Scene or mbao.Mesh, got {type(scene).__name__}")


def render(
    scene,
    *,
    camera=None,
    width=512,
    height=512,
    bounces=1,
    samples=4,
    estimator="branching",
    rho=1.0,
    max_distance=math.inf,
    spp=1,
    normals="shading",
    seed=0,
    traversal="auto",
    device=None,
    traversal_stats=False,
    organisation="auto",
    tile_pixels=None,
    work_group_size=None,
    max_rays=None,
    progress=None,
    method="raytraced",
    hbao=None,
):
    """Renders b-bounce ambient occlusion (SPEC 1) and returns a Result.

    camera: an mbao.Camera; by default the scene's own (the Cornell box's, a glTF
        file's first perspective camera), else one framing the scene's bounds.
    width, height: image size in pixels, 1..16384.
    bounces: b >= 1 (branching: at most 16). samples: r, directions per hit.
    estimator: "branching" (the paper's: r + r^2 + ... + r^b rays per camera
        sample) or "path" (r paths of up to b segments).
    rho: albedo in [0, 1]. max_distance: hits farther away count as misses (> 0, inf).
    spp: camera samples per pixel (1: the pixel centre; more: jittered, box filter).
    normals: "shading" (interpolated vertex normals where the mesh has them) or "geometric".
    seed: any integer in [0, 2^64); the image is a pure function of the seed and
        the settings, whatever the device, tiling or work-group size.
    traversal: how rays walk the kd-tree: "pushdown" or "short-stack" (Horn et al. 2007),
        "restart" (Foley and Sugerman 2005), "stack" (a full stack), "lanes" (the full stack,
        sixteen rays per work item in vector lanes, for CPUs: the branching estimator in the
        wavefront organisation only; camera rays sixteen to a packet), or "auto": the device
        class's choice (docs/kernel-variants.md; stats["traversal_mode"] says which ran and
        stats["plan"] why). Same image either way.
    device: None, an index or name part from mbao.devices(), an mbao.Device or a pyopencl.Device.
    traversal_stats: count nodes, leaves, triangle tests and restarts per ray into
        stats["traversal"] (kernels built to count, somewhat slower).
    organisation: "megakernel" (one work item runs a pixel's whole estimator),
        "wavefront" (branching only: one launch per bounce over a compacted queue of
        the surfaces that bounce on), or "auto": the device class's choice, the wavefront
        wherever traversal is "lanes" (docs/kernel-variants.md).
        Same image bit for bit; stats["organisation"] says which ran.
    tile_pixels, work_group_size: how the work is cut up (None: automatic); they do not change the image.
    max_rays: a render that could trace more rays than this (camera rays included) is refused
        with a ValueError saying how many it would take; None: mbao.DEFAULT_MAX_RAYS (1e10).
        Branching work grows as samples^bounces: the path estimator needs samples * bounces.
    progress: None, or a callable progress(tiles_done, tiles_total) called after each tile.
    method: "raytraced" (the estimators above) or "hbao": screen-space horizon-based AO
        (SPEC 4) on the camera rays' hits through the pixel centres, with radius
        max_distance (finite), one bounce, spp 1; hbao: an mbao.HBAO for its settings.

    The GIL is released while rendering. Ctrl-C (KeyboardInterrupt), or an exception raised by
    progress, stops the render after the tile in flight; the next render works as usual.
    """
    _check_scene(scene)
    if camera is not None and not isinstance(camera, _core.Camera):
        raise TypeError(f"camera must be an mbao.Camera or None, got {type(camera).__name__}")
    seed = _checks.integer("seed", seed, 0, 2**64 - 1, "[0, 2**64)")
    ao, mask, stats = _core.render(
        scene,
        camera,
        resolve(device),
        width=_checks.integer("width", width),
        height=_checks.integer("height", height),
        bounces=_checks.integer("bounces", bounces),
        samples=_checks.integer("samples", samples),
        estimator=_checks.choice("estimator", estimator, ESTIMATORS),
        rho=_checks.real("rho", rho),
        max_distance=_checks.real("max_distance", max_distance),
        spp=_checks.integer("spp", spp),
        normals=_checks.choice("normals", normals, NORMAL_MODES),
        seed=seed,
        traversal=_checks.choice("traversal", traversal, TRAVERSALS),
        traversal_stats=_checks.boolean("traversal_stats", traversal_stats),
        organisation=_checks.choice("organisation", organisation, ORGANISATIONS),
        tile_pixels=_optional_count("tile_pixels", tile_pixels),
        work_group_size=_optional_count("work_group_size", work_group_size),
        max_rays=_core.DEFAULT_MAX_RAYS if max_rays is None else _checks.integer("max_rays", max_rays, 1, 2**64 - 1,
                                                                                   "[1, 2**64)"),
        progress=_progress(progress),
        method=_checks.choice("method", method, METHODS),
        hbao=_hbao_settings(hbao),
    )
    return Result(ao, mask, stats)


def _hbao_settings(hbao):
    if hbao is None:
        return _core.HBAO()
    if not isinstance(hbao, _core.HBAO):
        raise TypeError(f"hbao must be None or an mbao.HBAO, got {type(hbao).__name__}")
    return hbao


def _progress(progress):
    if progress is not None and not callable(progress):
        raise TypeError(f"progress must be None or a callable (tiles_done, tiles_total), got {type(progress).__name__}")
    return progress


def _optional_count(name, value):
    if value is None:
        return 0
    value = _checks.integer(name, value)
    if value < 1:
        raise ValueError(f"{name} must be >= 1 or None, got {value}")
    return value


def trace(scene, origins, directions, *, t_max=math.inf, any_hit=False, traversal="auto", device=None,
          traversal_stats=False):
    """Traces rays through the scene's kd-tree.

    origins, directions: (N, 3) arrays (directions need not be unit length; t is
    in units of their length). t_max: a number or an (N,) array; hits must have
    0 < t <= t_max. any_hit: stop at the first hit found instead of the closest.
    traversal: as for render; "auto" is "lanes" on CPUs for trees at least 16 deep.

    Returns (t, triangle, barycentrics): t (N,) float32, inf for a miss; triangle
    (N,) int64 index into scene.indices, -1 for a miss; barycentrics (N, 2)
    float32, the weights of the triangle's second and third vertex. With
    traversal_stats, a fourth (N, 4) uint32 array: per ray the nodes and leaves
    visited, the triangles tested and the restarts.
    """
    _check_scene(scene)
    origins = _checks.rows("origins", origins, 3, "fiu", np.float32)
    directions = _checks.rows("directions", directions, 3, "fiu", np.float32)
    if len(origins) != len(directions):
        raise ValueError(f"origins has {len(origins)} rows but directions has {len(directions)}")
    any_hit = _checks.boolean("any_hit", any_hit)
    try:
        limits = np.broadcast_to(np.asarray(t_max, dtype=np.float32), (len(origins),))
    except (TypeError, ValueError):
        raise ValueError(f"t_max must be a number or one per ray ({len(origins)}), got {t_max!r}") from None
    if not np.all(limits > 0):  # NaN fails too
        raise ValueError("t_max must be > 0 (inf for unlimited)")
    rays = np.ascontiguousarray(np.column_stack([directions, limits]), dtype=np.float32)
    return _core.trace(
        scene,
        origins,
        rays,
        resolve(device),
        any_hit,
        _checks.choice("traversal", traversal, TRAVERSALS),
        _checks.boolean("traversal_stats", traversal_stats),
    )
