"""A viewer served from a thread, and a WebSocket client of it that speaks the
page's protocol (docs/viewer.md), for the viewer's tests."""

import asyncio
import contextlib
import io
import json
import struct
import time

import aiohttp
import numpy as np
from PIL import Image

from mbao.viewer import open_viewer
from mbao.viewer.server import BackgroundServer

# Every wait in these tests is bounded: a frame comes within this many seconds or the test fails.
FRAME_TIMEOUT_S = 120


@contextlib.contextmanager
def served(scene=None, **options):
    """A viewer serving on 127.0.0.1 and a free port, stopped after."""
    viewer = open_viewer(scene, port=0, **options)
    server = BackgroundServer(viewer)
    try:
        yield viewer
    finally:
        server.close()


def decode(payload):
    """A frame's image as (H, W) uint8."""
    return np.asarray(Image.open(io.BytesIO(payload)))


class Client:
    """One page's socket: `hello` is the server's first message."""

    def __init__(self, socket, hello):
        self.socket, self.hello = socket, hello
        self.sent = 0  # text messages sent, as the server counts them in a frame's messages_read

    async def send(self, **message):
        await self.socket.send_str(json.dumps(message))
        self.sent += 1

    async def receive(self):
        """The next message: (header, payload) for a binary one, (message, None) for text."""
        message = await self.socket.receive(timeout=FRAME_TIMEOUT_S)
        if message.type == aiohttp.WSMsgType.TEXT:
            return json.loads(message.data), None
        assert message.type == aiohttp.WSMsgType.BINARY, message
        length = struct.unpack("<I", message.data[:4])[0]
        return json.loads(message.data[4 : 4 + length]), message.data[4 + length :]

    async def until(self, accept):
        """Messages until one for which accept(message, payload) holds; returns it."""
        deadline = time.monotonic() + FRAME_TIMEOUT_S
        while time.monotonic() < deadline:
            message, payload = await self.receive()
            if accept(message, payload):
                return message, payload
        raise TimeoutError("no such message within the time limit")

    async def still_frame(self, frames):
        """The still frame that has accumulated `frames` frames of the view as
        this client last set it: the view's first frames, from before the
        server read the set, may arrive after it was sent."""
        return await self.until(
            lambda m, p: m["type"] == "frame"
            and not m["moving"]
            and m["frames"] == frames
            and m["messages_read"] == self.sent
        )

    async def error(self):
        message, _ = await self.until(lambda m, p: m["type"] == "error")
        return message["message"]


@contextlib.asynccontextmanager
async def connected(viewer, headers=None):
    async with aiohttp.ClientSession() as http:
        async with http.ws_connect(viewer.url.split("?")[0] + "ws" + _query(viewer), headers=headers) as socket:
            hello = json.loads((await socket.receive(timeout=FRAME_TIMEOUT_S)).data)
            assert hello["type"] == "hello", hello
            yield Client(socket, hello)


def _query(viewer):
    return f"?token={viewer.token}" if viewer.token else ""


def run(coroutine):
    return asyncio.run(coroutine)
