"""The viewer's web server (docs/viewer.md): the page, its static files and a
WebSocket per client, for one scene. Loopback-only unless told otherwise; any
other address needs the token printed in the URL."""

import asyncio
import concurrent.futures
import importlib.resources
import ipaddress
import math
import secrets
import threading

import numpy as np
from aiohttp import WSMsgType, web

from ..render import trace
from . import messages, view_settings
from .session import ViewSession

# The page's files, by the only names a client can ask for: no path it sends reaches the file system.
STATIC_FILES = {"index.html": "text/html", "viewer.js": "text/javascript", "viewer.css": "text/css"}
DEFAULT_PORT = 8750
PORT_RETRIES = 50  # ports tried after a busy default one, as Jupyter does
_TOKEN_COOKIE = "mbao_view_token"


class Viewer:
    """A scene served to every client that connects, each with a view of its own.

    scene: an mbao.Scene; camera: the view's home camera (None: the scene's
    own, else one framing it); settings: the views' first settings
    (view_settings); bake: what load_bake found in the file, or None.
    port: None for the first free one from DEFAULT_PORT, 0 for any.
    token: what every request must carry (?token=, then a cookie); None: a
    random one where the host is not loopback, else none."""

    def __init__(self, scene, camera, settings, device, bake=None, host="127.0.0.1", port=None, token=None):
        self.scene, self.device, self.bake = scene, device, bake
        self.methods = tuple(m for m in view_settings.METHODS if m != "baked" or bake is not None)
        self.settings = view_settings.updated(view_settings.defaults(), settings, self.methods)
        self.home_camera = camera or scene.default_camera(self.settings["width"], self.settings["height"])
        self.camera = self.home_camera  # a new view's: a script may set it
        self.host, self.port = host, port
        self.token = token if token is not None or _is_loopback(host) else secrets.token_urlsafe(24)
        self.sessions = []
        self.active = None  # the session whose page changed its view last: the one a notebook's handle reads
        self._sockets = set()
        # One render thread for every client: they share the device, and a frame at a time keeps each fast.
        self._executor = concurrent.futures.ThreadPoolExecutor(1, thread_name_prefix="mbao-view")
        self._runner = None
        self.loop = None

    @property
    def url(self):
        host = f"[{self.host}]" if ":" in self.host else self.host
        return f"http://{host}:{self.port}/" + (f"?token={self.token}" if self.token else "")

    async def run(self, function, *args):
        """`function(*args)` on the render thread."""
        return await asyncio.get_running_loop().run_in_executor(self._executor, function, *args)

    # Serving.

    async def start(self):
        """Binds and starts serving; self.port is then the port bound."""
        self.loop = asyncio.get_running_loop()
        app = web.Application(middlewares=[self._guard])
        app.router.add_get("/", self._index)
        app.router.add_get("/static/{name}", self._static)
        app.router.add_get("/ws", self._websocket)
        self._runner = web.AppRunner(app, handle_signals=False, access_log=None)
        await self._runner.setup()
        for port in self._ports():
            site = web.TCPSite(self._runner, self.host, port)
            try:
                await site.start()
            except OSError as error:
                if self.port is not None or port == DEFAULT_PORT + PORT_RETRIES:
                    await self._runner.cleanup()
                    raise OSError(f"cannot serve on {self.host}:{port}: {error.strerror or error}") from None
                continue
            self.port = self._runner.addresses[0][1]
            return

    def _ports(self):
        if self.port is not None:
            return [self.port]
        return range(DEFAULT_PORT, DEFAULT_PORT + PORT_RETRIES + 1)

    async def stop(self):
        for session in self.sessions:
            session.generation += 1  # the frame in flight stops at its next tile
        for socket in list(self._sockets):
            await socket.close()
        if self._runner is not None:
            await self._runner.cleanup()
        self._executor.shutdown(wait=True, cancel_futures=True)

    @web.middleware
    async def _guard(self, request, handler):
        """The token, where one is needed, and the Host header, against DNS rebinding where none is."""
        if self.token is not None:
            given = request.query.get("token") or request.cookies.get(_TOKEN_COOKIE) or ""
            if not secrets.compare_digest(given, self.token):
                raise web.HTTPForbidden(text="mbao view: this server needs the token its URL carries (?token=...)\n")
        elif not _is_loopback(request.url.host or ""):
            raise web.HTTPForbidden(text=f"mbao view: serves loopback hosts only, not {request.host!r}\n")
        response = await handler(request)
        if self.token is not None and not isinstance(response, web.WebSocketResponse):
            response.set_cookie(_TOKEN_COOKIE, self.token, httponly=True, samesite="Strict")
        return response

    async def _index(self, request):
        return self._file("index.html")

    async def _static(self, request):
        name = request.match_info["name"]
        if name not in STATIC_FILES:
            raise web.HTTPNotFound()
        return self._file(name)

    def _file(self, name):
        text = importlib.resources.files(__package__).joinpath("static", name).read_text(encoding="utf-8")
        return web.Response(text=text, content_type=STATIC_FILES[name], headers={"Cache-Control": "no-store"})

    async def _websocket(self, request):
        origin = request.headers.get("Origin")
        if origin is not None and origin != f"{request.scheme}://{request.host}":
            raise web.HTTPForbidden(text=f"mbao view: WebSocket from another origin ({origin}) refused\n")
        socket = web.WebSocketResponse(max_msg_size=messages.MAX_MESSAGE_BYTES, heartbeat=30)
        await socket.prepare(request)
        session = ViewSession(self, _sender(socket))
        self.sessions.append(session)
        self.active = self.active or session
        self._sockets.add(socket)
        renderer = asyncio.create_task(session.run())
        try:
            await session.send_json(type="hello", **self.hello())
            async for message in socket:
                if message.type == WSMsgType.TEXT:
                    await session.handle(message.data)
                elif message.type == WSMsgType.BINARY:
                    await session.send_json(type="error", message="messages are JSON text, got binary data")
        finally:
            session.generation += 1  # drops the frame in flight: a client that goes stops its work
            renderer.cancel()
            self.sessions.remove(session)
            self._sockets.discard(socket)
            if self.active is session:
                self.active = self.sessions[-1] if self.sessions else None
        return socket

    def hello(self):
        """What the page learns first: the scene, the device, the home camera
        and the view's first, the settings and their specs."""
        lo, hi = (np.asarray(corner) for corner in self.scene.bounds)
        return dict(
            scene=dict(
                name=self.scene.name,
                triangles=self.scene.triangle_count,
                bounds=[lo.tolist(), hi.tolist()],
                radius=self.suggested_radius(),
                default_radius=self._default_radius(),
            ),
            device=self.device.name,
            home=messages.camera_json(self.home_camera),
            camera=messages.camera_json(self.camera),
            settings=messages.settings_json(self.settings),
            specs=view_settings.described(self.methods),
        )

    def suggested_radius(self):
        """The radius the slider centres on: the camera's suggestion, else a quarter of the scene's diagonal (SPEC 1)."""
        if self.home_camera.max_distance is not None:
            return self.home_camera.max_distance
        lo, hi = (np.asarray(corner) for corner in self.scene.bounds)
        return float(np.linalg.norm(hi - lo)) / 4

    def _default_radius(self):
        """The radius a render takes where the settings give none (SPEC 1): the camera's suggestion, else unlimited."""
        radius = self.home_camera.max_distance
        return messages.UNLIMITED if radius is None or math.isinf(radius) else radius

    # Work the sessions ask for.

    def pick(self, camera, settings, x, y):
        """The scene point under the image point (x, y) (fractions, from the top left), or None."""
        direction = _ray_direction(camera, settings["width"] / settings["height"], x, y)
        t, triangle, _ = trace(self.scene, np.array([camera.eye]), direction[None], device=self.device)
        if triangle[0] < 0:
            return None
        return (np.asarray(camera.eye) + float(t[0]) * direction).tolist()

    def broadcast(self, camera=None, settings=None):
        """Sets every view's camera or settings (checked), and tells their pages (from any thread)."""
        settings = None if settings is None else view_settings.updated(self.settings, settings, self.methods)

        async def apply():
            if camera is not None:
                self.camera = camera
            if settings is not None:
                self.settings = settings
            for session in self.sessions:
                session.apply(camera, settings, interactive=False)
                await session.send_state()

        asyncio.run_coroutine_threadsafe(apply(), self.loop).result()


def _sender(socket):
    async def send(data):
        if socket.closed:
            return
        if isinstance(data, str):
            await socket.send_str(data)
        else:
            await socket.send_bytes(data)

    return send


def _is_loopback(host):
    if host == "localhost":
        return True
    try:
        return ipaddress.ip_address(host.strip("[]")).is_loopback
    except ValueError:
        return False


def _ray_direction(camera, aspect, x, y):
    """The direction through image point (x, y) of a pinhole camera (SPEC 3.1)."""
    eye, target, up = (np.asarray(v, dtype=np.float64) for v in (camera.eye, camera.target, camera.up))
    forward = (target - eye) / np.linalg.norm(target - eye)
    right = np.cross(forward, up)
    right /= np.linalg.norm(right)
    true_up = np.cross(right, forward)
    half = math.tan(math.radians(camera.vfov_deg) / 2)
    direction = forward + (2 * x - 1) * half * aspect * right + (1 - 2 * y) * half * true_up
    return (direction / np.linalg.norm(direction)).astype(np.float32)


class BackgroundServer:
    """A Viewer served from a thread of its own, as a notebook needs (its kernel's loop is busy)."""

    def __init__(self, viewer):
        self.viewer = viewer
        self._loop = asyncio.new_event_loop()
        started = concurrent.futures.Future()
        self._thread = threading.Thread(target=self._serve, args=(started,), name="mbao-view-server", daemon=True)
        self._thread.start()
        started.result()

    def _serve(self, started):
        asyncio.set_event_loop(self._loop)
        try:
            self._loop.run_until_complete(self.viewer.start())
        except BaseException as error:  # reaches the caller through the future
            started.set_exception(error)
            return
        started.set_result(None)
        self._loop.run_forever()

    def close(self):
        if not self._loop.is_running():
            return
        asyncio.run_coroutine_threadsafe(self.viewer.stop(), self._loop).result()
        self._loop.call_soon_threadsafe(self._loop.stop)
        self._thread.join()
        self._loop.close()
