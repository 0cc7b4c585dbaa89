"""Converged reference images: progressive path-traced AO with its own error bar per pixel."""

import dataclasses
import json
import math
import os
import time
from typing import Any, Optional

import numpy as np

from . import _checks, _core
from ._progress import checked_progress, progress_reporter
from ._types import CameraLike, DeviceLike, Progress, SceneLike
from ._warnings import warn
from .render import render
from .scene import as_camera, as_scene

# Reference passes take their seeds from the top half of the 64-bit range, so
# they share no random numbers with renders at the small seeds people use.
_FIRST_SEED = 2**63


@dataclasses.dataclass(frozen=True)
class Reference:
    """A converged image and how well it converged.

    ao: (H, W) float32, the mean over all passes (1 where camera rays missed).
    standard_error: (H, W) float32, the standard error of that mean per pixel.
    mask: (H, W) bool, where the camera ray hit geometry.
    settings: what it was rendered with (scene, camera, size, bounces, rho,
        max_distance, samples per pass), and how: passes, target_error, converged, seconds.
    """

    ao: np.ndarray
    standard_error: np.ndarray
    mask: np.ndarray
    settings: dict

    def save(self, path):
        """Writes an EXR with channels ao, standard_error and mask, and the settings
        as JSON in its "mbao:settings" attribute; Reference.load reads it back."""
        import OpenImageIO as oiio

        path = os.fspath(path)
        if not path.lower().endswith(".exr"):
            raise ValueError(f"path: a reference is saved as .exr (float channels and metadata), got {path!r}")
        height, width = self.ao.shape
        spec = oiio.ImageSpec(width, height, 3, oiio.FLOAT)
        spec.channelnames = _CHANNELS
        spec.attribute("mbao:settings", json.dumps(self.settings))
        pixels = np.stack([self.ao, self.standard_error, self.mask.astype(np.float32)], axis=-1)
        image = oiio.ImageBuf(spec)
        image.set_pixels(oiio.ROI(0, width, 0, height, 0, 1, 0, 3), np.ascontiguousarray(pixels, np.float32))
        if not image.write(path, oiio.FLOAT):
            raise OSError(f"cannot write {path!r}: {image.geterror()}")

    @classmethod
    def load(cls, path):
        """Reads a reference written by save(); raises mbao.LoadError naming the file otherwise."""
        import OpenImageIO as oiio

        path = os.fspath(path)
        image = oiio.ImageBuf(path)
        if image.has_error:
            raise _core.LoadError(f"{path}: cannot read it as an image: {image.geterror()}")
        spec = image.spec()
        settings = spec.getattribute("mbao:settings")
        names = list(spec.channelnames)
        if sorted(names) != sorted(_CHANNELS) or settings is None:
            raise _core.LoadError(
                f"{path}: not an mbao reference (channels {tuple(names)}, "
                f"expected {_CHANNELS} and an mbao:settings attribute)"
            )
        pixels = image.get_pixels(oiio.FLOAT)
        ao, standard_error, mask = (pixels[..., names.index(name)].copy() for name in _CHANNELS)  # EXR sorts them
        return cls(ao, standard_error, mask > 0.5, json.loads(settings))


_CHANNELS = ("ao", "standard_error", "mask")


def reference(
    scene: SceneLike,
    *,
    camera: CameraLike = None,
    width: int = 256,
    height: int = 256,
    bounces: int = 1,
    rho: float = 1.0,
    max_distance: Optional[float] = None,
    target_error: float = 2e-3,
    samples: int = 64,
    min_passes: int = 8,
    max_passes: int = 100_000,
    device: DeviceLike = None,
    progress: Progress = None,
    client: Any = None,
) -> "Reference":
    """Renders until the standard error of every covered pixel is at most target_error.

    Each pass is one path-estimator render with `samples` paths per pixel at
    the pixel centre (as the methods compared with it), with its own seed; a
    pixel's passes are independent, so its standard error is the spread of its
    pass values over sqrt(passes). Passes run in chunks of 8 (the last one
    cut at max_passes); the target is checked after each chunk, once
    min_passes are done, so that the spread itself is estimated. At most
    max_passes are run, after which the reference comes back with a warning
    and settings["converged"] False.

    scene, camera and max_distance: as for mbao.render (paths taken; no radius
        given: the camera's suggestion, else inf). settings["max_distance"] is
        the radius used.
    progress: as for render, over the passes: None, a bar on a terminal for a
        reference longer than a few seconds; False, none; True, a bar; or a
        callable progress(passes_done, passes_expected), the passes expected
        estimated from the standard error so far.
    client: None renders here. A dask.distributed.Client renders the chunks
        on its workers' devices (`device` is then unused; the scene is sent
        to each worker once), which send back each chunk's mean and sum of
        squared deviations, not its passes. Chunks are combined in chunk
        order, here as there (docs/spec.md 5), so the reference is the one
        rendered here, bit for bit, on the same kind of device; a worker lost
        midway costs its chunks' time, not the result.
    Returns a Reference.
    """
    scene = as_scene(scene)
    target_error = _checks.real("target_error", target_error)
    if not target_error > 0.0:
        raise ValueError(f"target_error must be > 0, got {target_error}")
    min_passes = _checks.integer("min_passes", min_passes, 2, 2**31, "[2, 2**31]")
    max_passes = _checks.integer("max_passes", max_passes, min_passes, 2**31, "[min_passes, 2**31]")
    checked_progress(progress)
    width, height = _checks.integer("width", width), _checks.integer("height", height)
    camera = as_camera(camera, scene, (width, height))
    if camera is None:
        camera = scene.default_camera(width, height)
    settings = dict(
        camera=camera,
        width=width,
        height=height,
        bounces=bounces,
        samples=samples,
        estimator="path",
        rho=rho,
        max_distance=max_distance,
    )

    started = time.perf_counter()
    chunks = [(first, min(_PASSES_PER_CHUNK, max_passes - first)) for first in range(0, max_passes, _PASSES_PER_CHUNK)]
    if client is None:
        rendered = (_chunk(scene, settings, first, count, device) for first, count in chunks)
    else:
        rendered = _chunks_on(client, scene, settings, chunks)
    total = _Moments()
    with progress_reporter(progress, "reference", "pass", min_passes) as report:
        for chunk in rendered:
            total.merge(chunk)
            passes = total.count
            worst = float(total.standard_error()[chunk.mask].max(initial=0.0))
            if report is not None:
                expected = max(passes, min_passes, _passes_needed(passes, worst, target_error, max_passes))
                report(passes, expected, f"standard_error={worst:.2g}")
            if passes >= min_passes and worst <= target_error:
                break
        rendered.close()  # with a client: cancels the chunks not needed
    converged = worst <= target_error
    if not converged:
        warn(
            f"reference: after {max_passes} passes the largest standard error is {worst:.3g}, "
            f"above target_error={target_error}"
        )
    settings.update(
        scene=scene.name,
        camera=_camera_dict(camera),
        max_distance=chunk.max_distance,
        passes=passes,
        target_error=target_error,
        converged=converged,
        seconds=time.perf_counter() - started,
    )
    return Reference(
        total.mean.astype(np.float32), total.standard_error().astype(np.float32), chunk.mask.copy(), settings
    )


# Passes per chunk: what a worker renders and sends back at once, and how
# often the target is checked. Fixed, so that the sums are the same whoever
# renders the chunks.
_PASSES_PER_CHUNK = 8


def _chunks_on(client, scene, settings, chunks):
    """_chunk of each chunk on the cluster's workers, in chunk order."""
    from ._cluster import results_of, scene_for_workers  # only references on a cluster need Dask

    on_cluster = scene_for_workers(client, scene, broadcast=True)
    return results_of(client, ((_chunk, on_cluster, settings, first, count) for first, count in chunks))


def _chunk(scene, settings, first, count, device=None):
    """The moments of passes first .. first + count - 1, added in pass order."""
    moments = _Moments()
    for index in range(first, first + count):
        result = render(scene, seed=_FIRST_SEED + index, device=device, progress=False, **settings)
        moments.add(result.ao)
    moments.mask, moments.max_distance = result.mask, result.stats["max_distance"]
    return moments


def _camera_dict(camera):
    return dict(eye=list(camera.eye), target=list(camera.target), up=list(camera.up), vfov_deg=camera.vfov_deg)


def reference_camera(reference: "Reference") -> _core.Camera:
    """The mbao.Camera a Reference was rendered with."""
    c = reference.settings["camera"]
    return _core.Camera(c["eye"], c["target"], c["up"], c["vfov_deg"])


class _Moments:
    """Per pixel, the count, mean and sum of squared deviations of passes, in
    float64: Welford's update for one pass, Chan et al.'s for a chunk of them."""

    def __init__(self):
        self.count, self.mean, self.squares = 0, 0.0, 0.0
        self.mask, self.max_distance = None, None  # a chunk's: its last pass's

    def add(self, values):
        values = values.astype(np.float64)
        self.count += 1
        delta = values - self.mean
        self.mean = self.mean + delta / self.count
        self.squares = self.squares + delta * (values - self.mean)

    def merge(self, other):
        count = self.count + other.count
        delta = other.mean - self.mean
        self.mean = self.mean + delta * (other.count / count)
        self.squares = self.squares + other.squares + delta * delta * (self.count * other.count / count)
        self.count = count

    def standard_error(self):
        if self.count < 2:
            return np.full_like(self.mean, np.inf)
        return np.sqrt(self.squares / (self.count - 1) / self.count)


def _passes_needed(passes, worst, target_error, max_passes):
    """The standard error falls as 1/sqrt(passes): the passes it will take at this rate."""
    if worst <= target_error:
        return passes
    if not math.isfinite(worst):  # one pass: no spread yet
        return passes + 1
    return min(max_passes, math.ceil(passes * (worst / target_error) ** 2))
