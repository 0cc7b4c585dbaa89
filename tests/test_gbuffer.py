"""The G-buffer (SPEC 7.2), the one that HBAO, the spatial filter and temporal
accumulation read: per pixel, the camera ray through its centre and what it
hit, checked against mbao.trace's rays and the scene's own triangles."""

import numpy as np
import pytest

import mbao
from conftest import shared_scene

WIDTH, HEIGHT = 40, 30


def camera_basis(camera):
    forward = np.subtract(camera.target, camera.eye).astype(np.float64)
    forward /= np.linalg.norm(forward)
    right = np.cross(forward, camera.up)
    right /= np.linalg.norm(right)
    return forward, right, np.cross(right, forward)


def pixel_centre_directions(camera, width, height):
    """SPEC 3.1's rays through the pixel centres, unit length, (height, width, 3)."""
    forward, right, up = camera_basis(camera)
    tan_half = np.tan(np.radians(camera.vfov_deg) / 2)
    u = ((np.arange(width) + 0.5) / width * 2 - 1) * tan_half * width / height
    v = (1 - (np.arange(height) + 0.5) / height * 2) * tan_half
    directions = forward + u[None, :, None] * right + v[:, None, None] * up
    return directions / np.linalg.norm(directions, axis=-1, keepdims=True)


def expected_gbuffer(scene, camera, width, height):
    """What the G-buffer must hold, from mbao.trace and the mesh: (t, triangle, barycentrics, directions)."""
    directions = pixel_centre_directions(camera, width, height).reshape(-1, 3)
    t, triangle, barycentrics = mbao.trace(scene, np.tile(camera.eye, (len(directions), 1)), directions)
    return t, triangle, barycentrics, directions


def turned_to(normals, towards):
    """Unit normals, each turned to the side `towards` points to."""
    normals = normals / np.linalg.norm(normals, axis=-1, keepdims=True)
    return np.where(np.einsum("ij,ij->i", normals, towards)[:, None] < 0, -normals, normals)


SCENES = ["cornell box", "bunny", "sponza"]


def scene_and_camera(name):
    if name == "cornell box":
        scene = mbao.cornell_box()
        return scene, scene.camera
    folder = shared_scene(name)
    return mbao.load(folder / "scene.glb"), mbao.Camera.load(folder / "camera.json")


@pytest.mark.parametrize("name", SCENES)
def test_each_pixel_holds_its_centre_rays_hit(name):
    scene, camera = scene_and_camera(name)
    g = mbao.gbuffer(scene, camera=camera, width=WIDTH, height=HEIGHT)
    t, triangle, barycentrics, directions = expected_gbuffer(scene, camera, WIDTH, HEIGHT)
    hit = np.isfinite(t)
    np.testing.assert_array_equal(g.mask.reshape(-1), hit)
    assert 0.2 < hit.mean()
    # The closest hit; a ray through a shared edge may name either triangle, at the same distance.
    np.testing.assert_allclose(g.t.reshape(-1)[hit], t[hit], rtol=1e-5)
    same = g.triangle.reshape(-1)[hit] == triangle[hit]
    assert same.mean() > 0.99
    scale = np.abs(scene.vertices).max()
    points = np.asarray(camera.eye) + t[hit, None] * directions[hit]
    np.testing.assert_allclose(g.position.reshape(-1, 3)[hit], points, atol=1e-5 * scale)
    forward, _, _ = camera_basis(camera)
    np.testing.assert_allclose(g.depth.reshape(-1)[hit], (points - camera.eye) @ forward, atol=1e-5 * scale)
    np.testing.assert_allclose(
        g.footprint.reshape(-1)[hit], 2 * t[hit] * np.tan(np.radians(camera.vfov_deg) / 2) / HEIGHT, rtol=1e-5
    )

    corners = scene.vertices[scene.indices[triangle[hit][same]]]
    geometric = turned_to(
        np.cross(corners[:, 1] - corners[:, 0], corners[:, 2] - corners[:, 0]), -directions[hit][same]
    )
    np.testing.assert_allclose(g.geometric_normal.reshape(-1, 3)[hit][same], geometric, atol=1e-5)
    shading = geometric
    if scene.normals is not None:  # SPEC 3.3: the interpolated vertex normal, on the geometric normal's side
        b = barycentrics[hit][same]
        weights = np.column_stack([1 - b[:, 0] - b[:, 1], b[:, 0], b[:, 1]])
        shading = turned_to(
            np.einsum("ij,ijk->ik", weights, scene.normals[scene.indices[triangle[hit][same]]]), geometric
        )
    np.testing.assert_allclose(g.shading_normal.reshape(-1, 3)[hit][same], shading, atol=1e-4)


def test_a_missed_pixel_holds_nothing():
    scene = mbao.cornell_box()
    camera = mbao.Camera((278, 273, -800), (400, 300, 0), (0, 1, 0), 60.0)  # sees past the box's edge
    g = mbao.gbuffer(scene, camera=camera, width=WIDTH, height=HEIGHT)
    assert not g.mask.all()
    missed = ~g.mask
    np.testing.assert_array_equal(g.triangle[missed], -1)
    for plane in (g.t, g.depth, g.footprint, g.position, g.geometric_normal, g.shading_normal):
        np.testing.assert_array_equal(plane[missed], 0.0)


def test_hbao_covers_the_pixels_the_gbuffer_does():
    scene = mbao.cornell_box()
    camera = mbao.Camera((278, 273, -800), (400, 300, 0), (0, 1, 0), 60.0)
    g = mbao.gbuffer(scene, camera=camera, width=WIDTH, height=HEIGHT)
    hbao = mbao.render(scene, camera=camera, width=WIDTH, height=HEIGHT, method="hbao", max_distance=100.0)
    np.testing.assert_array_equal(hbao.mask, g.mask)


@pytest.mark.parametrize("traversal", ["stack", "lanes", "short-stack"])
def test_every_walk_makes_the_same_gbuffer(traversal):
    """Camera rays in packets (lanes) or one per work item: the same hits, so the same planes."""
    scene = mbao.cornell_box()
    reference = mbao.gbuffer(scene, width=WIDTH, height=HEIGHT, engine=mbao.Engine(traversal="stack"))
    g = mbao.gbuffer(scene, width=WIDTH, height=HEIGHT, engine=mbao.Engine(traversal=traversal))
    assert g.stats["traversal_mode"] == traversal
    for name in ("position", "t", "depth", "geometric_normal", "shading_normal", "footprint", "triangle", "mask"):
        np.testing.assert_array_equal(getattr(g, name), getattr(reference, name), err_msg=name)


def test_a_gbuffer_far_from_the_origin_is_in_world_units():
    """Positions come back in the world frame, whatever frame the device works in."""
    scene = mbao.cornell_box()
    offset = np.array([3e5, -2e5, 1e5], dtype=np.float32)
    moved = mbao.Mesh(scene.vertices + offset, scene.indices)
    camera = scene.camera
    far_camera = mbao.Camera(np.add(camera.eye, offset), np.add(camera.target, offset), camera.up, camera.vfov_deg)
    near, far = mbao.gbuffer(scene, width=WIDTH, height=HEIGHT), mbao.gbuffer(
        moved, camera=far_camera, width=WIDTH, height=HEIGHT
    )
    np.testing.assert_array_equal(far.mask, near.mask)
    np.testing.assert_allclose(far.position[far.mask] - offset, near.position[near.mask], atol=0.1)
