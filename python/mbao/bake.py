"""Baking multi-bounce AO into assets: a value per vertex or per texel (SPEC 6)."""

import concurrent.futures
import dataclasses
import math
import os
import textwrap
import threading
import weakref
from typing import Any, Optional, Tuple, Union

import numpy as np
from numpy.typing import ArrayLike

from . import _checks, _core
from ._progress import checked_progress, progress_reporter
from ._types import CameraLike, DeviceLike, Progress, SceneLike
from ._warnings import warn
from .devices import resolve
from .render import warn_if_closed
from .scene import FRAME, Mesh, as_camera, as_scene, load
from .settings import BAKE_SETTINGS, RENDER, Engine, checked, describe, engine_values

WRAP_MODES = ("repeat", "mirrored-repeat", "clamp-to-edge")


@dataclasses.dataclass(frozen=True)
class BakedTexture:
    """One material's baked texture (SPEC 6.3), row 0 at v = 0 (glTF's top row).

    image: (H, W) float32, each texel the mean of L_b over the surface whose UVs
        fall in it; texels near a covered one hold its value (dilation), farther
        ones 1.
    standard_error: (H, W) float32, the standard error of each texel (its
        source's where dilated, 0 where 1 was filled in).
    coverage: (H, W) bool, the texels that hold surface.
    texcoord: n of the UV set TEXCOORD_n used, or "generated".
    triangles: (K,) the material's triangles, indices into scene.indices.
    texcoords: (K, 3, 2) float32, the UVs of their corners as baked: a lookup
        at a point of triangle triangles[k] interpolates texcoords[k].
    stats: covered, claimed_twice, dilated (texel counts), unmapped_triangles
        (triangles of zero UV area, which no texel holds) and wrap (s, t).
    """

    image: np.ndarray
    standard_error: np.ndarray
    coverage: np.ndarray
    texcoord: object
    triangles: np.ndarray
    texcoords: np.ndarray
    stats: dict


@dataclasses.dataclass(frozen=True)
class Bake:
    """What mbao.bake made (SPEC 6).

    target: "vertices" or "texture".
    values: vertices only: (N,) float32, per vertex of scene.vertices, the mean
        of L_b over its one-ring weighted by its hat function (1 = open; 1 where
        no triangle of positive area uses it). None for textures.
    standard_error: vertices only: (N,) float32, the standard error of each
        value, from the spread of its estimates (0 where a vertex has no surface).
    textures: texture only: {material index: BakedTexture}, -1 for triangles
        without a material, 0 for an mbao.Mesh; empty for vertices.
    settings: what it was baked with.
    stats: the renderer's statistics of the bake (rays_secondary, frame_ms, plan,
        ...); for textures frame_ms and rays_secondary are summed over the
        materials, the rest is the last material's.
    """

    target: str
    values: np.ndarray
    standard_error: np.ndarray
    settings: dict
    stats: dict
    textures: dict = dataclasses.field(default_factory=dict)

    def __repr__(self):
        what = (
            f"{len(self.values)} values, mean {float(np.mean(self.values)):.3f}"
            if self.values is not None
            else f"{len(self.textures)} textures"
        )
        return f"<mbao.Bake {self.target}: {what}, {self.stats['frame_ms'] / 1e3:.1f} s on {self.stats['device']}>"


_DEFAULTS = {name: spec["default"] for name, spec in BAKE_SETTINGS.items()}


def bake(
    scene: SceneLike,
    *,
    target: str = _DEFAULTS["target"],
    bounces: int = 1,
    samples: int = _DEFAULTS["samples"],
    estimator: str = _DEFAULTS["estimator"],
    directions: int = _DEFAULTS["directions"],
    rho: float = 1.0,
    max_distance: Optional[float] = None,
    camera: CameraLike = None,
    normals: str = "shading",
    texcoord: Union[None, int, str] = None,
    resolution: Union[int, Tuple[int, int]] = 1024,
    padding: int = _DEFAULTS["padding"],
    wrap: Union[None, str, Tuple[str, str]] = None,
    seed: int = 0,
    max_rays: int = _core.DEFAULT_MAX_RAYS,
    triangles: Optional[ArrayLike] = None,
    engine: Optional[Engine] = None,
    device: DeviceLike = None,
    progress: Progress = None,
    client: Any = None,
) -> "Bake":
    """Bakes b-bounce ambient occlusion (SPEC 1) into values per vertex (SPEC 6.2)
    or per texel (SPEC 6.3).

    scene: an mbao.Scene (mbao.load, mbao.Mesh) or the path of a scene file; a
        texture bake of a loaded file into its own UV sets needs
        mbao.load(path, texcoords=True).
    target, samples, estimator, directions, padding: the bake's own settings,
        below.
    bounces, rho, normals, seed, max_rays: as for mbao.render.
    texcoord: texture only: n of the UV set TEXCOORD_n. None: per material, its
        occlusionTexture's texCoord where it has one, else TEXCOORD_1 where all
        its triangles have it, else TEXCOORD_0; an mbao.Mesh's texcoords are set 0.
        "generate": a new UV set per material, charts of neighbouring triangles
        laid flat (projected, or by conformal maps, whichever packs better)
        and packed at one texel density with `padding` texels between them
        (the texture's stats say charts, worst_stretch, texels_per_unit and
        texels_used).
    resolution: texture only: the texture's size, an int or (width, height), each in [1, 16384].
    wrap: texture only: how UVs outside [0, 1] map, "repeat", "mirrored-repeat"
        or "clamp-to-edge", or a pair of them (along u, along v); None: the
        sampler of the material's occlusion texture, else "repeat" (glTF's default).
    max_distance, camera: the AO radius in world units, by render's rule (SPEC
        1): the one given, else the one `camera` suggests (an mbao.Camera or
        the path of a camera.json, used for nothing else), else the one the
        scene's own camera suggests (a glTF camera's extras), else inf.
        stats["max_distance"] is the radius used and stats["max_distance_source"]
        where it came from: "settings", "camera" or "none". A bake with no
        radius that comes out nearly black warns: in a closed scene every ray
        hits something.
    triangles: the triangles baked, indices into scene.indices; None: all of
        them. The others still occlude and reflect, but are baked nowhere: a
        vertex's one-ring is its triangles baked (a vertex in none gets 1), and
        each material's texture holds only its triangles baked (SPEC 6).
    engine: an mbao.Engine, as for render.
    device: as for render.
    progress: as for render, over the bake's tiles (with a client, its parts):
        None, a bar on a terminal for a bake longer than a few seconds; False,
        none; True, a bar; or a callable progress(tiles_done, tiles_total).
    client: a dask.distributed.Client traces the bake in parts on its
        workers' devices (`device` is then unused): a bake's estimates are one
        image, split by its pixels' positions, each pixel's rays keyed by the
        pixel, so the bake is the one made here, bit for bit (SPEC 6.6). The
        workers send back each position's two moments; the values, standard
        errors and dilation are made here.

    A surface is baked on its front side, the side its triangles' corners run
    counter-clockwise seen from (SPEC 6.1). A UV set in which two surfaces
    claim one texel (mirrored halves, tiles, overlapping islands) is refused
    with an mbao.Error before any ray is traced. The result is a function of the
    scene, the settings and the seed. The GIL is released while baking; Ctrl-C
    stops after the tile in flight. Returns an mbao.Bake.
    """
    own = dict(target=target, samples=samples, estimator=estimator, directions=directions, padding=padding)
    own = {name: checked(BAKE_SETTINGS[name], value) for name, value in own.items()}
    _core.check_settings("bake", own)
    target, samples, estimator, directions, padding = own.values()
    checked_progress(progress)
    from_file = isinstance(scene, (str, os.PathLike))
    scene = load(scene, texcoords=True) if target == "texture" and from_file else as_scene(scene)
    radius, radius_source = _radius(scene, max_distance, camera)
    baked = _baked_triangles(scene, triangles)
    given = dict(
        bounces=bounces,
        estimator=estimator,
        rho=rho,
        max_distance=radius,
        normals=normals,
        seed=seed,
        max_rays=max_rays,
    )
    values = dict({name: checked(RENDER[name], value) for name, value in given.items()}, samples=directions)
    if engine is not None and not isinstance(engine, Engine):
        raise TypeError(f"engine must be None or an mbao.Engine, got {type(engine).__name__}")
    values.update(engine_values(engine or Engine()))
    settings = dict(given, target=target, samples=samples, directions=directions)
    if target == "vertices":
        with progress_reporter(progress, "bake", "tile") as on_tile:
            if client is None:
                ao, standard_error, stats = _core.bake_vertices(scene, baked, resolve(device), values, samples, on_tile)
            else:
                positions = _core.vertex_bake_positions(scene, baked, samples)
                mean, second_moment, stats = _traced_on(client, scene, baked, positions, values, samples, on_tile)
                ao, standard_error = _core.finish_vertex_bake(scene, baked, samples, mean, second_moment)
        stats = dict(stats, max_distance_source=radius_source)
        warn_if_closed(scene, ao, np.ones(ao.shape, bool), stats, "vertices")
        return Bake(target, ao, standard_error, settings, stats)

    width, height = _resolution(resolution)
    wrap = None if wrap is None else _wrap(wrap)
    if texcoord is not None and texcoord != "generate":
        texcoord = _checks.integer("texcoord", texcoord, 0, 7, '[0, 7] (TEXCOORD_n), "generate" or None')
    materials = (
        _generated_materials(scene, baked, width, height, padding)
        if texcoord == "generate"
        else _texture_materials(scene, baked, texcoord, wrap)
    )
    textures, stats = _bake_textures(
        scene, materials, (width, height), padding, values, samples, device, progress, client
    )
    settings.update(texcoord=texcoord, resolution=(width, height), padding=padding, wrap=wrap)
    stats = dict(stats, max_distance_source=radius_source)
    for texture in textures.values():
        warn_if_closed(scene, texture.image, texture.coverage, stats, "covered texels")
    return Bake(target, None, None, settings, stats, textures)


bake.__doc__ = (
    bake.__doc__.rstrip()
    + "\n\n    The bake's own settings (SPEC 6):\n\n"
    + "\n".join(textwrap.indent(describe(spec), "    ") for spec in BAKE_SETTINGS.values())
    + "\n"
)


def _baked_triangles(scene, triangles):
    """The triangles a bake bakes: sorted, each once, as uint32 indices into scene.indices."""
    if triangles is None:
        return np.arange(scene.triangle_count, dtype=np.uint32)
    given = np.asarray(triangles)
    if given.ndim != 1 or given.size == 0 or given.dtype.kind not in "iu":
        raise ValueError(
            f"triangles must be a non-empty list of triangle indices, got an array of shape "
            f"{given.shape} and dtype {given.dtype}"
        )
    outside = (given < 0) | (given >= scene.triangle_count)
    if outside.any():
        raise ValueError(
            f"triangles: {int(given[outside][0])} is not a triangle of the scene, whose triangles are "
            f"0 to {scene.triangle_count - 1}"
        )
    return np.unique(given).astype(np.uint32)


def _radius(scene, max_distance, camera):
    """(radius, source) by SPEC 1's rule for a bake: given, else suggested by `camera` or the scene's own, else inf."""
    if max_distance is not None:
        return checked(RENDER["max_distance"], max_distance), "settings"
    if camera == FRAME:
        raise ValueError('camera="frame" suggests no radius: a bake takes only the radius of the camera it is given')
    suggesting = as_camera(camera) if camera is not None else scene.camera
    if suggesting is not None and suggesting.max_distance is not None:
        return suggesting.max_distance, "camera"
    return math.inf, "none"


def _bake_textures(scene, materials, resolution, padding, values, samples, device, progress, client):
    """{material: BakedTexture} and the renders' statistics, frame_ms and rays_secondary summed."""
    width, height = resolution
    # Every layout first: a UV set that cannot be baked is refused before any ray is traced.
    layouts = {}
    for material in materials:
        layout = material.layout or _core.TexelLayout(
            scene, material.texcoords, material.triangles, width, height, *material.wrap
        )
        _refuse_claimed_twice(layout, material)
        _refuse_or_warn_of_unmapped(scene, material)
        layouts[material.index] = (material, layout)
    textures, totals = {}, dict(frame_ms=0.0, rays_secondary=0)
    for index, (material, layout) in layouts.items():
        with progress_reporter(progress, f"bake {material.name}", "tile") as on_tile:
            if client is None:
                image, standard_error, filled, stats = _core.bake_texels(
                    layout, resolve(device), values, samples, padding, on_tile
                )
            else:
                recipe = _TexelRecipe(material.texcoords, material.triangles, width, height, material.wrap)
                mean, second_moment, stats = _traced_on(
                    client, scene, recipe, layout.bake_positions(samples), values, samples, on_tile
                )
                image, standard_error, filled = _core.finish_texel_bake(layout, samples, padding, mean, second_moment)
        texture_stats = dict(
            material.stats,
            covered=layout.covered_count,
            claimed_twice=layout.claimed_twice,
            dilated=int(filled.sum()),
            unmapped_triangles=layout.unmapped_triangles,
            wrap=material.wrap,
            texels_used=layout.covered_count / (width * height),
        )
        textures[index] = BakedTexture(
            image,
            standard_error,
            layout.covered.astype(bool),
            material.set,
            material.triangles,
            material.texcoords,
            texture_stats,
        )
        for name in totals:
            totals[name] += stats[name]
    return textures, dict(stats, **totals)


# The fewest positions a part of a bake on a cluster traces: fewer cost more
# in hand-overs than they trace.
_MIN_POSITIONS_PER_PART = 1 << 14


def _traced_on(client, scene, points, positions, values, samples, on_part):
    """Every position's two moments of a bake, traced in parts on the cluster's
    workers, and the parts' stats, frame_ms and rays_secondary summed.
    points: what the estimates' points are drawn from: a vertex bake's triangles
    baked (uint32 indices), or a texture bake's _TexelRecipe."""
    from ._cluster import default_in_flight, results_of, scene_for_workers  # only bakes on a cluster need Dask

    parts = max(1, min(2 * default_in_flight(client), positions // _MIN_POSITIONS_PER_PART))
    bounds = [positions * k // parts for k in range(parts + 1)]
    ranges = list(zip(bounds, bounds[1:]))
    on_cluster = scene_for_workers(client, scene, broadcast=True)
    # To each worker once, like the scene.
    points = client.scatter(points, broadcast=True, hash=False)
    tasks = ((_trace_part, on_cluster, points, values, samples, first, end) for first, end in ranges)
    mean, second_moment = np.empty(positions, np.float32), np.empty(positions, np.float32)
    stats, totals = None, dict(frame_ms=0.0, rays_secondary=0)
    results = results_of(client, tasks)
    try:
        for done, ((first, end), (part_mean, part_second_moment, stats)) in enumerate(zip(ranges, results), 1):
            mean[first:end], second_moment[first:end] = part_mean, part_second_moment
            for name in totals:
                totals[name] += stats[name]
            if on_part is not None:
                on_part(done, parts)
    finally:
        results.close()
    return mean, second_moment, dict(stats, **totals)


def _trace_part(scene, points, values, samples, first, end):
    """On a worker: positions [first, end) of a bake."""
    if isinstance(points, _TexelRecipe):
        return _core.trace_texel_bake(
            _layout_on_worker(scene, points), resolve(None), values, samples, first, end, None
        )
    return _core.trace_vertex_bake(scene, points, resolve(None), values, samples, first, end, None)


@dataclasses.dataclass(eq=False)
class _TexelRecipe:
    """What a worker builds a texture bake's TexelLayout from."""

    texcoords: np.ndarray
    triangles: np.ndarray
    width: int
    height: int
    wrap: tuple


# On a worker: the layout of each recipe it holds, built by the first part
# that needs it and dropped with the recipe once the bake is done. Building
# one rasterizes the whole UV set, which each part would otherwise repeat.
_layouts_on_worker = weakref.WeakKeyDictionary()
_layouts_lock = threading.Lock()


def _layout_on_worker(scene, recipe):
    with _layouts_lock:  # a worker's other threads wait for the layout rather than build it again
        layout = _layouts_on_worker.get(recipe)
        if layout is None:
            layout = _layouts_on_worker[recipe] = _core.TexelLayout(
                scene, recipe.texcoords, recipe.triangles, recipe.width, recipe.height, *recipe.wrap
            )
        return layout


def _resolution(resolution):
    if isinstance(resolution, (tuple, list)):
        if len(resolution) != 2:
            raise ValueError(f"resolution must be an int or (width, height), got {resolution!r}")
        sides = resolution
    else:
        sides = (resolution, resolution)
    lo, hi = _core.BAKE_RESOLUTION_RANGE
    return tuple(_checks.integer("resolution", side, lo, hi, f"[{lo}, {hi}] on each side") for side in sides)


def _wrap(wrap):
    if wrap is None:
        return "repeat", "repeat"
    if isinstance(wrap, str):
        wrap = (wrap, wrap)
    if not isinstance(wrap, (tuple, list)) or len(wrap) != 2:
        raise TypeError(f"wrap must be None, a wrap mode or a pair of them, got {wrap!r}")
    return tuple(_checks.choice("wrap", mode, WRAP_MODES) for mode in wrap)


@dataclasses.dataclass(frozen=True)
class _Material:
    """What a texture bake takes of one material: its triangles and the UV set they are baked into."""

    index: int  # the key of Bake.textures: the glTF material, -1 for triangles without one
    name: str  # for messages
    triangles: np.ndarray
    texcoords: np.ndarray  # (K, 3, 2): the UVs of each triangle's corners
    set: object  # n of TEXCOORD_n, or "generated"
    wrap: tuple
    stats: dict = dataclasses.field(default_factory=dict)  # a generated set's: charts, worst_stretch, texels_per_unit
    layout: object = None  # a generated set's TexelLayout, made while generating it


def _texture_materials(scene, baked, texcoord, wrap):
    """The materials of a texture bake of `scene`'s triangles `baked`, each with its UV set (SPEC 6.3)."""
    if isinstance(scene, Mesh):
        if texcoord not in (None, 0):
            raise ValueError(
                f"texcoord must be None or 0 for an mbao.Mesh (its one set of texcoords), got {texcoord!r}"
            )
        if scene.texcoords is None:
            raise ValueError(
                f"{scene.name}: a texture bake needs UVs, and this mesh has none: give mbao.Mesh "
                f'texcoords=, or bake target="vertices"'
            )
        return [_Material(0, "the mesh", baked, scene.texcoords[scene.indices[baked]], 0, wrap or ("repeat", "repeat"))]
    uv_sets = scene.uv_sets
    if uv_sets is None:
        raise ValueError(
            f"{scene.name}: a texture bake needs the file's UV sets: load it with "
            f"mbao.load(path, texcoords=True), or pass its path; any scene bakes with "
            f'texcoord="generate"'
        )
    materials = []
    for index, triangles in _by_material(scene, baked).items():
        info = (
            uv_sets["materials"][index]
            if index >= 0
            else dict(name="", occlusion_texcoord=None, wrap=("repeat", "repeat"))
        )
        name = f"material {index} ({info['name']!r})" if index >= 0 else "the triangles without a material"
        used = np.unique(scene.indices[triangles])
        has = [n for n, values in enumerate(uv_sets["sets"]) if np.isfinite(values[used]).all()]
        chosen = texcoord
        if chosen is None:
            chosen = info["occlusion_texcoord"]
            if chosen is None:
                chosen = next((n for n in (1, 0) if n in has), None)
            if chosen is None:
                raise ValueError(
                    f"{scene.name}: {name} has no UV set on all its triangles to bake into "
                    f'(TEXCOORD_1 or TEXCOORD_0); bake target="vertices"'
                )
        if chosen not in has:
            raise ValueError(
                f"{scene.name}: {name}: TEXCOORD_{chosen} is missing on some of its triangles; "
                f"it has {', '.join(f'TEXCOORD_{n}' for n in has) or 'no UV set'}"
            )
        corners = uv_sets["sets"][chosen][scene.indices[triangles]]
        materials.append(
            _Material(index, f"{scene.name}: {name}", triangles, corners, chosen, wrap or tuple(info["wrap"]))
        )
    return materials


def _warn_if_packed_closer(name, stats, resolution, padding):
    """SPEC 6.3: charts that fit only closer than `padding` are packed so, with a warning naming the resolution that keeps it."""
    if stats["chart_padding"] == padding:
        return
    keeping = stats["size_keeping_padding"]
    keeping = (
        "no resolution up to 16384 keeps them that far apart"
        if keeping is None
        else f"resolution={_resolution_text(keeping)} keeps them {padding} apart"
    )
    apart = f"{stats['chart_padding']} texel{'s' if stats['chart_padding'] != 1 else ''} apart"
    warn(
        f"{name}: its {stats['charts']} generated charts fit {resolution[0]} x {resolution[1]} texels only "
        f"{apart}, not padding={padding}, at {stats['texels_per_unit']:.3g} texels per unit; {keeping}"
    )


def _resolution_text(size):
    return f"{size[0]}" if size[0] == size[1] else f"({size[0]}, {size[1]})"


def _by_material(scene, baked):
    """{material index: its triangles among `baked`}, for a scene loaded with its UV sets."""
    triangle_materials = scene.uv_sets["triangle_materials"][baked]
    return {index: baked[triangle_materials == index] for index in np.unique(triangle_materials).tolist()}


def _generated_materials(scene, baked, width, height, padding):
    """Per material, a new UV set of charts packed into the texture (SPEC 6.3's texcoord="generate")."""
    if isinstance(scene, Mesh) or scene.uv_sets is None:
        key = 0 if isinstance(scene, Mesh) else -1
        groups = {key: baked}
        names = {key: "the mesh" if isinstance(scene, Mesh) else scene.name}
    else:
        groups = _by_material(scene, baked)
        names = {index: f"{scene.name}: material {index}" for index in groups}
    # The materials' UV sets are independent: generated on all cores at once (the core releases the GIL).
    with concurrent.futures.ThreadPoolExecutor(max_workers=os.cpu_count()) as pool:
        generated = list(
            pool.map(lambda triangles: _core.lightmap_uvs(scene, triangles, width, height, padding), groups.values())
        )
    materials = []
    for (index, triangles), (corners, stats, layout) in zip(groups.items(), generated):
        _warn_if_packed_closer(names[index], stats, (width, height), padding)
        materials.append(
            _Material(index, names[index], triangles, corners, "generated", ("repeat", "repeat"), stats, layout)
        )
    return materials


def _uv_set_name(material):
    return "the generated UV set" if material.set == "generated" else f"UV set TEXCOORD_{material.set}"


def _refuse_or_warn_of_unmapped(scene, material):
    """SPEC 6.3: a material whose triangles' UVs have no area has nothing to
    bake into (refused); one where some have none is baked, with a warning of
    how many are left out. Triangles without surface count for neither."""
    surface = _areas(scene.vertices[scene.indices[material.triangles]]) > 0
    unmapped = int((surface & ~(_areas(material.texcoords) > 0)).sum())
    if unmapped and unmapped == surface.sum():
        raise ValueError(
            f"{material.name}, {_uv_set_name(material)}: the UVs of all its {unmapped} triangles have "
            f"no area (each on a line or a point), so nothing can be baked into them; bake into a new "
            f'UV set of mbao\'s (texcoord="generate"), or per vertex (target="vertices")'
        )
    if unmapped:
        warn(
            f"{material.name}, {_uv_set_name(material)}: {unmapped} of its {int(surface.sum())} triangles "
            f"have UVs without area and are left out of the bake"
        )


def _areas(corners):
    """Twice the area of each triangle of (K, 3, 2) or (K, 3, 3) corners, in float64."""
    corners = corners.astype(np.float64)
    cross = np.cross(corners[:, 1] - corners[:, 0], corners[:, 2] - corners[:, 0])
    return np.abs(cross) if cross.ndim == 1 else np.linalg.norm(cross, axis=1)


def _refuse_claimed_twice(layout, material):
    """SPEC 6.3: a UV set in which any covered texel is claimed twice cannot hold one value per texel."""
    if layout.claimed_twice == 0:
        return
    fraction = layout.claimed_twice / layout.covered_count
    raise _core.Error(
        f"{material.name}, {_uv_set_name(material)}: {fraction:.1%} of its "
        f"{layout.covered_count} covered texels are claimed by more than one surface (overlap: "
        f"mirrored halves, tiled UVs or overlapping islands), so one value per texel cannot serve "
        f'them; bake into a new UV set of mbao\'s (texcoord="generate"), into one without overlaps, '
        f'or per vertex (target="vertices")'
    )
