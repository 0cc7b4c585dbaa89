"""Test geometry with known answers, as (vertices, indices) numpy arrays."""

import numpy as np

# The 6 faces of the unit cube as quads, counter-clockwise seen from inside: the
# triangles face in (SPEC 6.1), which only a bake tells apart.
_CUBE_FACES = [
    [0, 2, 3, 1],
    [4, 5, 7, 6],  # x = 0, x = 1
    [0, 1, 5, 4],
    [2, 6, 7, 3],  # y = 0, y = 1
    [0, 4, 6, 2],
    [1, 3, 7, 5],  # z = 0, z = 1
]


def quads_to_triangles(quads):
    quads = np.asarray(quads)
    return np.concatenate([quads[:, [0, 1, 2]], quads[:, [0, 2, 3]]])


def box(lo, hi):
    """A closed axis-aligned box: 8 vertices, 12 triangles facing in."""
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
    return merge(
        *[box((x, y, z), (x + size, y + size, z + size)) for x in range(n) for y in range(n) for z in range(n)]
    )


def plane(half_size, y=0.0, divisions=1):
    """A square in the plane y = const, split into divisions^2 quads."""
    s = np.linspace(-half_size, half_size, divisions + 1)
    xx, zz = np.meshgrid(s, s, indexing="ij")
    vertices = np.column_stack([xx.ravel(), np.full(xx.size, y), zz.ravel()])
    k = divisions + 1
    quads = [
        [i * k + j, i * k + j + 1, (i + 1) * k + j + 1, (i + 1) * k + j]
        for i in range(divisions)
        for j in range(divisions)
    ]
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
    ring_points = np.column_stack(
        [np.sin(t).ravel() * np.cos(p).ravel(), np.cos(t).ravel(), np.sin(t).ravel() * np.sin(p).ravel()]
    )
    normals = np.vstack([[0, 1, 0], ring_points, [0, -1, 0]])
    top, bottom = 0, len(normals) - 1
    ring = lambda r, s: 1 + r * segments + s % segments
    triangles = [[top, ring(0, s + 1), ring(0, s)] for s in range(segments)]
    for r in range(rings - 2):
        for s in range(segments):
            triangles += [
                [ring(r, s), ring(r, s + 1), ring(r + 1, s + 1)],
                [ring(r, s), ring(r + 1, s + 1), ring(r + 1, s)],
            ]
    triangles += [[bottom, ring(rings - 2, s), ring(rings - 2, s + 1)] for s in range(segments)]
    return np.asarray(center) + radius * normals, np.array(triangles), normals


def random_soup(rng, n, scale=1.0):
    """n triangles scattered in [0, scale]^3, mostly small, a few large."""
    centers = rng.random((n, 1, 3)) * scale
    sizes = 0.3 * scale * rng.random((n, 1, 1)) ** 3
    vertices = (centers + sizes * (rng.random((n, 3, 3)) - 0.5)).reshape(-1, 3)
    return vertices, np.arange(3 * n).reshape(n, 3)


def icosphere(radius=1.0, center=(0.0, 0.0, 0.0), subdivisions=2):
    """A closed sphere from a subdivided icosahedron: 20 * 4^subdivisions triangles
    facing out. Unlike the UV sphere it has no coplanar neighbours, so rounding
    its vertices to float32 keeps it convex."""
    g = (1.0 + 5.0**0.5) / 2.0
    vertices = [
        [-1, g, 0],
        [1, g, 0],
        [-1, -g, 0],
        [1, -g, 0],
        [0, -1, g],
        [0, 1, g],
        [0, -1, -g],
        [0, 1, -g],
        [g, 0, -1],
        [g, 0, 1],
        [-g, 0, -1],
        [-g, 0, 1],
    ]
    vertices = [np.array(v, float) / np.linalg.norm(v) for v in vertices]
    faces = [
        [0, 11, 5],
        [0, 5, 1],
        [0, 1, 7],
        [0, 7, 10],
        [0, 10, 11],
        [1, 5, 9],
        [5, 11, 4],
        [11, 10, 2],
        [10, 7, 6],
        [7, 1, 8],
        [3, 9, 4],
        [3, 4, 2],
        [3, 2, 6],
        [3, 6, 8],
        [3, 8, 9],
        [4, 9, 5],
        [2, 4, 11],
        [6, 2, 10],
        [8, 6, 7],
        [9, 8, 1],
    ]
    for _ in range(subdivisions):
        midpoints = {}

        def midpoint(a, b):
            key = (min(a, b), max(a, b))
            if key not in midpoints:
                m = vertices[a] + vertices[b]
                vertices.append(m / np.linalg.norm(m))
                midpoints[key] = len(vertices) - 1
            return midpoints[key]

        refined = []
        for a, b, c in faces:
            ab, bc, ca = midpoint(a, b), midpoint(b, c), midpoint(c, a)
            refined += [[a, ab, ca], [b, bc, ab], [c, ca, bc], [ab, bc, ca]]
        faces = refined
    return np.asarray(center) + radius * np.array(vertices), np.array(faces)


def frame(normal):
    """Two unit vectors that with the unit `normal` make a right-handed frame (along, across, normal)."""
    n = np.asarray(normal, float) / np.linalg.norm(normal)
    along = np.cross(n, [1.0, 0.0, 0.0] if abs(n[0]) < 0.9 else [0.0, 1.0, 0.0])
    along /= np.linalg.norm(along)
    return along, np.cross(n, along), n


def tilted(mesh, normal):
    """A mesh made in the plane y = 0 turned so that y becomes `normal`: no axis
    is parallel to the plane, so its float32 vertices lie off it by rounding."""
    vertices, indices = mesh
    along, across, n = frame(normal)
    return np.asarray(vertices, float) @ np.array([along, n, across]), indices


def needle_fan(count, length, normal=(1.0, 2.0, 3.0)):
    """count needles in the plane through the origin with the given normal: from
    an apex `length` away to a 1/count wide piece of the unit segment across the
    origin, aspect ratio count * length. Returns vertices, indices, the unit normal."""
    along, across, n = frame(normal)
    base = np.outer(np.linspace(-0.5, 0.5, count + 1), across)
    vertices = np.vstack([-length * along, base])
    indices = np.array([[0, 1 + i, 2 + i] for i in range(count)])
    return vertices, indices, n


def t_junction_box():
    """A closed parallelepiped on integer corners, no face parallel to an axis,
    with one face split in two along its midline: the two new vertices lie
    exactly (in float32 too) on the middle of the edges the neighbouring faces
    keep whole, a T-junction on each. Returns vertices, indices, the indices of
    the two T-vertices and of the two long edges they lie on."""
    a, b, c, o = map(np.array, ((4, 1, 2), (2, 6, -2), (-1, 2, 5), (-3, -2, -1)))
    corners = np.array([o + i * a + j * b + k * c for i in (0, 1) for j in (0, 1) for k in (0, 1)], float)
    faces = quads_to_triangles(_CUBE_FACES)
    whole = np.delete(faces, [1, 7], axis=0)  # all but the face i = 1 (corners 4, 5, 7, 6)
    vertices = np.vstack([corners, corners[4] + b / 2, corners[5] + b / 2])
    halves = quads_to_triangles([[4, 5, 9, 8], [8, 9, 7, 6]])
    return vertices, np.vstack([whole, halves]), [8, 9], [(4, 6), (5, 7)]


def shrinking_spiral(rng, count, shrink=0.97, size=1e-3):
    """count small triangles along a spiral that shrinks by `shrink` per triangle:
    each turn a smaller copy of the last, which the kd-tree builder keeps cutting."""
    k = np.arange(count)
    r = shrink**k
    centers = np.column_stack([r * np.cos(k), r * np.sin(k), r])
    vertices = centers[:, None, :] + size * r[:, None, None] * (rng.random((count, 3, 3)) - 0.5)
    return vertices.reshape(-1, 3), np.arange(3 * count).reshape(count, 3)
