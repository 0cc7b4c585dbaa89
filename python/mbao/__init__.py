"""mbao: multi-bounce ambient occlusion, ray traced with OpenCL.

    import mbao
    scene = mbao.cornell_box()            # or mbao.load("scene.glb"), or mbao.Mesh(vertices, indices)
    result = mbao.render(scene, bounces=2)
    mbao.save_image("ao.png", result.ao)

What is computed, and every convention, is defined in docs/spec.md (section numbers
in the docstrings refer to it).
"""

from .bake import Bake, bake
from .batch import render_many
from .bake_file import bake_file
from . import _core
from ._core import (
    DEFAULT_MAX_RAYS,
    HBAO,
    Camera,
    Denoise,
    Device,
    DeviceError,
    Error,
    LoadError,
    Scene,
    Temporal,
    cornell_box,
)
from .convergence import convergence, format_convergence, plot_convergence
from .devices import devices
from .gtao import gtao_multibounce
from .images import save_image
from .reference import Reference, reference, reference_camera
from .render import GBuffer, Result, gbuffer, render, render_sequence, trace
from .scene import Mesh, load
from .settings import Engine
from .stored_bake import StoredBake, load_bake
from ._signatures import give_signatures

give_signatures(Camera, Denoise, Device, HBAO, Scene, Temporal)

__all__ = [
    "DEFAULT_MAX_RAYS",
    "Bake",
    "Camera",
    "Denoise",
    "Device",
    "DeviceError",
    "Engine",
    "GBuffer",
    "HBAO",
    "Error",
    "LoadError",
    "Mesh",
    "Reference",
    "Result",
    "Scene",
    "StoredBake",
    "Temporal",
    "bake",
    "bake_file",
    "convergence",
    "cornell_box",
    "devices",
    "format_convergence",
    "gbuffer",
    "gtao_multibounce",
    "load",
    "load_bake",
    "plot_convergence",
    "reference",
    "reference_camera",
    "render",
    "render_many",
    "render_sequence",
    "save_image",
    "trace",
    "view",
    "View",
]


def __getattr__(name):
    """mbao.view and mbao.View, imported on first use: only the viewer needs its web server (aiohttp)."""
    if name in ("view", "View"):
        from . import viewer

        return getattr(viewer, name)
    raise AttributeError(f"module 'mbao' has no attribute {name!r}")


__version__ = _core.__version__  # the repository's VERSION, as the module was built with it
