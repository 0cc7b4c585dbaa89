"""Argument checks that name the argument and what it allows."""

import numbers

import numpy as np


def integer(name, value, lo=-(2**63), hi=2**63 - 1, range_text=None):
    """An int (numpy integers too, bools not) in [lo, hi]; the C++ core checks
    the narrower ranges of the settings, this one what fits its 64 bits."""
    if isinstance(value, (bool, np.bool_)) or not isinstance(value, numbers.Integral):
        raise TypeError(f"{name} must be an integer, got {type(value).__name__} {value!r}")
    value = int(value)
    if not lo <= value <= hi:
        raise ValueError(f"{name} must be in {range_text or f'[{lo}, {hi}]'}, got {value}")
    return value


def real(name, value):
    """A real number (ints too, bools not), as a float."""
    if isinstance(value, (bool, np.bool_)) or not isinstance(value, numbers.Real):
        raise TypeError(f"{name} must be a number, got {type(value).__name__} {value!r}")
    return float(value)


def boolean(name, value):
    if not isinstance(value, (bool, np.bool_)):
        raise TypeError(f"{name} must be a bool, got {type(value).__name__}")
    return bool(value)


def choice(name, value, allowed):
    if not isinstance(value, str):
        raise TypeError(f"{name} must be a string, one of {', '.join(map(repr, allowed))}; got {value!r}")
    if value not in allowed:
        raise ValueError(f"{name} must be one of {', '.join(map(repr, allowed))}; got {value!r}")
    return value


def rows(name, value, columns, kinds, dtype):
    """An (N, columns) array of a dtype kind in `kinds`, as a C-contiguous `dtype` copy or view."""
    try:
        array = np.asarray(value)
    except Exception as error:  # ragged lists and the like
        raise TypeError(f"{name} must be an ({'N'}, {columns}) array: {error}") from None
    if array.dtype.kind not in kinds:
        raise TypeError(f"{name} must hold {_kind_names(kinds)}, got dtype {array.dtype}")
    if array.ndim != 2 or array.shape[1] != columns:
        raise ValueError(f"{name} must have shape (N, {columns}), got {array.shape}")
    with np.errstate(over="ignore"):  # reported below, naming the row
        converted = np.ascontiguousarray(array, dtype=dtype)
    if converted.dtype.kind == "f" and array.dtype.kind in "fiu":
        overflowed = np.isinf(converted) & np.isfinite(array)
        if overflowed.any():
            row = int(np.flatnonzero(overflowed.any(axis=1))[0])
            raise ValueError(
                f"{name}: row {row} holds {array[row].tolist()}, beyond the range of {np.dtype(dtype).name} "
                f"(+-{np.finfo(dtype).max:.3g})"
            )
    return converted


def _kind_names(kinds):
    names = {"f": "floats", "i": "integers", "u": "unsigned integers"}
    return " or ".join(names[k] for k in kinds)
