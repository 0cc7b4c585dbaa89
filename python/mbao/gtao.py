"""The multi-bounce fit of GTAO (Jimenez et al. 2016): cheap interreflection from one bounce."""

from typing import Union

import numpy as np
from numpy.typing import ArrayLike


def gtao_multibounce(visibility: ArrayLike, rho: Union[float, ArrayLike]) -> np.ndarray:
    """Approximates b-bounce access from single-bounce access.

    visibility: 1-bounce access x in [0, 1] (HBAO's or ray-traced b = 1), any shape.
    rho: albedo in [0, 1], a number or an array that broadcasts against visibility.

    Jimenez et al. fitted a cubic in x per albedo to ground truth of their scenes:
    a = 2.0404 rho - 0.3324, b = -4.7951 rho + 0.6417, c = 2.7552 rho + 0.6903,
    result max(x, ((a x + b) x + c) x). It never darkens x, and for rho = 0 it is x
    within the fit's error. Returned as float32, the shape of the broadcast inputs.
    """
    x = _unit_interval("visibility", visibility)
    albedo = _unit_interval("rho", rho)
    a = 2.0404 * albedo - 0.3324
    b = -4.7951 * albedo + 0.6417
    c = 2.7552 * albedo + 0.6903
    return np.maximum(x, ((a * x + b) * x + c) * x).astype(np.float32)


def _unit_interval(name, value):
    if isinstance(value, (bool, np.bool_)):
        raise TypeError(f"{name} must be a number or an array of numbers, got a bool")
    array = np.asarray(value)
    if array.dtype.kind not in "fiu":
        raise TypeError(f"{name} must hold numbers, got dtype {array.dtype}")
    array = array.astype(np.float64)
    if not np.all((array >= 0.0) & (array <= 1.0)):  # NaN fails too
        raise ValueError(f"{name} must be in [0, 1]")
    return array
