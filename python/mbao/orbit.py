"""Camera orbits: the cameras of one, and a rendered sequence written as an animated GIF (python -m mbao orbit)."""

import math
import os

import numpy as np

from ._core import Camera


def orbit_cameras(camera, frames, degrees=360.0):
    """`frames` cameras whose eyes turn about the vertical line through
    camera.target (along camera.up), right-handed, `degrees` in all: the first
    is `camera`, and a full turn stops one step short of it, so that it loops."""
    if isinstance(frames, bool) or not isinstance(frames, int) or frames < 1:
        raise ValueError(f"frames must be an integer >= 1, got {frames!r}")
    if not math.isfinite(degrees):
        raise ValueError(f"degrees must be finite, got {degrees}")
    eye, target, up = (np.asarray(v, float) for v in (camera.eye, camera.target, camera.up))
    axis = up / np.linalg.norm(up)
    offset = eye - target
    cameras = []
    for k in range(frames):
        angle = math.radians(degrees) * k / frames
        # Rodrigues' rotation of the eye's offset from the target about the axis.
        turned = (
            offset * math.cos(angle)
            + np.cross(axis, offset) * math.sin(angle)
            + axis * np.dot(axis, offset) * (1.0 - math.cos(angle))
        )
        cameras.append(Camera(tuple(target + turned), camera.target, camera.up, camera.vfov_deg, camera.max_distance))
    return cameras


def check_gif(path, fps, argument="path"):
    """Raises ValueError, naming `argument`, unless `path` is a .gif and fps one that GIF can time."""
    if not os.fspath(path).lower().endswith(".gif"):
        raise ValueError(f"{argument} {os.fspath(path)!r}: an orbit is written as .gif")
    if not 0.0 < fps <= 100.0:
        raise ValueError(f"fps must be in (0, 100] (GIF times frames in hundredths of a second), got {fps:g}")


def save_gif(path, images, fps=25.0):
    """Writes (H, W) images in [0, 1] as a looping animated GIF of 8-bit greys,
    values as they are (no gamma), as save_image's PNGs. GIF times frames in
    hundredths of a second, so fps is rounded to 100 / a whole number."""
    from PIL import Image  # imported here: only orbits need Pillow

    check_gif(path, fps)
    frames = [
        Image.fromarray(np.round(np.clip(image, 0.0, 1.0) * 255.0).astype(np.uint8), mode="L") for image in images
    ]
    if not frames:
        raise ValueError("an orbit needs at least one frame")
    frames[0].save(os.fspath(path), save_all=True, append_images=frames[1:], duration=10 * round(100.0 / fps), loop=0)
