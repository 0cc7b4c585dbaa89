"""Converged reference images: progressive path-traced AO with its own error bar per pixel."""

import dataclasses
import json
import math
import os
import time
import warnings

import numpy as np

from . import _checks, _core
from ._progress import progress_bar
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
            raise _core.LoadError(f"{path}: not an mbao reference (channels {tuple(names)}, "
                                  f"expected {_CHANNELS} and an mbao:settings attribute)")
        pixels = image.get_pixels(oiio.FLOAT)
        ao, standard_error, mask = (pixels[..., names.index(name)].copy() for name in _CHANNELS)  # EXR sorts them
        return cls(ao, standard_error, mask > 0.5, json.loads(settings))


_CHANNELS = ("ao", "standard_error", "mask")


def reference(scene, *, camera=None, width=256, height=256, bounces=1, rho=1.0, max_distance=None,
              target_error=2e-3, samples=64, min_passes=8, max_passes=100_000, device=None, progress=True):
    """Renders until the standard error of every covered pixel is at most target_error.

    Each pass is one path-estimator render with `samples` paths per pixel at
    the pixel centre (as the methods compared with it), with its own seed; a
    pixel's passes are independent, so its standard error is the spread of its
    pass values over sqrt(passes). At least min_passes are run, so that the
    spread itself is estimated; at most max_passes, after which the reference
    comes back with a warning and settings["converged"] False.

    scene, camera and max_distance: as for mbao.render (paths taken; no radius
        given: the camera's suggestion, else inf). settings["max_distance"] is
        the radius used.
    progress: a tqdm progress bar over the passes (False: none).
    Returns a Reference.
    """
    scene, camera = as_scene(scene), as_camera(camera)
    target_error = _checks.real("target_error", target_error)
    if not target_error > 0.0:
        raise ValueError(f"target_error must be > 0, got {target_error}")
    min_passes = _checks.integer("min_passes", min_passes, 2, 2**31, "[2, 2**31]")
    max_passes = _checks.integer("max_passes", max_passes, min_passes, 2**31, "[min_passes, 2**31]")
    progress = _checks.boolean("progress", progress)
    width, height = _checks.integer("width", width), _checks.integer("height", height)
    if camera is None:
        camera = scene.default_camera(width, height)
    settings = dict(camera=camera, width=width, height=height, bounces=bounces, samples=samples, estimator="path",
                    rho=rho, max_distance=max_distance)

    started = time.perf_counter()
    running = _RunningMean()
    with progress_bar(progress, min_passes, "reference", "pass") as bar:
        for passes in range(1, max_passes + 1):
            result = render(scene, seed=_FIRST_SEED + passes - 1, device=device, **settings)
            running.add(result.ao)
            worst = float(running.standard_error()[result.mask].max(initial=0.0))
            if bar is not None:
                bar.total = max(passes, min_passes, _passes_needed(passes, worst, target_error, max_passes))
                bar.set_postfix(standard_error=f"{worst:.2g}")
                bar.update(1)
            if passes >= min_passes and worst <= target_error:
                break
    converged = worst <= target_error
    if not converged:
        warnings.warn(f"reference: after {max_passes} passes the largest standard error is {worst:.3g}, "
                      f"above target_error={target_error}", stacklevel=2)
    settings.update(scene=scene.name, camera=_camera_dict(camera), max_distance=result.stats["max_distance"],
                    passes=passes, target_error=target_error,
                    converged=converged, seconds=time.perf_counter() - started)
    return Reference(running.mean.astype(np.float32), running.standard_error().astype(np.float32),
                     result.mask.copy(), settings)


def _camera_dict(camera):
    return dict(eye=list(camera.eye), target=list(camera.target), up=list(camera.up), vfov_deg=camera.vfov_deg)


def reference_camera(reference):
    """The mbao.Camera a Reference was rendered with."""
    c = reference.settings["camera"]
    return _core.Camera(c["eye"], c["target"], c["up"], c["vfov_deg"])


class _RunningMean:
    """Welford's running mean and variance per pixel, in float64."""

    def __init__(self):
        self.count, self.mean, self._squares = 0, 0.0, 0.0

    def add(self, values):
        values = values.astype(np.float64)
        self.count += 1
        delta = values - self.mean
        self.mean = self.mean + delta / self.count
        self._squares = self._squares + delta * (values - self.mean)

    def standard_error(self):
        if self.count < 2:
            return np.full_like(self.mean, np.inf)
        return np.sqrt(self._squares / (self.count - 1) / self.count)


def _passes_needed(passes, worst, target_error, max_passes):
    """The standard error falls as 1/sqrt(passes): the passes it will take at this rate."""
    if worst <= target_error:
        return passes
    if not math.isfinite(worst):  # one pass: no spread yet
        return passes + 1
    return min(max_passes, math.ceil(passes * (worst / target_error) ** 2))
