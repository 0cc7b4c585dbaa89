"""The camera of SPEC 3.1: which pixel sees which point."""

import numpy as np

import mbao
from analytic import spec_ray_directions


def inside_triangle(points, a, b, c):
    """Which points (in the triangle's plane) lie inside, and how far from its edges."""
    n = np.cross(b - a, c - a)
    edges = [
        np.einsum("...i,i->...", np.cross(q - p, points - p), n) / np.linalg.norm(n) / np.linalg.norm(q - p)
        for p, q in ((a, b), (b, c), (c, a))
    ]
    distance = np.min(np.abs(edges), axis=0)
    return np.all(np.array(edges) > 0, axis=0), distance


def test_pixels_see_what_the_spec_formula_points_at():
    """An off-centre triangle in the plane z = 0, a tilted camera and a wide
    image: the coverage mask is exactly where the SPEC's pixel-centre rays
    meet the triangle (pixels whose ray passes within 1e-4 of an edge aside)."""
    a, b, c = np.array([-1.0, -0.5, 0.0]), np.array([2.0, 0.2, 0.0]), np.array([0.3, 1.7, 0.0])
    scene = mbao.Mesh([a, b, c], [[0, 1, 2]])
    camera = mbao.Camera((0.8, -0.6, 3.0), (0.2, 0.4, 0.0), up=(0.3, 1.0, 0.1), vfov_deg=50.0)
    width, height = 37, 23
    result = mbao.render(scene, camera=camera, width=width, height=height)

    directions = spec_ray_directions(camera, width, height)
    eye = np.asarray(camera.eye)
    t = -eye[2] / directions[..., 2]
    points = eye + t[..., None] * directions
    inside, distance = inside_triangle(points, a, b, c)
    clear = distance > 1e-4
    assert inside.sum() > 50 and (~inside).sum() > 50
    np.testing.assert_array_equal(result.mask[clear], inside[clear])
    # The triangle is bright where it is seen (nothing above it) and misses are 1.
    np.testing.assert_array_equal(result.ao, 1.0)


def test_row_zero_is_the_top_and_x_grows_to_the_right():
    """A quad filling the upper-left quarter of the view: y up is the top rows,
    -x is the left columns (right = forward x up)."""
    quad = np.array([[-5.0, 0.0, 0.0], [0.0, 0.0, 0.0], [0.0, 5.0, 0.0], [-5.0, 5.0, 0.0]])
    scene = mbao.Mesh(quad, [[0, 1, 2], [0, 2, 3]])
    camera = mbao.Camera((0.0, 0.0, 1.0), (0.0, 0.0, 0.0), vfov_deg=90.0)  # looking down -z, x to the right
    result = mbao.render(scene, camera=camera, width=8, height=8)
    expected = np.zeros((8, 8), bool)
    expected[:4, :4] = True
    np.testing.assert_array_equal(result.mask, expected)


def test_the_cornell_box_has_its_own_camera():
    camera = mbao.cornell_box().camera
    assert camera.eye == (278.0, 273.0, -800.0)
    assert camera.target == (278.0, 273.0, 0.0)
    assert camera.up == (0.0, 1.0, 0.0)
    assert camera.vfov_deg == np.float32(39.3077)


def test_a_mesh_without_a_camera_is_framed_whole():
    """The default camera of a mesh sees all of it, at any aspect ratio."""
    rng = np.random.default_rng(3)
    vertices = rng.normal(size=(60, 3)) * (4.0, 1.0, 0.5) + (10.0, -3.0, 2.0)
    scene = mbao.Mesh(vertices, np.arange(60).reshape(20, 3))
    for width, height in ((32, 32), (64, 16), (16, 64)):
        result = mbao.render(scene, width=width, height=height)
        rows, columns = np.nonzero(result.mask)
        assert len(rows) > 0
        # Nothing is cut off: no covered pixel on the image border.
        assert rows.min() > 0 and columns.min() > 0 and rows.max() < height - 1 and columns.max() < width - 1


def test_camera_frame_frames_the_whole_scene_whatever_camera_it_has(tmp_path):
    """SPEC 3.1: camera="frame" is the framing camera even where the file has
    a close-up camera of its own, which stays the default."""
    from gltf_writer import GltfBuilder
    from meshes import box, merge

    vertices, indices = merge(box((-4.0, 0.0, -1.0), (-3.0, 1.0, 0.0)), box((3.0, 0.0, -1.0), (4.0, 2.0, 0.0)))
    b = GltfBuilder()
    b.add_scene(
        [
            b.add_node(mesh=b.add_mesh([b.primitive(vertices, indices)])),
            b.add_node(camera=b.add_perspective_camera(0.3), translation=(3.5, 1.0, 3.0)),
        ]
    )
    scene = mbao.load(b.write(tmp_path / "close_up.glb"))
    width, height = 48, 32
    assert scene.default_camera(width, height).eye == scene.camera.eye  # the file's camera is the default
    framed = mbao.render(scene, camera="frame", width=width, height=height)
    np.testing.assert_array_equal(
        framed.ao, mbao.render(scene, camera=scene.framing_camera(width, height), width=width, height=height).ao
    )
    rows, columns = np.nonzero(framed.mask)
    assert rows.min() > 0 and columns.min() > 0 and rows.max() < height - 1 and columns.max() < width - 1
    assert columns.min() < width / 3 and columns.max() > 2 * width / 3  # both boxes, left and right
    close_up = mbao.render(scene, width=width, height=height).mask  # the file's camera: one box, cut by the border
    assert close_up[:, 0].any() or close_up[0, :].any() or close_up[:, -1].any() or close_up[-1, :].any()
