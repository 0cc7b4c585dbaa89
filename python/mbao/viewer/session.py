"""One client's view: its camera and settings, and the loop that renders them
(docs/viewer.md). The latest state wins: input bumps the view's generation,
and the frame in flight, which checks it between tiles, gives up."""

import asyncio
import io
import json
import logging
import struct
import time

import numpy as np

from .. import _core
from . import messages
from .frames import StillView, Superseded, moving_frame, moving_size

_log = logging.getLogger("mbao")


class ViewSession:
    """A client's view: `send` is a coroutine function that takes the text
    (JSON) or bytes of a message to the page. It renders a first still frame
    of the viewer's camera before the page says anything."""

    def __init__(self, viewer, send):
        self.viewer = viewer
        self._send = send  # a coroutine function taking str (JSON) or bytes
        self.camera = viewer.camera
        self.settings = dict(viewer.settings)
        self.interactive = False
        self.generation = 0
        self.messages_read = 0  # the page's text messages, counted as read: frames say how many their view had seen
        self.last_still = None  # the last still frame's Frame, for saving and snapshots
        self._still = None
        self._ms_per_pixel = None
        self._wake = asyncio.Event()
        self._wake.set()

    # Input, from the page or a script.

    def apply(self, camera=None, settings=None, interactive=None):
        """Takes a checked camera and settings (either may be None: unchanged);
        the frame in flight is dropped and the view starts again."""
        if camera is not None:
            self.camera = camera
        if settings is not None:
            self.settings = settings
        if interactive is not None:
            self.interactive = interactive
        self.generation += 1
        self._still = None
        self._wake.set()

    async def handle(self, text):
        """One message from the page; a bad one is answered with an error and changes nothing."""
        self.messages_read += 1
        try:
            message = messages.parse(text, self.settings, self.viewer.methods, self.viewer.home_camera.max_distance)
        except (TypeError, ValueError) as error:
            await self.send_json(type="error", message=str(error))
            await self.send_state()  # the view as it still is, for a page that took the bad value as set
            return
        if message["type"] == "set":
            self.viewer.active = self
            self.apply(message.get("camera"), message.get("settings"), message.get("interactive"))
        elif message["type"] == "pick":
            point = await self.viewer.run(self.viewer.pick, self.camera, self.settings, message["x"], message["y"])
            await self.send_json(type="picked", point=point)
        elif message["type"] == "save":
            await self._save(message["what"])

    # The render loop.

    async def run(self):
        """Renders what the view asks for until cancelled (the client has gone)."""
        while True:
            await self._wake.wait()
            self._wake.clear()
            generation, camera, messages_read = self.generation, self.camera, self.messages_read
            if self._still is None and not self.interactive:
                self._still = StillView(
                    self.viewer.scene, self.camera, self.settings, self.viewer.device, self.viewer.bake
                )
            try:
                frame, payload = await self.viewer.run(
                    self._render_and_encode,
                    generation,
                    camera,
                    self.settings,
                    None if self.interactive else self._still,
                )
            except Superseded:
                continue
            except (ValueError, TypeError, OSError, _core.Error) as error:
                if generation == self.generation:
                    await self.send_json(type="error", message=str(error))
                continue
            except Exception as error:  # a fault of mbao's: the page is told, and the server serves on
                _log.exception("mbao view: a frame failed")
                await self.send_json(type="error", message=f"internal error: {error!r} (the server's log has more)")
                continue
            if generation != self.generation and not frame.moving:
                continue  # a still frame of a view that has changed: its accumulation is void
            if not frame.moving:
                self.last_still = frame
            await self._send_frame(frame, payload, camera, generation, messages_read)
            if not (frame.final or frame.moving):
                self._wake.set()

    def _render_and_encode(self, generation, camera, settings, still):
        """On the render thread: the next frame of the view as it was at
        `generation` (a moving one where `still` is None), encoded."""

        def cancelled():
            if generation != self.generation:
                raise Superseded()

        cancelled()
        start = time.perf_counter()
        if still is None:
            size = moving_size(settings, self._ms_per_pixel)
            frame = moving_frame(self.viewer.scene, camera, settings, size, self.viewer.device, self.viewer.bake)
            payload = encode(frame.result.ao, "jpeg")
            self._ms_per_pixel = (time.perf_counter() - start) * 1e3 / (size[0] * size[1])
            return frame, payload
        frame = still.next_frame(cancelled)
        if self._ms_per_pixel is None:
            self._ms_per_pixel = (time.perf_counter() - start) * 1e3 / frame.result.ao.size
        return frame, encode(frame.result.ao, "png")

    async def _send_frame(self, frame, payload, camera, generation, messages_read):
        height, width = frame.result.ao.shape
        stats = frame.result.stats
        rays = stats.get("rays_primary", 0) + stats.get("rays_secondary", 0)
        header = dict(
            type="frame",
            format="jpeg" if frame.moving else "png",
            width=width,
            height=height,
            frames=frame.frames,
            final=frame.final,
            moving=frame.moving,
            frame_ms=stats["frame_ms"],
            mrays_per_s=rays / stats["frame_ms"] / 1e3 if stats["frame_ms"] > 0 else None,
            standard_error=frame.standard_error,
            camera=messages.camera_json(camera),
            generation=generation,
            messages_read=messages_read,
        )
        await self._send(pack(header, payload))

    async def _save(self, what):
        if what == "camera":
            radius = self.settings["max_distance"]
            if radius is None:
                radius = self.camera.max_distance
            data = json.dumps(messages.camera_json(self.camera, radius), indent=2).encode()
            await self._send(pack(dict(type="file", name="camera.json", mime="application/json"), data))
            return
        if self.last_still is None:
            await self.send_json(type="error", message=f"no still frame to save as {what} yet")
            return
        data = await self.viewer.run(image_file, self.last_still, what)
        mime = "image/png" if what == "png" else "image/x-exr"
        await self._send(pack(dict(type="file", name=f"ao.{what}", mime=mime), data))

    async def send_json(self, **message):
        await self._send(json.dumps(message, allow_nan=False))

    async def send_state(self):
        await self.send_json(
            type="state", camera=messages.camera_json(self.camera), settings=messages.settings_json(self.settings)
        )


def pack(header, payload):
    """A binary message: the header's JSON length (4 bytes, little-endian), the JSON, then the payload."""
    text = json.dumps(header, allow_nan=False).encode()
    return struct.pack("<I", len(text)) + text + payload


def to_8bit(ao):
    """The 8-bit values mbao.save_image writes for `ao` (clipped, rounded to nearest)."""
    return np.floor(np.clip(ao, 0.0, 1.0) * 255.0 + 0.5).astype(np.uint8)


def encode(ao, kind):
    """The image as the page shows it: a grey PNG (save_image's values) or a JPEG."""
    from PIL import Image

    out = io.BytesIO()
    image = Image.fromarray(to_8bit(ao), mode="L")
    if kind == "png":
        image.save(out, format="PNG", compress_level=1)
    else:
        image.save(out, format="JPEG", quality=85)
    return out.getvalue()


def image_file(frame, what):
    """The still frame as mbao.save_image writes it, with its coverage as alpha: PNG or EXR bytes."""
    import os
    import tempfile

    from ..images import save_image

    with tempfile.TemporaryDirectory() as folder:
        path = os.path.join(folder, f"ao.{what}")
        save_image(path, frame.result.ao, alpha=frame.result.coverage)
        with open(path, "rb") as file:
            return file.read()
