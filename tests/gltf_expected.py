"""What the glTF loading tests expect, computed without the loader: transforms
and normals with numpy, and the helpers that load a file and check its errors."""

import math
import re

import numpy as np
import pytest

import mbao
from caught_warnings import caught_warnings
from gltf_writer import CONTAINERS, UNSIGNED_SHORT, GltfBuilder

# -- geometry and transforms, computed independently of the loader ------------

TRIANGLE = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0]], np.float32)
QUAD = np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]], np.float32)
QUAD_INDICES = np.array([[0, 1, 2], [0, 2, 3]])
QUAD_NORMALS = np.tile(np.float32([0, 0, 1]), (4, 1))


def quaternion(axis, degrees):
    """Unit quaternion (x, y, z, w) for a rotation about `axis`."""
    axis = np.asarray(axis, float) / np.linalg.norm(axis)
    half = math.radians(degrees) / 2
    return (*(axis * math.sin(half)), math.cos(half))


def rotation_matrix(q):
    x, y, z, w = q
    m = np.eye(4)
    m[:3, :3] = [
        [1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
        [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
        [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)],
    ]
    return m


def trs_matrix(translation=(0, 0, 0), rotation=(0, 0, 0, 1), scale=(1, 1, 1)):
    """glTF's local transform: T * R * S."""
    t = np.eye(4)
    t[:3, 3] = translation
    return t @ rotation_matrix(rotation) @ np.diag([*scale, 1.0])


def transform_points(matrix, points):
    points = np.asarray(points, np.float64)
    return (points @ matrix[:3, :3].T + matrix[:3, 3]).astype(np.float32)


def transform_normals(matrix, normals):
    """Inverse-transpose of the 3x3 part, then normalised."""
    n = np.asarray(normals, np.float64) @ np.linalg.inv(matrix[:3, :3])  # == (inv(M).T @ n.T).T
    return (n / np.linalg.norm(n, axis=1, keepdims=True)).astype(np.float32)


def random_trs(rng):
    axis = rng.normal(size=3)
    scale = rng.uniform(0.3, 3.0, size=3) * rng.choice([-1, 1], size=3)
    return {
        "translation": rng.uniform(-10, 10, size=3),
        "rotation": quaternion(axis, rng.uniform(0, 360)),
        "scale": scale,
    }


@pytest.fixture
def rng():
    return np.random.default_rng(20240611)


def assert_close(actual, expected, scale=1.0):
    """float32 agreement: 1e-5 relative, with an absolute floor for values near 0."""
    np.testing.assert_allclose(actual, expected, rtol=1e-5, atol=1e-6 * scale)


# -- loading helpers ---------------------------------------------------------------


def load_clean(path):
    """mbao.load, asserting that a well-formed file loads without any warning."""
    with caught_warnings() as caught:
        scene = mbao.load(path)
    assert [str(w.message) for w in caught] == []
    assert scene.warnings == []
    return scene


def assert_load_error(path, *elements):
    """mbao.load(path) raises mbao.LoadError naming the file and every element given."""
    with pytest.raises(mbao.LoadError) as raised:
        mbao.load(path)
    message = str(raised.value)
    assert str(path) in message
    for element in elements:
        assert re.search(rf"\b{re.escape(element)}\b", message), f"{element!r} not named in: {message}"
    return message


def single_mesh_file(path, primitives_of, container=None, **node):
    """A file with one mesh (primitives_of(builder) gives its primitives) on one root node."""
    b = GltfBuilder()
    mesh = b.add_mesh(primitives_of(b))
    b.add_scene([b.add_node(mesh=mesh, **node)])
    return b.write(path, container)


@pytest.fixture(params=CONTAINERS)
def container(request):
    """Each of: .gltf with a data URI, .gltf with an external .bin, .glb."""
    return request.param


# -- files ---------------------------------------------------------------------------


def build_reference_scene():
    """A bit of everything: a hierarchy, TRS and matrix nodes, indexed and
    non-indexed primitives, normals on some primitives only, and a camera."""
    b = GltfBuilder()
    with_normals = b.primitive(QUAD, QUAD_INDICES, normals=QUAD_NORMALS, index_type=UNSIGNED_SHORT)
    plain = b.primitive(TRIANGLE)
    mesh = b.add_mesh([with_normals, plain])
    camera = b.add_perspective_camera(yfov=0.7)
    child = b.add_node(mesh=mesh, matrix=trs_matrix((0, 1, 0), quaternion((1, 0, 0), 30), (1, 2, 1)))
    eye = b.add_node(camera=camera, translation=(0, 0, 10))
    root = b.add_node(mesh=mesh, translation=(1, 2, 3), rotation=quaternion((0, 1, 0), 45), children=[child])
    b.add_scene([root, eye], default=True)
    return b


def two_scene_file(path, default=None):
    """Scene 0 holds a triangle at z = 0, scene 1 one at z = 1."""
    b = GltfBuilder()
    mesh = b.add_mesh([b.primitive(TRIANGLE)])
    b.add_scene([b.add_node(mesh=mesh)])
    b.add_scene([b.add_node(mesh=mesh, translation=(0, 0, 1))])
    if default is not None:
        b.doc["scene"] = default
    return b.write(path)
