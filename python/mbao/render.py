"""Rendering and ray queries."""

import dataclasses
import inspect
import math
from typing import Any, Iterable, Iterator, Optional, Tuple, Union

import numpy as np
from numpy.typing import ArrayLike

from . import _checks, _core
from ._progress import checked_progress, progress_reporter
from ._types import CameraLike, DeviceLike, Progress, SceneLike
from ._warnings import warn
from .devices import resolve
from .scene import as_camera, as_scene
from .settings import ENGINE, RENDER, Engine, checked, describe, engine_values


@dataclasses.dataclass(frozen=True)
class Result:
    """A rendered image.

    ao: (height, width) float32, the b-bounce access (1 = open), row 0 at the top;
        pixels whose camera rays all missed are 1, like open surfaces.
    mask: (height, width) bool, True where any camera sample hit geometry.
    coverage: (height, width) float32, the fraction of each pixel's camera samples
        that hit geometry, in 255ths rounded up (0 only where all missed): the
        alpha that tells the background apart (SPEC 2; save_image(..., alpha=)).
    stats: build_ms, tree_reused, kernel_build_ms, kernel_cache ("memory", "disk"
        or "compiled"), kernel_options, traversal_mode, organisation, plan (why
        "auto" chose the kernel variant it did, a line per choice), kernels (the
        program's entry points the frame launched, in order), max_distance
        (the radius used) and max_distance_source ("settings", "camera", "scene":
        HBAO's quarter diagonal, or "none": inf), upload_ms, frame_ms (gbuffer_ms,
        HBAO's G-buffer's part of it, denoise_ms, the spatial filter's, and
        temporal_ms, temporal accumulation's: 0 without them),
        rays_primary, rays_secondary, memory_bytes, tiles, device, tree.
    variance: (height, width) float32 with variance=True, else None: each
        pixel's variance as an estimate of its expectation, from the spread of
        its own samples (SPEC 7.1); 0 where every camera sample missed.
    history_length: (height, width) uint32 in a sequence with temporal
        accumulation, else None: the frames each pixel's value averages
        (SPEC 7.4): 1 where it has no history, 0 where its camera ray missed.
    """

    ao: np.ndarray
    mask: np.ndarray
    stats: dict
    coverage: np.ndarray
    variance: np.ndarray = None
    history_length: np.ndarray = None

    def __repr__(self):
        h, w = self.ao.shape
        return f"<mbao.Result {w}x{h}, frame {self.stats['frame_ms']:.1f} ms on {self.stats['device']}>"


def render(
    scene: SceneLike,
    *,
    camera: CameraLike = None,
    hbao: Optional[_core.HBAO] = None,
    denoise: Union[None, bool, _core.Denoise] = None,
    engine: Optional[Engine] = None,
    device: DeviceLike = None,
    progress: Progress = None,
    **settings: Any,
) -> "Result":
    # The signature and the docstring are made below from the settings' table.
    scene = as_scene(scene)
    values = _setting_values("render", _engine(engine, settings), settings)
    camera = as_camera(camera, scene, render_size(values))
    return _render(scene, camera, values, resolve(device), progress=progress, hbao=hbao, denoise=denoise)


def render_sequence(
    scene: SceneLike,
    cameras: Iterable[CameraLike],
    *,
    temporal: Union[bool, _core.Temporal] = True,
    denoise: Union[None, bool, _core.Denoise] = None,
    engine: Optional[Engine] = None,
    device: DeviceLike = None,
    progress: Progress = None,
    **settings: Any,
) -> Iterator["Result"]:
    """Renders a frame per camera, yielding a Result for each as it is done.

    scene: as render's; loaded once for the whole sequence.
    cameras: an iterable of mbao.Camera, camera.json paths, "frame" or None
        (as render's camera); it may be a generator.
    temporal: True, an mbao.Temporal, or False: each frame blends its render
        with the history of the frames before, reprojected into its camera
        through the camera hits, and drops it where the surface differs (a
        disocclusion); Result.history_length says how many frames each pixel
        averages (SPEC 7.4). A still camera converges as a progressive render
        does. Needs spp=1 and samples >= 2.
    denoise: as render's, run on each frame after the accumulation; the history
        keeps the unfiltered value.
    settings: render's; frame k is rendered with seed + k, so that its noise is
        independent of the frames before.

    The sequence is a function of its cameras, its settings and the seed. Its
    arguments are checked when it is called, each camera as its frame comes.
    """
    scene = as_scene(scene)
    values = _setting_values("render_sequence", _engine(engine, settings), settings)
    history = _core.TemporalHistory(_temporal_settings(temporal)) if temporal is not False else None
    _denoise_settings(denoise)
    return _frames(scene, cameras, values, resolve(device), denoise, history, checked_progress(progress))


def _frames(scene, cameras, values, device, denoise, history, progress):
    first_seed = values.get("seed", RENDER["seed"]["default"])
    for k, camera in enumerate(cameras):
        frame = dict(values, seed=checked(RENDER["seed"], first_seed + k))
        yield _render(
            scene,
            as_camera(camera, scene, render_size(values)),
            frame,
            device,
            progress=progress,
            denoise=denoise,
            history=history,
        )


def render_size(values):
    """(width, height) of a render with these setting values."""
    return tuple(values.get(name, RENDER[name]["default"]) for name in ("width", "height"))


def _setting_values(function, engine, settings):
    """{name: value} of the settings, checked against the table, and the engine's."""
    values = {}
    for name, value in settings.items():
        if name not in RENDER:
            raise TypeError(
                f"{function}() got an unexpected keyword argument {name!r}; its settings are "
                f"{', '.join(RENDER)}, and engine=mbao.Engine(...) takes {', '.join(ENGINE)}"
            )
        values[name] = checked(RENDER[name], value)
    values.update(engine_values(engine))
    return values


def _render(scene, camera, values, device, *, progress=None, hbao=None, denoise=None, history=None):
    with progress_reporter(progress, "render", "tile") as on_tile:
        ao, coverage, variance, history_length, stats = _core.render(
            scene, camera, device, values, on_tile, _hbao_settings(hbao), _denoise_settings(denoise), history
        )
    mask = coverage > 0
    warn_if_closed(scene, ao, mask, stats, "covered pixels")
    return Result(ao, mask, stats, coverage.astype(np.float32) / 255, variance, history_length)


def warn_if_closed(scene, ao, mask, stats, values):
    """Warns where an unlimited radius left 99% of the masked `values` (covered
    pixels, vertices, texels) below 0.01: in a closed scene every AO ray hits
    something. Only with 100 of them or more, where 99% leaves room for an open
    one. Python's default filter shows it once per scene (the message names
    it), at the user's line that called mbao."""
    covered = ao[mask]
    if not math.isinf(stats["max_distance"]) or covered.size < 100 or np.mean(covered < 0.01) < 0.99:
        return
    warn(
        f"{scene.name}: {np.mean(covered < 0.01):.0%} of the {values} are below 0.01 with "
        f"max_distance=inf: the scene looks closed, so every AO ray hits something. Give a radius in "
        f"world units (max_distance=...), or a camera.json that suggests one (SPEC 1)"
    )


render.__doc__ = f"""Renders b-bounce ambient occlusion (SPEC 1) and returns a Result.

scene: an mbao.Scene (mbao.load, mbao.Mesh, mbao.cornell_box()), or the path of a
    scene file (mbao.load's formats), loaded for this call (load it once with mbao.load
    to render it again).
camera: an mbao.Camera, the path of a camera.json file, or "frame" for the
    camera that frames the whole scene (SPEC 3.1); by default the scene's own
    (the Cornell box's, a glTF file's first perspective camera), else the
    framing one.

{chr(10).join(describe(spec) for spec in RENDER.values())}

hbao: an mbao.HBAO with HBAO's own settings, for method="hbao".
denoise: None (the raw image), True or an mbao.Denoise: the image filtered by
    an edge-aware a-trous filter guided by the camera hits and each pixel's
    variance (SPEC 7.3), at spp=1 and samples >= 2; stats["denoise_ms"] is its
    share of frame_ms, and Result.variance (variance=True) the filtered variance.
engine: an mbao.Engine: how the work is done (traversal, kernel organisation,
    tiles, work groups, traversal counts). None: mbao's choice for the device.
    No engine setting changes the image; stats["plan"] says what was chosen.
device: None, an index or name part from mbao.devices(), an mbao.Device or a pyopencl.Device.
progress: None (the default): a bar over the tiles on a terminal, for a render
    of several tiles that takes more than a few seconds; False: none; True: a
    bar; a callable progress(tiles_done, tiles_total), called after each tile.

Bad arguments raise TypeError or ValueError naming the argument and its allowed
range. The GIL is released while rendering. Ctrl-C (KeyboardInterrupt), or an
exception raised by progress, stops the render after the tile in flight; the
next render works as usual.
"""

render.__signature__ = inspect.Signature(
    [
        inspect.Parameter("scene", inspect.Parameter.POSITIONAL_OR_KEYWORD),
        inspect.Parameter("camera", inspect.Parameter.KEYWORD_ONLY, default=None),
    ]
    + [
        inspect.Parameter(name, inspect.Parameter.KEYWORD_ONLY, default=spec["default"])
        for name, spec in RENDER.items()
    ]
    + [
        inspect.Parameter(name, inspect.Parameter.KEYWORD_ONLY, default=None)
        for name in ("hbao", "denoise", "engine", "device", "progress")
    ]
)


def _engine(engine, settings):
    """The engine settings: `engine`, or an Engine of the engine keywords render() took before there was one."""
    if engine is not None and not isinstance(engine, Engine):
        raise TypeError(f"engine must be None or an mbao.Engine, got {type(engine).__name__}")
    old = {name: settings.pop(name) for name in list(settings) if name in ENGINE}
    if not old:
        return engine or Engine()
    if engine is not None:
        raise TypeError(f"{', '.join(old)} given beside engine=: give engine settings in mbao.Engine(...) only")
    warn(
        f"render({', '.join(f'{name}=...' for name in old)}) is deprecated and will go in the next "
        f"release: pass engine=mbao.Engine({', '.join(f'{name}=...' for name in old)})",
        DeprecationWarning,
    )
    return Engine(**old)


def _denoise_settings(denoise):
    if denoise is None or denoise is False:
        return None
    if denoise is True:
        return _core.Denoise()
    if not isinstance(denoise, _core.Denoise):
        raise TypeError(f"denoise must be None, True or an mbao.Denoise, got {type(denoise).__name__}")
    return denoise


def _temporal_settings(temporal):
    if temporal is True:
        return _core.Temporal()
    if not isinstance(temporal, _core.Temporal):
        raise TypeError(f"temporal must be True, False or an mbao.Temporal, got {type(temporal).__name__}")
    return temporal


def _hbao_settings(hbao):
    if hbao is None:
        return _core.HBAO()
    if not isinstance(hbao, _core.HBAO):
        raise TypeError(f"hbao must be None or an mbao.HBAO, got {type(hbao).__name__}")
    return hbao


def trace(
    scene: SceneLike,
    origins: ArrayLike,
    directions: ArrayLike,
    *,
    t_max: Union[float, ArrayLike] = math.inf,
    any_hit: bool = False,
    traversal: str = "auto",
    device: DeviceLike = None,
    traversal_stats: bool = False,
) -> Tuple[np.ndarray, ...]:
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
    scene = as_scene(scene)
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
        checked(ENGINE["traversal"], traversal),
        _checks.boolean("traversal_stats", traversal_stats),
    )


@dataclasses.dataclass(frozen=True)
class GBuffer:
    """Per pixel, the hit of the camera ray through its centre (SPEC 7.2): what
    HBAO and the screen-space filters read. Arrays are (height, width), vectors
    (height, width, 3), row 0 at the top; where no triangle covers a pixel,
    mask is False, triangle -1 and every other value 0.

    position: the hit point, in world units.
    t: its distance along the camera ray; depth: along the view direction.
    geometric_normal, shading_normal: unit, turned to the eye (SPEC 3.3).
    footprint: the side of the pixel at distance t.
    triangle: int64, the hit triangle's index into scene.indices.
    stats: as a Result's; frame_ms is the G-buffer's time.
    """

    position: np.ndarray
    t: np.ndarray
    depth: np.ndarray
    geometric_normal: np.ndarray
    shading_normal: np.ndarray
    footprint: np.ndarray
    triangle: np.ndarray
    mask: np.ndarray
    stats: dict

    def __repr__(self):
        h, w = self.t.shape
        return f"<mbao.GBuffer {w}x{h}, {self.stats['frame_ms']:.1f} ms on {self.stats['device']}>"


def gbuffer(
    scene: SceneLike,
    *,
    camera: CameraLike = None,
    width: int = RENDER["width"]["default"],
    height: int = RENDER["height"]["default"],
    engine: Optional[Engine] = None,
    device: DeviceLike = None,
) -> "GBuffer":
    """The G-buffer (SPEC 7.2) of scene seen from camera, as HBAO's frames make
    it: a GBuffer. scene, camera, width, height, engine and device are as for
    render; the engine's traversal walks the camera rays ("auto": in packets
    on CPUs)."""
    scene = as_scene(scene)
    values = _setting_values("gbuffer", _engine(engine, {}), dict(width=width, height=height))
    camera = as_camera(camera, scene, render_size(values))
    plane, origin, stats = _core.gbuffer(scene, camera, resolve(device), values)
    triangle = plane["triangle"].view(np.uint32).astype(np.int64)
    mask = triangle != 0xFFFFFFFF
    triangle[~mask] = -1
    position = np.stack([plane["x"], plane["y"], plane["z"]], axis=-1)
    position[mask] += np.asarray(origin, dtype=np.float32)
    return GBuffer(
        position=position,
        t=plane["t"],
        depth=plane["depth"],
        geometric_normal=np.stack([plane["nx"], plane["ny"], plane["nz"]], axis=-1),
        shading_normal=np.stack([plane["sx"], plane["sy"], plane["sz"]], axis=-1),
        footprint=plane["footprint"],
        triangle=triangle,
        mask=mask,
        stats=stats,
    )
