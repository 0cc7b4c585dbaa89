"""mbao.load: a glTF file's camera (SPEC 3.4), and the Scene a loaded file gives.

Every file here is written by tests/gltf_writer.py, so each test states its
whole input.
"""

import math
import warnings

import numpy as np
import pytest

import mbao
from gltf_expected import (
    QUAD,
    QUAD_INDICES,
    TRIANGLE,
    assert_close,
    build_reference_scene,
    container,
    load_clean,
    quaternion,
    single_mesh_file,
    trs_matrix,
)
from gltf_writer import GltfBuilder, file_name


# == camera ===========================================================================


def camera_file(path, camera_node, parent=None, yfov=0.9):
    """A quad at the origin and one perspective camera on a node (under `parent` if given)."""
    b = GltfBuilder()
    mesh = b.add_mesh([b.primitive(QUAD, QUAD_INDICES)])
    camera = b.add_node(camera=b.add_perspective_camera(yfov), **camera_node)
    roots = [b.add_node(mesh=mesh)]
    roots.append(b.add_node(children=[camera], **parent) if parent else camera)
    b.add_scene(roots)
    return b.write(path)


def assert_camera(camera, world, yfov):
    """eye at the node's origin, looking down its -Z, up its +Y, vfov = yfov in degrees."""
    forward = world[:3, :3] @ [0, 0, -1]
    up = world[:3, :3] @ [0, 1, 0]
    eye = np.array(camera.eye)
    assert_close(eye, world[:3, 3], scale=10)
    direction = np.array(camera.target) - eye
    assert_close(direction / np.linalg.norm(direction), forward / np.linalg.norm(forward))
    assert_close(np.array(camera.up) / np.linalg.norm(camera.up), up / np.linalg.norm(up))
    assert camera.vfov_deg == pytest.approx(math.degrees(yfov), rel=1e-6)


def test_camera_at_a_translated_node_looks_down_minus_z(tmp_path, container):
    node = {"translation": (1, 2, 8)}
    scene = load_clean(camera_file(tmp_path / file_name("cam", container), node, yfov=0.9))
    assert isinstance(scene.camera, mbao.Camera)
    assert_camera(scene.camera, trs_matrix(**node), 0.9)
    assert_close(scene.camera.eye, (1, 2, 8))


def test_camera_orientation_follows_node_rotation_and_parents(tmp_path):
    node = {"translation": (0, 1, 4), "rotation": quaternion((1, 0.5, 0), -25)}
    parent = {"translation": (3, 0, 0), "rotation": quaternion((0, 1, 0), 120), "scale": (2, 2, 2)}
    scene = load_clean(camera_file(tmp_path / "rot.gltf", node, parent=parent, yfov=1.2))
    assert_camera(scene.camera, trs_matrix(**parent) @ trs_matrix(**node), 1.2)


def test_camera_is_the_first_perspective_one_of_the_default_scene(tmp_path):
    b = GltfBuilder()
    mesh = b.add_mesh([b.primitive(QUAD, QUAD_INDICES)])
    ortho = b.add_orthographic_camera()
    wide, narrow = b.add_perspective_camera(1.5), b.add_perspective_camera(0.3)
    outside = b.add_node(camera=narrow, translation=(0, 0, 99))  # not in the scene
    b.add_scene(
        [
            b.add_node(mesh=mesh),
            b.add_node(camera=ortho, translation=(0, 0, 7)),
            b.add_node(children=[b.add_node(camera=wide, translation=(0, 0, 5))]),
            b.add_node(camera=narrow, translation=(0, 0, 3)),
        ]
    )
    assert outside not in b.doc["scenes"][0]["nodes"]
    camera = load_clean(b.write(tmp_path / "cams.gltf")).camera
    np.testing.assert_array_equal(camera.eye, [0, 0, 5])
    assert camera.vfov_deg == pytest.approx(math.degrees(1.5), rel=1e-6)


@pytest.mark.parametrize(
    "extras, radius",
    [
        ({"max_distance": 2.5}, 2.5),
        ({"max_distance": 0}, None),
        ({"max_distance": "far"}, None),
        ({"other": 1}, None),
        (None, None),
    ],
)
def test_a_cameras_extras_may_suggest_the_radius(tmp_path, extras, radius):
    b = GltfBuilder()
    mesh = b.add_mesh([b.primitive(QUAD, QUAD_INDICES)])
    b.add_scene(
        [b.add_node(mesh=mesh), b.add_node(camera=b.add_perspective_camera(0.9, extras=extras), translation=(0, 0, 3))]
    )
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        scene = mbao.load(b.write(tmp_path / "radius.gltf"))
    assert scene.camera.max_distance == radius
    bad = extras is not None and "max_distance" in extras and radius is None
    assert any("extras.max_distance ignored" in str(w.message) for w in caught) == bad
    if radius is not None:  # render takes it as it takes camera.json's (SPEC 1)
        result = mbao.render(scene, width=4, height=4)
        assert (result.stats["max_distance"], result.stats["max_distance_source"]) == (radius, "camera")


def test_no_camera_when_the_default_scene_has_none(tmp_path):
    b = GltfBuilder()
    mesh = b.add_mesh([b.primitive(TRIANGLE)])
    b.add_node(camera=b.add_perspective_camera(0.5))  # a perspective camera, but in no scene
    b.add_scene([b.add_node(mesh=mesh, camera=b.add_orthographic_camera())])  # orthographic only
    assert load_clean(b.write(tmp_path / "nocam.gltf")).camera is None


# == the Scene API on a loaded file ===============================================


@pytest.fixture
def loaded(tmp_path):
    b = build_reference_scene()
    return load_clean(b.write(tmp_path / "reference.glb"))


def test_vertices_are_read_only_float32_rows(loaded):
    vertices = loaded.vertices
    assert vertices.dtype == np.float32 and vertices.ndim == 2 and vertices.shape[1] == 3
    assert not vertices.flags.writeable
    with pytest.raises(ValueError):
        vertices[0, 0] = 1.0


def test_indices_are_uint32_rows_into_vertices(loaded):
    indices = loaded.indices
    assert indices.dtype == np.uint32 and indices.shape == (loaded.triangle_count, 3)
    assert indices.max() < len(loaded.vertices)
    assert not indices.flags.writeable


def test_normals_have_one_row_per_vertex(loaded):
    assert loaded.normals.dtype == np.float32 and loaded.normals.shape == loaded.vertices.shape
    assert not loaded.normals.flags.writeable


def test_bounds_are_the_box_around_the_triangles(tmp_path, loaded):
    lo, hi = loaded.bounds
    assert_close(lo, loaded.vertices.min(axis=0), scale=10)
    assert_close(hi, loaded.vertices.max(axis=0), scale=10)

    # A vertex that no triangle uses does not count.
    points = np.concatenate([TRIANGLE, np.float32([[50, 50, 50]])])
    path = single_mesh_file(tmp_path / "unused.gltf", lambda b: [b.primitive(points, [0, 1, 2])])
    lo, hi = load_clean(path).bounds
    np.testing.assert_array_equal(lo, [0, 0, 0])
    np.testing.assert_array_equal(hi, [1, 1, 0])


def test_triangle_count_and_name(loaded):
    assert loaded.triangle_count == len(loaded.indices) == 6
    assert isinstance(loaded.name, str) and "reference.glb" in loaded.name


def test_render_uses_the_file_camera(tmp_path):
    # The camera looks down -Z (up +Y) at a big quad covering only x < 0, y > 0:
    # the top-left quarter of the image (row 0 is the top).
    b = GltfBuilder()
    quad = np.float32([[-100, 0, 0], [0, 0, 0], [0, 100, 0], [-100, 100, 0]])
    mesh = b.add_mesh([b.primitive(quad, QUAD_INDICES)])
    b.add_scene([b.add_node(mesh=mesh), b.add_node(camera=b.add_perspective_camera(1.0), translation=(0, 0, 5))])
    result = mbao.render(load_clean(b.write(tmp_path / "quarter.glb")), width=8, height=8, samples=1)
    expected = np.zeros((8, 8), bool)
    expected[:4, :4] = True
    np.testing.assert_array_equal(result.mask, expected)


def test_render_a_loaded_file_without_camera(tmp_path):
    scene = load_clean(single_mesh_file(tmp_path / "plain.gltf", lambda b: [b.primitive(QUAD, QUAD_INDICES)]))
    assert scene.camera is None
    result = mbao.render(scene, width=8, height=8, samples=1)
    assert result.mask.any()
    assert np.isfinite(result.ao).all()
