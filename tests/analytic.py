"""Closed-form answers and the statistics to compare estimates with them."""

import math

import numpy as np

import mbao


def polygon_occlusion(point, normal, polygon):
    """The cosine-weighted fraction of the hemisphere a convex polygon covers,
    seen from `point` (Lambert's formula for the form factor of a polygon)."""
    v = np.asarray(polygon, float) - point
    total = 0.0
    for a, b in zip(v, np.roll(v, -1, axis=0)):
        angle = math.acos(np.clip(np.dot(a, b) / (np.linalg.norm(a) * np.linalg.norm(b)), -1, 1))
        g = np.cross(a, b)
        total += angle * np.dot(normal, g / np.linalg.norm(g))
    return abs(total) / (2.0 * math.pi)


def _spec_basis(camera):
    """SPEC 3.1's eye, forward, right, up' and tan(vfov / 2)."""
    eye, target, up = (np.asarray(v, float) for v in (camera.eye, camera.target, camera.up))
    forward = (target - eye) / np.linalg.norm(target - eye)
    right = np.cross(forward, up)
    right /= np.linalg.norm(right)
    return eye, forward, right, np.cross(right, forward), math.tan(math.radians(camera.vfov_deg) / 2.0)


def spec_ray_directions(camera, width, height):
    """Pixel-centre ray directions, (height, width, 3), straight from SPEC 3.1."""
    _, forward, right, true_up, tan_half = _spec_basis(camera)
    u = ((np.arange(width) + 0.5) / width) * 2.0 - 1.0
    v = 1.0 - ((np.arange(height) + 0.5) / height) * 2.0
    d = forward + u[None, :, None] * tan_half * (width / height) * right + v[:, None, None] * tan_half * true_up
    return d / np.linalg.norm(d, axis=2, keepdims=True)


def spec_image_position(camera, width, height, points):
    """SPEC 3.1 inverted: the pixel coordinates (x, y) of (N, 3) points, each
    pixel's centre at its column and row."""
    eye, forward, right, true_up, tan_half = _spec_basis(camera)
    d = points - eye
    depth = d @ forward
    u, v = (d @ right) / (depth * tan_half * (width / height)), (d @ true_up) / (depth * tan_half)
    return (u + 1.0) * 0.5 * width - 0.5, (1.0 - v) * 0.5 * height - 0.5


def one_pixel_access(scene, eye, target, **settings):
    """L at the point the camera ray through a 1x1 image meets (the pixel centre
    looks straight at target)."""
    camera = mbao.Camera(eye, target, up=(0, 1, 0), vfov_deg=10.0)
    result = mbao.render(scene, camera=camera, width=1, height=1, **settings)
    assert result.mask[0, 0]
    return float(result.ao[0, 0]), result.stats


def assert_within_standard_errors(estimate, expected, samples, k=4.0):
    """A mean of `samples` Bernoulli(expected) outcomes lies within k standard errors."""
    standard_error = math.sqrt(expected * (1.0 - expected) / samples)
    assert (
        abs(estimate - expected) <= k * standard_error
    ), f"{estimate} is {abs(estimate - expected) / standard_error:.1f} standard errors from {expected}"
