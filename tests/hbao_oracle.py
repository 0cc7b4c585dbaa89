"""HBAO as SPEC 4 defines it, in numpy and double precision: the oracle the
kernel is tested against. It reads the G-buffer's points and normals as they
are (no depth reconstruction, exact sin and cos), and draws its jitter from
the same Philox4x32-10 words as the kernel."""

import numpy as np

M0, M1, W0, W1 = 0xD2511F53, 0xCD9E8D57, 0x9E3779B9, 0xBB67AE85
MASK = np.uint64(0xFFFFFFFF)


def philox4x32_10(counter, key):
    """Philox4x32-10 (Salmon et al. 2011) of arrays of counters (4, n) uint64 and a key (2 ints)."""
    x = [np.asarray(word, dtype=np.uint64) & MASK for word in counter]
    k0, k1 = np.uint64(key[0]), np.uint64(key[1])
    for _ in range(10):
        product0, product1 = np.uint64(M0) * x[0], np.uint64(M1) * x[2]
        x = [
            (product1 >> np.uint64(32)) ^ x[1] ^ k0,
            product1 & MASK,
            (product0 >> np.uint64(32)) ^ x[3] ^ k1,
            product0 & MASK,
        ]
        k0, k1 = (k0 + np.uint64(W0)) & MASK, (k1 + np.uint64(W1)) & MASK
    return x


def unit_float(bits):
    return (bits >> np.uint64(8)).astype(np.float64) / 16777216.0


def hbao(gbuffer, camera, radius, seed=0, directions=8, steps=6, angle_bias_deg=10.0, falloff=1.0):
    """Access (1 = open) per pixel from an mbao.GBuffer seen from camera (SPEC 4)."""
    height, width = gbuffer.t.shape
    forward = np.subtract(camera.target, camera.eye)
    forward = forward / np.linalg.norm(forward)
    right = np.cross(forward, camera.up)
    right /= np.linalg.norm(right)
    up = np.cross(right, forward)
    eye = np.asarray(camera.eye, dtype=np.float64)
    to_view = np.stack([right, up, forward])  # rows: view x, y, z
    points = (gbuffer.position.reshape(-1, 3) - eye) @ to_view.T
    normals = gbuffer.shading_normal.reshape(-1, 3).astype(np.float64) @ to_view.T
    covered = gbuffer.mask.reshape(-1)
    pixel = np.arange(width * height)
    x, y = pixel % width, pixel // width
    words = philox4x32_10([pixel, 0 * pixel, 0 * pixel, 0 * pixel], (seed & 0xFFFFFFFF, seed >> 32))
    rotation, first_step = unit_float(words[0]), 1.0 + unit_float(words[1])
    tan_half = np.tan(np.radians(camera.vfov_deg) / 2)
    with np.errstate(divide="ignore", invalid="ignore"):
        step = radius / (points[:, 2] * tan_half) * (0.5 * height) / (steps + 1)
    sin_bias = np.sin(np.radians(angle_bias_deg))
    occlusion = np.zeros(width * height)
    for i in range(directions):
        angle = 2 * np.pi * (i + rotation) / directions
        sin_horizon = np.full(width * height, sin_bias)
        for k in range(steps):
            along = (first_step + k) * step
            with np.errstate(invalid="ignore"):
                sx = np.rint(x + along * np.cos(angle))
                sy = np.rint(y - along * np.sin(angle))  # image rows grow downward, view y upward
                inside = (sx >= 0) & (sy >= 0) & (sx < width) & (sy < height) & covered
            seen = np.where(inside, sy * width + sx, 0).astype(np.int64)
            d = points[seen] - points
            d2 = np.einsum("ij,ij->i", d, d)
            with np.errstate(divide="ignore", invalid="ignore"):
                sin_sample = np.einsum("ij,ij->i", d, normals) / np.sqrt(d2)
                r2 = d2 / radius**2
                rises = inside & covered[seen] & (seen != pixel) & (d2 > 0) & (r2 <= 1) & (sin_sample > sin_horizon)
            occlusion += np.where(rises, (1 - falloff * r2) * (sin_sample - sin_horizon), 0.0)
            sin_horizon = np.where(rises, sin_sample, sin_horizon)
    access = np.where(covered & (step >= 0.5), np.clip(1 - occlusion / directions, 0, 1), 1.0)
    return access.reshape(height, width)
