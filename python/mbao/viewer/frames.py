"""The frames of a view: a moving camera's, sized to a frame budget, and a
still camera's, accumulated as render_sequence accumulates them (SPEC 8).

Everything here runs on the render thread; a frame is cancelled between tiles
by its `cancelled` callable, which raises Superseded.
"""

import dataclasses
import math

import numpy as np

from .. import _core
from ..gtao import gtao_multibounce
from ..render import render, render_sequence
from ..settings import RENDER, Engine
from .baked import baked_occlusion

# A moving camera's frame, render and encoding, should take this long: about
# 15 frames a second, with time left for the transfer and the page.
MOVING_FRAME_BUDGET_MS = 60.0
# A moving frame is at least this fraction of the view's width and height.
MOVING_MIN_SCALE = 1 / 16
# Pixels per tile of a still frame: the granularity at which input cancels it.
STILL_TILE_PIXELS = 16384


_STILL_ENGINE = Engine(tile_pixels=STILL_TILE_PIXELS)


class Superseded(Exception):
    """The view changed while its frame was rendering."""


@dataclasses.dataclass
class Frame:
    """A frame as the page gets it: result, an mbao.Result of the image shown."""

    result: object
    frames: int  # accumulated into it: 1 without temporal accumulation
    moving: bool
    standard_error: float = None  # the mean over covered pixels, where a variance is known
    final: bool = False  # no further frame of this view will refine it (StillView says)


def render_settings(settings):
    """The settings of a view that mbao.render takes."""
    values = {name: settings[name] for name in RENDER}
    if settings["method"] != "raytraced":
        values["method"] = "hbao"
    return values


def moving_size(settings, ms_per_pixel):
    """(width, height) of a moving frame: the view's, scaled so that a frame
    at `ms_per_pixel` (None: not measured yet) keeps the frame budget."""
    width, height = settings["width"], settings["height"]
    if ms_per_pixel is None:
        scale = 0.25
    else:
        scale = math.sqrt(MOVING_FRAME_BUDGET_MS / ms_per_pixel / (width * height))
    scale = min(1.0, max(MOVING_MIN_SCALE, scale))
    return max(1, round(width * scale)), max(1, round(height * scale))


def moving_frame(scene, camera, settings, size, device, bake):
    """One frame of a moving camera, at `size`, without history. It is not
    cancelled: it fits the frame budget, and a frame of the camera a moment
    ago shows more than none."""
    values = dict(render_settings(settings), width=size[0], height=size[1])
    if settings["method"] == "baked":
        return _baked_frame(scene, camera, values, device, bake, moving=True)
    result = render(scene, camera=camera, device=device, denoise=settings["denoise"] or None, progress=False, **values)
    return _frame(result, settings, frames=1, moving=True)


class StillView:
    """A still camera's frames: render_sequence's, one at a time, until `frames`."""

    def __init__(self, scene, camera, settings, device, bake):
        self.scene, self.camera, self.settings, self.device, self.bake = scene, camera, settings, device, bake
        self.accumulates = settings["temporal"] and settings["method"] == "raytraced"
        self.limit = self._limit()
        self.done = 0
        self._cancelled = None
        self._sequence = None

    def _limit(self):
        if not self.accumulates:
            return 1
        return self.settings["frames"] or _core.Temporal().max_length

    def next_frame(self, cancelled):
        """The next frame; raises Superseded where `cancelled` does."""
        self._cancelled = cancelled
        if self.settings["method"] == "baked":
            frame = _baked_frame(
                self.scene, self.camera, render_settings(self.settings), self.device, self.bake, moving=False
            )
        elif not self.accumulates:
            frame = self._single()
        else:
            frame = self._accumulated()
        self.done += 1
        frame.final = self.done >= self.limit
        return frame

    def _single(self):
        values = _with_variance(render_settings(self.settings))
        result = render(
            self.scene,
            camera=self.camera,
            device=self.device,
            progress=self._progress,
            denoise=self.settings["denoise"] or None,
            **values,
            engine=_STILL_ENGINE,
        )
        return _frame(result, self.settings, frames=1, moving=False)

    def _accumulated(self):
        if self._sequence is None:
            values = _with_variance(render_settings(self.settings))
            self._sequence = render_sequence(
                self.scene,
                _forever(self.camera),
                temporal=True,
                denoise=self.settings["denoise"] or None,
                device=self.device,
                progress=self._progress,
                engine=_STILL_ENGINE,
                **values,
            )
        # A frame that raises Superseded ends the generator, and this view with it: its session starts another.
        return _frame(next(self._sequence), self.settings, frames=self.done + 1, moving=False)

    def _progress(self, done, total):
        self._cancelled()


def _forever(camera):
    while True:
        yield camera


def _with_variance(values):
    """`values` with the variance estimated, where it can be (SPEC 7.1), for the readout of the standard error."""
    can = values["method"] == "raytraced" and (values["spp"] >= 2 or values["samples"] >= 2)
    return dict(values, variance=True) if can else values


def _frame(result, settings, frames, moving):
    if settings["method"] == "hbao+gtao":
        fitted = gtao_multibounce(np.clip(result.ao, 0, 1), settings["rho"])
        result = dataclasses.replace(result, ao=np.where(result.mask, fitted, result.ao).astype(np.float32))
    standard_error = None
    if result.variance is not None and result.mask.any():
        standard_error = float(np.sqrt(np.maximum(result.variance[result.mask], 0)).mean())
    return Frame(result, frames=frames, moving=moving, standard_error=standard_error)


def _baked_frame(scene, camera, values, device, bake, moving):
    result = baked_occlusion(scene, bake, camera, values["width"], values["height"], device)
    return Frame(result, frames=1, moving=moving)
