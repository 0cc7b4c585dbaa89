"""The live viewer: `python -m mbao view` and, in a notebook, mbao.view (docs/viewer.md)."""

import html
import types
from typing import Any, Optional

from .. import _core
from .._types import CameraLike, DeviceLike, SceneLike
from ..devices import resolve
from ..scene import as_camera, is_gltf_path, load
from ..render import render_size
from ..stored_bake import load_bake
from .frames import StillView
from .server import BackgroundServer, Viewer

__all__ = ["View", "view", "open_viewer"]


def open_viewer(scene=None, *, camera=None, device=None, host="127.0.0.1", port=None, token=None, **settings):
    """A Viewer of `scene` (None: the built-in Cornell box; a path: any file
    mbao.load reads, with the bake a glTF file holds), not yet serving;
    the other arguments are Viewer's and the view's settings."""
    bake = None
    if scene is None:
        scene = _core.cornell_box()
    elif not isinstance(scene, _core.Scene):
        path = scene
        scene = load(path, texcoords=is_gltf_path(path))  # only a glTF file stores a bake mbao reads
        bake = load_bake(path, scene)
    return Viewer(
        scene,
        as_camera(camera, scene, render_size(settings)),
        settings,
        resolve(device),
        bake=bake,
        host=host,
        port=port,
        token=token,
    )


class View:
    """A live view served to the notebook's cell (mbao.view's result).

    camera: the view's camera as its page last set it; assign an mbao.Camera
        (or a camera.json path) and every page showing it follows.
    settings: the view's settings, read-only; assign a dict of the ones to
        change (`v.settings = {"bounces": 2}`) and the pages follow.
    snapshot(): an mbao.Result of the view as it stands.
    close(): stops the server; the cell's view goes blank.
    """

    def __init__(self, viewer, server, cell_height):
        self._viewer, self._server, self._cell_height = viewer, server, cell_height

    @property
    def url(self):
        return self._viewer.url

    @property
    def camera(self):
        session = self._active()
        return session.camera if session else self._viewer.camera

    @camera.setter
    def camera(self, camera):
        camera = as_camera(camera)
        if camera is None:
            raise TypeError("camera must be an mbao.Camera or the path of a camera.json file")
        self._viewer.broadcast(camera=camera)

    @property
    def settings(self):
        session = self._active()
        return types.MappingProxyType(dict(session.settings if session else self._viewer.settings))

    @settings.setter
    def settings(self, changes):
        self._viewer.broadcast(settings=changes)

    def snapshot(self):
        """The view's last still frame as an mbao.Result (its accumulation so
        far), or, before the page has shown one, a render of the view."""
        session = self._active()
        if session is not None and session.last_still is not None:
            return session.last_still.result
        viewer = self._viewer
        first = StillView(viewer.scene, self.camera, dict(self.settings), viewer.device, viewer.bake)
        return first.next_frame(cancelled=lambda: None).result

    def show(self):
        """Shows the view in the cell's output (mbao.view does on its own)."""
        from IPython.display import HTML, display

        display(HTML(self._iframe()))

    def close(self):
        self._server.close()

    def _active(self):
        return self._viewer.active

    def _iframe(self):
        return (
            f'<iframe src="{html.escape(self.url)}" title="mbao view" style="width: 100%; '
            f'height: {int(self._cell_height)}px; border: 0"></iframe>'
        )

    def __repr__(self):
        return f"<mbao.View of {self._viewer.scene.name} at {self.url}>"


def view(
    scene: Optional[SceneLike] = None,
    *,
    camera: CameraLike = None,
    device: DeviceLike = None,
    host: str = "127.0.0.1",
    port: Optional[int] = None,
    cell_height: int = 620,
    **settings: Any,
) -> "View":
    """Shows a live, progressive view of `scene` in a notebook cell and returns
    its handle, an mbao.View.

    scene: an mbao.Scene, the path of a file mbao.load reads, or None for the
        built-in Cornell box.
    camera: the home camera (an mbao.Camera or camera.json path); None: the scene's own.
    settings: render's (bounces, samples, rho, max_distance, width, height, ...),
        method ("raytraced", "hbao", "hbao+gtao", or "baked" for a file that
        holds a bake), denoise, temporal and frames (docs/viewer.md).
    host, port: where the server listens: 127.0.0.1 and a free port from 8750
        by default. Another address needs the token the URL carries.
    cell_height: the height of the view in the cell's output, in pixels.

    The page is served by a server in this process, which the browser showing
    the notebook must reach: on another machine, forward the port (docs/viewer.md).
    """
    viewer = open_viewer(scene, camera=camera, device=device, host=host, port=port, **settings)
    handle = View(viewer, BackgroundServer(viewer), cell_height)
    if _in_a_kernel():
        handle.show()
    return handle


def _in_a_kernel():
    """Whether this runs in a Jupyter kernel, whose front end shows HTML (a script's IPython prints it)."""
    try:
        from IPython import get_ipython
    except ImportError:
        return False
    shell = get_ipython()
    return shell is not None and getattr(shell, "kernel", None) is not None
