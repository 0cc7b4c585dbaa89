"""The Python API's contract for mbao.Mesh and mbao.Camera: what they accept,
keep and refuse, and mbao's error classes.
"""

import json
import math

import numpy as np
import pytest

import mbao


# -- mbao.Mesh ------------------------------------------------------------------------

VERTICES = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]], dtype=np.float64)
INDICES = np.array([[0, 1, 2], [0, 2, 3]])


@pytest.mark.parametrize("vertex_type", [np.float64, np.float32, np.int32, np.int64, np.uint8])
@pytest.mark.parametrize("index_type", [np.int32, np.int64, np.uint16, np.uint32])
def test_mesh_accepts_numeric_types(vertex_type, index_type):
    mesh = mbao.Mesh(VERTICES.astype(vertex_type), INDICES.astype(index_type))
    assert isinstance(mesh, mbao.Scene)
    assert mesh.vertices.dtype == np.float32 and mesh.indices.dtype == np.uint32
    np.testing.assert_array_equal(mesh.vertices, VERTICES.astype(np.float32))
    np.testing.assert_array_equal(mesh.indices, INDICES.astype(np.uint32))
    assert mesh.triangle_count == 2


def test_mesh_accepts_lists():
    mesh = mbao.Mesh(VERTICES.tolist(), INDICES.tolist(), normals=[[0, 0, 1]] * 4)
    np.testing.assert_array_equal(mesh.vertices, VERTICES.astype(np.float32))
    np.testing.assert_array_equal(mesh.indices, INDICES)
    np.testing.assert_array_equal(mesh.normals, np.tile(np.float32([0, 0, 1]), (4, 1)))


def test_mesh_round_trips_its_arrays(rng):
    vertices = rng.normal(size=(30, 3))
    indices = rng.integers(0, 30, size=(20, 3))
    normals = rng.normal(size=(30, 3))
    mesh = mbao.Mesh(vertices, indices, normals)
    np.testing.assert_array_equal(mesh.vertices, vertices.astype(np.float32))
    np.testing.assert_array_equal(mesh.indices, indices.astype(np.uint32))
    assert mesh.normals.dtype == np.float32
    np.testing.assert_array_equal(mesh.normals, normals.astype(np.float32))
    lo, hi = mesh.bounds
    np.testing.assert_array_equal(lo, vertices.astype(np.float32).min(axis=0))
    np.testing.assert_array_equal(hi, vertices.astype(np.float32).max(axis=0))
    assert mbao.Mesh(vertices, indices).normals is None


def test_mesh_copies_its_input():
    vertices, indices, normals = VERTICES.astype(np.float32), INDICES.astype(np.uint32), np.zeros((4, 3), np.float32)
    mesh = mbao.Mesh(vertices, indices, normals)
    vertices[:] = 7
    indices[:] = 3
    normals[:] = 1
    np.testing.assert_array_equal(mesh.vertices, VERTICES.astype(np.float32))
    np.testing.assert_array_equal(mesh.indices, INDICES)
    np.testing.assert_array_equal(mesh.normals, 0)


NON_CONTIGUOUS = {
    "every other row": lambda a: np.repeat(a, 2, axis=0)[::2],
    "Fortran order": np.asfortranarray,
    "reversed columns of a reversed copy": lambda a: a[:, ::-1].copy()[:, ::-1],
}


@pytest.mark.parametrize("layout", NON_CONTIGUOUS.values(), ids=NON_CONTIGUOUS.keys())
def test_non_contiguous_arrays_are_accepted_by_copying(layout):
    normals = np.tile([0.0, 0.0, 1.0], (4, 1))
    expected = mbao.Mesh(VERTICES, INDICES, normals)
    arrays = [layout(a) for a in (VERTICES, INDICES, normals)]
    assert not any(a.flags.c_contiguous for a in arrays[:1])
    mesh = mbao.Mesh(*arrays)
    for name in ("vertices", "indices", "normals"):
        np.testing.assert_array_equal(getattr(mesh, name), getattr(expected, name))
    origins, directions = np.tile([0.2, 0.2, 1.0], (3, 1)), np.tile([0.0, 0.0, -1.0], (3, 1))
    np.testing.assert_array_equal(
        mbao.trace(mesh, layout(origins), layout(directions))[0], mbao.trace(mesh, origins, directions)[0]
    )


def test_mesh_arrays_are_read_only():
    mesh = mbao.Mesh(VERTICES, INDICES, normals=np.tile([0.0, 0.0, 1.0], (4, 1)))
    for array in (mesh.vertices, mesh.indices, mesh.normals):
        assert not array.flags.writeable
        with pytest.raises(ValueError):
            array[0, 0] = 1


BAD_MESHES = [
    ("vertices (N, 2)", dict(vertices=VERTICES[:, :2]), ValueError, r"vertices.*\(N, 3\)"),
    ("vertices flat", dict(vertices=VERTICES.ravel()), ValueError, r"vertices.*\(N, 3\)"),
    ("indices (M, 2)", dict(indices=INDICES[:, :2]), ValueError, r"indices.*\(N, 3\)"),
    ("indices flat", dict(indices=INDICES.ravel()), ValueError, r"indices"),
    ("normals (N, 2)", dict(normals=VERTICES[:, :2]), ValueError, r"normals"),
    ("normals rows", dict(normals=VERTICES[:3]), ValueError, r"normals.*3.*4"),
    ("float indices", dict(indices=INDICES.astype(np.float64)), TypeError, r"indices"),
    ("bool indices", dict(indices=INDICES.astype(bool)), TypeError, r"indices"),
    ("complex vertices", dict(vertices=VERTICES.astype(complex)), TypeError, r"vertices"),
    ("string vertices", dict(vertices=np.full((4, 3), "a")), TypeError, r"vertices"),
    ("negative index", dict(indices=[[0, 1, 2], [0, -1, 3]]), ValueError, r"triangle 1.*vertex -1"),
    ("index too large", dict(indices=[[0, 1, 2], [0, 2, 4]]), ValueError, r"triangle 1.*vertex 4"),
    ("no triangles", dict(indices=np.zeros((0, 3), int)), ValueError, r"no triangles"),
    (
        "NaN vertex",
        dict(vertices=np.where(np.arange(12).reshape(4, 3) == 4, np.nan, VERTICES)),
        ValueError,
        r"vertex 1",
    ),
    (
        "inf vertex",
        dict(vertices=np.where(np.arange(12).reshape(4, 3) == 9, np.inf, VERTICES)),
        ValueError,
        r"vertex 3",
    ),
]


@pytest.mark.parametrize("arguments, error, message", [b[1:] for b in BAD_MESHES], ids=[b[0] for b in BAD_MESHES])
def test_mesh_refuses_bad_arrays(arguments, error, message):
    settings = dict(vertices=VERTICES, indices=INDICES, normals=None)
    settings.update(arguments)
    with pytest.raises(error, match=message):
        mbao.Mesh(**settings)


# -- mbao.Camera ------------------------------------------------------------------------


def test_camera_keeps_its_parameters():
    camera = mbao.Camera((1, 2, 3), np.array([0.0, 0.5, 0.0]), (0, 1, 0), 50)
    assert camera.eye == pytest.approx((1, 2, 3))
    assert camera.target == pytest.approx((0, 0.5, 0))
    assert camera.up == pytest.approx((0, 1, 0))
    assert camera.vfov_deg == pytest.approx(50)
    assert camera.max_distance is None
    assert "Camera(" in repr(camera)


@pytest.mark.parametrize(
    "eye, target, up, vfov, message",
    [
        ((0, 0, 5), (0, 0, 0), (0, 0, 1), 45, r"up.*parallel"),
        ((0, 0, 5), (0, 0, 0), (0, 0, -3), 45, r"up.*parallel"),
        ((0, 0, 5), (0, 0, 0), (0, 0, 0), 45, r"up"),
        ((1, 1, 1), (1, 1, 1), (0, 1, 0), 45, r"eye.*target"),
        ((0, 0, 5), (0, 0, 0), (0, 1, 0), 0, r"vfov_deg.*\(0, 180\)"),
        ((0, 0, 5), (0, 0, 0), (0, 1, 0), 180, r"vfov_deg.*\(0, 180\)"),
        ((0, 0, 5), (0, 0, 0), (0, 1, 0), math.nan, r"vfov_deg"),
        ((0, 0, math.inf), (0, 0, 0), (0, 1, 0), 45, r"finite"),
    ],
)
def test_camera_refuses_degenerate_views(eye, target, up, vfov, message):
    with pytest.raises(ValueError, match=message):
        mbao.Camera(eye, target, up, vfov)


@pytest.mark.parametrize(
    "eye, target, up",
    [
        ((0, 0, 3e19), (0, 0, 0), (0, 1, 0)),
        ((0, 0, 1e-30), (0, 0, 0), (0, 1, 0)),
        ((0, 0, 5), (0, 0, 0), (0, 1e-30, 0)),
        ((0, 0, 3e38), (0, 0, -3e38), (0, 3e19, 0)),
    ],
)
def test_camera_frames_views_at_extreme_scales(eye, target, up):
    """Float squares overflow from about 1.8e19 and underflow below about 1e-23;
    these views are valid all the same, and were once refused as 'up parallel'."""
    camera = mbao.Camera(eye, target, up, 45)
    assert camera.eye == pytest.approx(eye)


def test_a_camera_far_beyond_the_box_sees_it_smaller_than_a_pixel():
    scene = mbao.cornell_box()
    default = scene.camera
    far = mbao.Camera((278, 273, -3e19), default.target, default.up, default.vfov_deg)
    result = mbao.render(scene, camera=far, width=32, height=32)
    assert not result.mask.any()
    assert np.all(result.ao == 1.0)


def write_json(path, document):
    path.write_text(json.dumps(document) if not isinstance(document, str) else document)
    return path


CAMERA_JSON = {"eye": [1, 2, 3], "target": [0, 0.5, 0], "up": [0, 1, 0], "vfov_deg": 50}


def test_camera_load(tmp_path):
    camera = mbao.Camera.load(write_json(tmp_path / "camera.json", CAMERA_JSON))  # a pathlib.Path
    assert camera.eye == pytest.approx((1, 2, 3))
    assert camera.target == pytest.approx((0, 0.5, 0))
    assert camera.up == pytest.approx((0, 1, 0))
    assert camera.vfov_deg == pytest.approx(50)
    assert camera.max_distance is None
    with_radius = mbao.Camera.load(str(write_json(tmp_path / "radius.json", dict(CAMERA_JSON, max_distance=2.5))))
    assert with_radius.max_distance == pytest.approx(2.5)


BAD_CAMERA_FILES = [
    ("not JSON", "{eye: "),
    ("not an object", [1, 2, 3]),
    ("eye missing", {k: v for k, v in CAMERA_JSON.items() if k != "eye"}),
    ("vfov_deg missing", {k: v for k, v in CAMERA_JSON.items() if k != "vfov_deg"}),
    ("eye of 2 numbers", dict(CAMERA_JSON, eye=[1, 2])),
    ("vfov_deg a string", dict(CAMERA_JSON, vfov_deg="50")),
    ("eye == target", dict(CAMERA_JSON, target=[1, 2, 3])),
    ("up parallel", dict(CAMERA_JSON, eye=[0, 5, 0], target=[0, 0, 0])),
    ("vfov_deg 180", dict(CAMERA_JSON, vfov_deg=180)),
    ("max_distance <= 0", dict(CAMERA_JSON, max_distance=0)),
]


@pytest.mark.parametrize("document", [b[1] for b in BAD_CAMERA_FILES], ids=[b[0] for b in BAD_CAMERA_FILES])
def test_camera_load_errors_name_the_file(tmp_path, document):
    path = write_json(tmp_path / "bad_camera.json", document)
    with pytest.raises(mbao.LoadError, match="bad_camera.json"):
        mbao.Camera.load(path)


def test_camera_load_missing_file(tmp_path):
    with pytest.raises(mbao.LoadError, match="no_such_camera.json"):
        mbao.Camera.load(tmp_path / "no_such_camera.json")


def test_error_hierarchy():
    assert issubclass(mbao.LoadError, mbao.Error)
    assert issubclass(mbao.DeviceError, mbao.Error)
    assert issubclass(mbao.Error, RuntimeError)
