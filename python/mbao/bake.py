"""Baking multi-bounce AO into assets: a value per vertex (SPEC 6)."""

import dataclasses
import math

import numpy as np

from . import _checks, _core
from ._progress import progress_bar
from .devices import resolve
from .scene import as_scene
from .settings import RENDER, Engine, checked, engine_values

TARGETS = ("vertices",)


@dataclasses.dataclass(frozen=True)
class Bake:
    """What mbao.bake made (SPEC 6).

    target: "vertices".
    values: (N,) float32, per vertex of scene.vertices: the mean of L_b over its
        one-ring weighted by its hat function (1 = open; 1 where no triangle of
        positive area uses it).
    standard_error: (N,) float32, the standard error of each value, from the
        spread of its estimates (0 where a vertex has no surface).
    settings: what it was baked with.
    stats: the renderer's statistics of the bake (rays_secondary, frame_ms, plan, ...).
    """

    target: str
    values: np.ndarray
    standard_error: np.ndarray
    settings: dict
    stats: dict

    def __repr__(self):
        return (f"<mbao.Bake {self.target}: {len(self.values)} values, mean {float(np.mean(self.values)):.3f}, "
                f"{self.stats['frame_ms'] / 1e3:.1f} s on {self.stats['device']}>")


def bake(scene, *, target="vertices", bounces=2, samples=256, rho=1.0, max_distance=math.inf, normals="shading",
         seed=0, max_rays=_core.DEFAULT_MAX_RAYS, engine=None, device=None, progress=True):
    """Bakes b-bounce ambient occlusion (SPEC 1) into values per vertex (SPEC 6.2).

    scene: an mbao.Scene (mbao.load, mbao.Mesh) or the path of a glTF file.
    target: "vertices": a value per vertex of scene.vertices.
    bounces, rho, normals, seed, max_rays: as for mbao.render.
    samples: estimates per vertex, each at its own point of the vertex's
        one-ring with one path of `bounces` segments; in [2, 65536].
    max_distance: the AO radius in world units; inf by default (a bake has no
        camera to suggest one).
    engine: an mbao.Engine, as for render.
    device: as for render.
    progress: True for a tqdm bar over the bake's tiles, False for none, or a
        callable progress(tiles_done, tiles_total).

    A surface is baked on its front side, the side its triangles' corners run
    counter-clockwise seen from (SPEC 6.1). The result is a function of the
    scene, the settings and the seed. The GIL is released while baking; Ctrl-C
    stops after the tile in flight. Returns an mbao.Bake.
    """
    scene = as_scene(scene)
    target = _checks.choice("target", target, TARGETS)
    lo, hi = _core.BAKE_SAMPLES_RANGE
    samples = _checks.integer("samples", samples, lo, hi, f"[{lo}, {hi}]")
    given = dict(bounces=bounces, rho=rho, max_distance=max_distance, normals=normals, seed=seed, max_rays=max_rays)
    values = {name: checked(RENDER[name], value) for name, value in given.items()}
    if engine is not None and not isinstance(engine, Engine):
        raise TypeError(f"engine must be None or an mbao.Engine, got {type(engine).__name__}")
    values.update(engine_values(engine or Engine()))
    with _tile_progress(progress) as on_tile:
        ao, standard_error, stats = _core.bake_vertices(scene, resolve(device), values, samples, on_tile)
    settings = dict(given, target=target, samples=samples)
    return Bake(target, ao, standard_error, settings, stats)


class _tile_progress:
    """progress= as the core takes it: a tqdm bar over the tiles, the caller's callable, or None."""

    def __init__(self, progress):
        if not (isinstance(progress, bool) or callable(progress)):
            raise TypeError(f"progress must be a bool or a callable (tiles_done, tiles_total), "
                            f"got {type(progress).__name__}")
        self._progress = progress
        self._bar = progress_bar(progress is True, None, "bake", "tile")

    def __enter__(self):
        bar = self._bar.__enter__()
        if bar is None:
            return self._progress or None

        def on_tile(done, total):
            bar.total = total
            bar.update(done - bar.n)

        return on_tile

    def __exit__(self, *exc):
        return self._bar.__exit__(*exc)
