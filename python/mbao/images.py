"""Writing images with OpenImageIO."""

import os
from typing import Optional

import numpy as np
from numpy.typing import ArrayLike

from ._types import PathLike

_FLOAT_FORMATS = (".exr", ".hdr", ".tif", ".tiff", ".pfm")


def check_writable(path, argument="path"):
    """Raises ValueError, naming `argument`, where OpenImageIO has no writer for the file name's extension."""
    import OpenImageIO as oiio

    if oiio.ImageOutput.create(os.fspath(path)) is None:
        extension = os.path.splitext(path)[1] or "none"
        raise ValueError(
            f"{argument} {os.fspath(path)!r}: OpenImageIO has no writer for the extension "
            f"({extension}); use .png (8-bit) or .exr (float)"
        )


def save_image(path: PathLike, array: ArrayLike, alpha: Optional[ArrayLike] = None) -> None:
    """Writes a (H, W) or (H, W, C) image; the format follows the file name.

    EXR (and TIFF, HDR, PFM) get 32-bit floats unchanged. PNG and the other
    formats get 8 bits: values clipped to [0, 1], no gamma (AO values are
    stored as they are). Boolean arrays (masks) are written as 0 and 1.

    alpha: None, or an (H, W) array in [0, 1], e.g. a render's coverage, written
    as a last channel (SPEC 2): a straight, not premultiplied, alpha "A" in
    8-bit formats, and a channel named "coverage" in float formats, where "A"
    would be read as premultiplied. Composite a straight alpha over a
    background as ao * alpha + background * (1 - alpha).
    """
    import OpenImageIO as oiio  # imported here: only saving needs it

    if not isinstance(path, (str, os.PathLike)):
        raise TypeError(f"path must be a str or os.PathLike, got {type(path).__name__}")
    path = os.fspath(path)
    data = np.asarray(array)
    if data.dtype.kind not in "fiub":
        raise TypeError(f"array must hold numbers, got dtype {data.dtype}")
    if data.ndim not in (2, 3) or data.size == 0:
        raise ValueError(f"array must be a non-empty (H, W) or (H, W, C) image, got shape {data.shape}")
    # OpenImageIO's Python binding reads arrays as (H, W, C).
    pixels = np.ascontiguousarray(data.reshape(data.shape[0], data.shape[1], -1), dtype=np.float32)
    float_format = os.path.splitext(path)[1].lower() in _FLOAT_FORMATS
    names = None
    if alpha is not None:
        pixels, names = _with_alpha(pixels, alpha, float_format)
    height, width, channels = pixels.shape
    if not float_format:
        pixels = np.clip(pixels, 0.0, 1.0)
    check_writable(path)
    spec = oiio.ImageSpec(width, height, channels, oiio.FLOAT)
    if names:
        spec.channelnames = names
        spec.alpha_channel = channels - 1 if not float_format else -1
        spec.attribute("oiio:UnassociatedAlpha", 1)  # the values as they are: a straight alpha
    image = oiio.ImageBuf(spec)
    image.set_pixels(oiio.ROI(0, width, 0, height, 0, 1, 0, channels), pixels)
    if not image.write(path, oiio.FLOAT if float_format else oiio.UINT8):
        raise OSError(f"cannot write {path!r}: {image.geterror()}")


def _with_alpha(pixels, alpha, float_format):
    """The pixels with `alpha` as a last channel, and the channels' names."""
    alpha = np.asarray(alpha)
    if alpha.dtype.kind not in "fiub":
        raise TypeError(f"alpha must hold numbers, got dtype {alpha.dtype}")
    if alpha.shape != pixels.shape[:2]:
        raise ValueError(f"alpha must have the image's shape {pixels.shape[:2]}, got {alpha.shape}")
    if not np.all((alpha >= 0) & (alpha <= 1)):
        raise ValueError("alpha must be in [0, 1] (a coverage), got values outside it")
    channels = pixels.shape[2]
    colour = {1: ["Y"], 3: ["R", "G", "B"]}.get(channels, [f"channel{k}" for k in range(channels)])
    names = colour + ["coverage" if float_format else "A"]
    return np.concatenate([pixels, alpha.astype(np.float32)[..., None]], axis=2), names
