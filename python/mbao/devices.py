"""Which OpenCL device runs the work."""

import numbers
from typing import List

from . import _core


def devices() -> List[_core.Device]:
    """Every OpenCL device of every platform, as mbao.Device objects; device= takes
    their index, a part of their "platform: name", the Device itself or a pyopencl.Device."""
    return _core.devices()


def resolve(device):
    """The mbao.Device that a device= argument names.

    None picks $MBAO_DEVICE if set, else the first GPU, else the first device.
    """
    if device is None:
        return _core.default_device()
    if isinstance(device, _core.Device):
        return device
    if isinstance(device, numbers.Integral) and not isinstance(device, bool):
        if device < 0:
            raise ValueError(f"device index must be >= 0, got {device}")
        return _core.find_device_by_index(int(device))
    if isinstance(device, str):
        return _core.find_device_by_name(device)
    if type(device).__module__.startswith("pyopencl") and hasattr(device, "int_ptr"):
        return _core.find_device_by_handle(device.int_ptr)
    raise TypeError(
        "device must be None, an index, a part of the device's name, an mbao.Device "
        f"or a pyopencl.Device; got {type(device).__name__}"
    )
