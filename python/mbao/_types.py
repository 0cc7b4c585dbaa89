"""The types that the public API's annotations name (PEP 484), for type
checkers and IDEs; nothing here runs."""

import os
from typing import Any, Callable, Mapping, Optional, Union

from . import _core

PathLike = Union[str, "os.PathLike[str]"]
# An mbao.Scene (mbao.Mesh is one) or the path of a scene file, loaded for the call.
SceneLike = Union[_core.Scene, PathLike]
# An mbao.Camera, the path of a camera.json file, "frame", or None (the scene's own camera).
CameraLike = Union[_core.Camera, PathLike, None]
# None (the default device), an index or part of a name from mbao.devices(), an mbao.Device or a pyopencl.Device.
DeviceLike = Union[None, int, str, _core.Device, Any]
# None (a bar on a terminal for long work), False, True, or a callable progress(done, total).
Progress = Union[None, bool, Callable[[int, Optional[int]], object]]
# A dict of mbao.render's arguments with a "scene".
Job = Mapping[str, Any]
