"""Test geometry with known answers, as (vertices, indices) numpy arrays."""

import numpy as np

# The 6 faces of the unit cube as quads, counter-clockwise seen from outside.
_CUBE_FACES = [
    [0, 2, 3, 1], [4, 5, 7, 6],  # x = 0, x = 1
    [0, 1, 5, 4], [2, 6, 7, 3],  # y = 0, y = 1
    [0, 4, 6, 2], [1, 3, 7, 5],  # z = 0, z = 1
]


def quads_to_triangles(quads):
    quads = np.asarray(quads)
    return np.concatenate([quads[:, [0, 1, 2]], quads[:, [0, 2, 3]]])


def box(lo, hi):
    """A closed axis-aligned box: 8 vertices, 12 triangles facing out."""
    lo, hi = np.asarray(lo, float), np.asarray(hi, float)
    corners = np.array([[(i >> 2) & 1, (i >> 1) & 1, i & 1] for i in range(8)], float)
    return lo + corners * (hi - lo), quads_to_triangles(_CUBE_FACES)


def merge(*meshes):
    vertices, indices, base = [], [], 0
    for v, i in meshes:
        vertices.append(np.asarray(v, float))
        indices.append(np.asarray(i) + base)
        base += len(v)
    return np.concatenate(vertices), np.concatenate(indices)


def box_grid(n, size=0.6):
    """n^3 closed boxes on the integer grid: many shared planes, edges on split candidates."""
    return merge(*[box((x, y, z), (x + size, y + size, z + size)) for x in range(n) for y in range(n) for z in range(n)])


def plane(half_size, y=0.0, divisions=1):
    """A square in the plane y = const, split into divisions^2 quads."""
    s = np.linspace(-half_size, half_size, divisions + 1)
    xx, zz = np.meshgrid(s, s, indexing="ij")
    vertices = np.column_stack([xx.ravel(), np.full(xx.size, y), zz.ravel()])
    k = divisions + 1
    quads = [[i * k + j, i * k + j + 1, (i + 1) * k + j + 1, (i + 1) * k + j] for i in range(divisions) for j in range(divisions)]
    return vertices, quads_to_triangles(quads)


def disk(radius, height, sides):
    """A regular polygon inscribed in the circle of `radius`, centred above the origin at y = height."""
    angles = np.linspace(0.0, 2.0 * np.pi, sides, endpoint=False)
    rim = np.column_stack([radius * np.cos(angles), np.full(sides, height), radius * np.sin(angles)])
    vertices = np.vstack([[0.0, height, 0.0], rim])
    indices = np.array([[0, 1 + i, 1 + (i + 1) % sides] for i in range(sides)])
    return vertices, indices


def sphere(radius=1.0, center=(0.0, 0.0, 0.0), rings=24, segments=48):
    """A closed UV sphere with its exact outward normals."""
    theta = np.linspace(0.0, np.pi, rings + 1)[1:-1]
    phi = np.linspace(0.0, 2.0 * np.pi, segments, endpoint=False)
    t, p = np.meshgrid(theta, phi, indexing="ij")
    ring_points = np.column_stack([np.sin(t).ravel() * np.cos(p).ravel(), np.cos(t).ravel(), np.sin(t).ravel() * np.sin(p).ravel()])
    normals = np.vstack([[0, 1, 0], ring_points, [0, -1, 0]])
    top, bottom = 0, len(normals) - 1
    ring = lambda r, s: 1 + r * segments + s % segments
    triangles = [[top, ring(0, s + 1), ring(0, s)] for s in range(segments)]
    for r in range(rings - 2):
        for s in range(segments):
            triangles += [[ring(r, s), ring(r, s + 1), ring(r + 1, s + 1)], [ring(r, s), ring(r + 1, s + 1), ring(r + 1, s)]]
    triangles += [[bottom, ring(rings - 2, s), ring(rings - 2, s + 1)] for s in range(segments)]
    return np.asarray(center) + radius * normals, np.array(triangles), normals


def random_soup(rng, n, scale=1.0):
    """n triangles scattered in [0, scale]^3, mostly small, a few large."""
    centers = rng.random((n, 1, 3)) * scale
    sizes = 0.3 * scale * rng.random((n, 1, 1)) ** 3
    vertices = (centers + sizes * (rng.random((n, 3, 3)) - 0.5)).reshape(-1, 3)
    return vertices, np.arange(3 * n).reshape(n, 3)
