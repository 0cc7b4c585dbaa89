"""Ambient occlusion against closed-form answers (SPEC 1-3). Statistical
checks allow 4 standard errors of the estimator, computed from its own variance."""

import math

import numpy as np
import pytest

import mbao
from analytic import assert_within_standard_errors, one_pixel_access, polygon_occlusion
from meshes import box, disk, merge, plane, sphere

ESTIMATORS = ("branching", "path")


@pytest.mark.parametrize("bounces", [1, 2, 3])
@pytest.mark.parametrize("estimator", ESTIMATORS)
def test_a_plane_is_open_everywhere(bounces, estimator):
    """Nothing above a plane occludes it: every covered pixel is exactly 1, also
    on a plane 10^4 times larger than the view, where self-intersection would show."""
    for half_size, eye in ((10.0, (0.0, 3.0, 4.0)), (1e4, (0.0, 1.0, 2.0))):
        scene = mbao.Mesh(*plane(half_size, divisions=3))
        camera = mbao.Camera(eye, (0.0, 0.0, 0.0), vfov_deg=60.0)
        result = mbao.render(scene, camera=camera, width=24, height=16, bounces=bounces, samples=8, estimator=estimator)
        assert result.mask.sum() > 100
        np.testing.assert_array_equal(result.ao[result.mask], 1.0)


@pytest.mark.filterwarnings("ignore:.*looks closed")  # closed on purpose, with an unlimited radius
@pytest.mark.parametrize("bounces", [1, 2, 3])
@pytest.mark.parametrize("estimator", ESTIMATORS)
def test_a_closed_box_is_closed_everywhere(bounces, estimator):
    """Seen from inside a closed box every ray hits a wall, whatever the bounce:
    every pixel is exactly 0. A ray slipping through an edge would show as > 0."""
    scene = mbao.Mesh(*box((-1.0, -1.5, -2.0), (1.0, 1.5, 2.0)))
    camera = mbao.Camera((0.2, -0.3, 0.1), (0.5, 0.4, 1.0), vfov_deg=100.0)
    result = mbao.render(scene, camera=camera, width=20, height=20, bounces=bounces, samples=4, estimator=estimator)
    assert result.mask.all()
    np.testing.assert_array_equal(result.ao, 0.0)


def test_convex_sphere_sees_no_occlusion_from_outside():
    """With geometric normals every direction leaving a convex surface escapes."""
    vertices, indices, normals = sphere(2.0, (1.0, -1.0, 0.5))
    scene = mbao.Mesh(vertices, indices, normals)
    camera = mbao.Camera((1.0, 2.0, 7.0), (1.0, -1.0, 0.5), vfov_deg=45.0)
    result = mbao.render(scene, camera=camera, width=24, height=24, bounces=2, samples=8, normals="geometric")
    assert result.mask.sum() > 100
    np.testing.assert_array_equal(result.ao[result.mask], 1.0)


@pytest.mark.parametrize("estimator", ESTIMATORS)
def test_point_under_a_coaxial_disk(estimator):
    """L_1 = h^2 / (h^2 + R^2) for a point under a parallel disk of radius R at
    height h (here a 256-sided polygon, whose exact value Lambert's formula gives)."""
    h, R, r = 1.0, 0.75, 1 << 16
    disk_mesh = disk(R, h, 256)
    scene = mbao.Mesh(*merge(plane(20.0), disk_mesh))
    expected = 1.0 - polygon_occlusion(np.zeros(3), np.array([0.0, 1.0, 0.0]), disk_mesh[0][1:])
    assert abs(expected - h * h / (h * h + R * R)) < 1e-3  # the polygon is a disk to this precision
    access, stats = one_pixel_access(scene, (1.5, 0.4, 0.3), (0.0, 0.0, 0.0), samples=r, estimator=estimator, seed=3)
    assert stats["rays_secondary"] == r  # every direction is above the floor: all traced
    assert_within_standard_errors(access, expected, r)


def test_max_distance_shrinks_the_disk():
    """Hits beyond max_distance count as misses: under the disk only the part
    within distance d occludes, a disk of radius sqrt(d^2 - h^2), so L_1 = h^2 / d^2."""
    h, R, r = 1.0, 0.75, 1 << 16
    scene = mbao.Mesh(*merge(plane(20.0), disk(R, h, 256)))
    eye, target = (1.5, 0.4, 0.3), (0.0, 0.0, 0.0)
    near, _ = one_pixel_access(scene, eye, target, samples=r, max_distance=0.999 * h)
    assert near == 1.0
    d = 1.1
    within, _ = one_pixel_access(scene, eye, target, samples=r, max_distance=d, seed=5)
    assert_within_standard_errors(within, h * h / (d * d), r)
    # Beyond the disk's farthest point (at sqrt(h^2 + R^2) = 1.25), max_distance changes nothing.
    unlimited, _ = one_pixel_access(scene, eye, target, samples=4096)
    beyond, _ = one_pixel_access(scene, eye, target, samples=4096, max_distance=1.26)
    assert beyond == unlimited


def leaning_normals(vertices, alpha):
    """Shading normals leaning from +y by alpha towards +x."""
    return np.tile([math.sin(alpha), math.cos(alpha), 0.0], (len(vertices), 1))


def test_directions_below_the_geometric_surface_are_mirrored_in_it():
    """On a lone plane whose shading normals lean by alpha, the cosine lobe
    around the shading normal dips below the plane; those directions are
    mirrored above it (SPEC 3.3), where nothing occludes them: 1 exactly,
    every direction traced."""
    alpha, r = math.radians(50.0), 1 << 12
    vertices, indices = plane(20.0)
    scene = mbao.Mesh(vertices, indices, leaning_normals(vertices, alpha))
    leaning, stats = one_pixel_access(scene, (0.3, 1.0, 1.2), (0.0, 0.0, 0.0), samples=r)
    assert leaning == 1.0 and stats["rays_secondary"] == r


def mirrored_lobe_disk_occlusion(normal, h, R, nodes=96):
    """The weight of the directions from the origin that, mirrored above the
    plane y = 0 where below it, meet the disk of radius R at height h (facing
    down), when drawn with density max(0, n.w) / pi around `normal` (SPEC 3.3):
    the integral over the disk of (max(0, n.w) + max(0, n.M(w))) / pi * cos / d^2,
    M negating y; Gauss-Legendre in radius and angle."""
    radii, radius_weights = np.polynomial.legendre.leggauss(nodes)
    angles, angle_weights = np.polynomial.legendre.leggauss(4 * nodes)
    rho, phi = (radii + 1) * R / 2, (angles + 1) * math.pi
    rr, pp = np.meshgrid(rho, phi, indexing="ij")
    points = np.stack([rr * np.cos(pp), np.full_like(rr, h), rr * np.sin(pp)], axis=-1)
    distance = np.linalg.norm(points, axis=-1)
    w = points / distance[..., None]
    mirrored = w * [1.0, -1.0, 1.0]
    density = (np.maximum(0.0, w @ normal) + np.maximum(0.0, mirrored @ normal)) / math.pi
    integrand = density * (h / distance) / distance**2 * rr  # cos at the disk, 1/d^2, polar area element
    return float(np.einsum("i,j,ij->", radius_weights * R / 2, angle_weights * math.pi, integrand))


@pytest.mark.parametrize("estimator", ESTIMATORS)
def test_a_disk_over_leaning_normals_occludes_by_the_mirrored_lobe(estimator):
    """Under a coaxial disk, normals leaning by alpha: L_1 = 1 minus the weight
    of the mirrored lobe that meets the disk (SPEC 3.3). The same with upright
    normals is the closed form h^2 / (h^2 + R^2), which checks the quadrature."""
    h, R, alpha, r = 1.0, 0.75, math.radians(50.0), 1 << 16
    upright = mirrored_lobe_disk_occlusion(np.array([0.0, 1.0, 0.0]), h, R)
    assert abs(1.0 - upright - h * h / (h * h + R * R)) < 1e-6
    disk_mesh = disk(R, h, 256)
    vertices, indices = merge(plane(20.0), disk_mesh)
    scene = mbao.Mesh(vertices, indices, leaning_normals(vertices, alpha))
    normal = np.array([math.sin(alpha), math.cos(alpha), 0.0])
    # The 256-gon is the disk to 1e-4 (test_point_under_a_coaxial_disk); far below 4 standard errors here.
    expected = 1.0 - mirrored_lobe_disk_occlusion(normal, h, R)
    access, _ = one_pixel_access(scene, (1.5, 0.4, 0.3), (0.0, 0.0, 0.0), samples=r, estimator=estimator, seed=7)
    assert_within_standard_errors(access, expected, r)


@pytest.mark.parametrize("bounces", [1, 2])
def test_a_closed_convex_mesh_with_smooth_normals_is_open_everywhere(bounces):
    """A smooth-shaded sphere and box (the box's corners shared by its faces, so
    its normals point out along the diagonals, as Blender's smooth-shaded cube):
    with the default shading normals every direction, mirrored where below its
    triangle, leaves the convex mesh, so every pixel and vertex is 1 exactly."""
    vertices, indices, normals = sphere(2.0, (1.0, -1.0, 0.5))
    box_vertices, box_indices = box((-1.0, -1.0, -1.0), (1.0, 1.0, 1.0))
    box_indices = box_indices[:, ::-1]  # the box's triangles face out
    for scene, eye, target in (
        (mbao.Mesh(vertices, indices, normals), (1.0, 2.0, 7.0), (1.0, -1.0, 0.5)),
        (mbao.Mesh(box_vertices, box_indices, box_vertices / math.sqrt(3.0)), (2.5, 3.0, 4.0), (0.0, 0.0, 0.0)),
    ):
        camera = mbao.Camera(eye, target, vfov_deg=45.0)
        result = mbao.render(scene, camera=camera, width=24, height=24, bounces=bounces, samples=8)
        assert result.mask.sum() > 100
        np.testing.assert_array_equal(result.ao[result.mask], 1.0)
        baked = mbao.bake(scene, bounces=bounces, samples=16, progress=False)
        np.testing.assert_array_equal(baked.values, 1.0)


def test_shading_normals_are_turned_to_the_side_the_ray_came_from():
    """Normals given pointing away from the camera are flipped like the
    geometric normal: seen from below, a plane with downward... or upward
    normals gives the same image."""
    vertices, indices = plane(20.0)
    up = np.tile([0.0, 1.0, 0.0], (len(vertices), 1))
    camera = mbao.Camera((0.0, -2.0, 1.0), (0.0, 0.0, 0.0), vfov_deg=60.0)
    images = [
        mbao.render(mbao.Mesh(vertices, indices, n), camera=camera, width=12, height=12, samples=8).ao
        for n in (up, -up)
    ]
    np.testing.assert_array_equal(images[0], images[1])
    np.testing.assert_array_equal(images[0], 1.0)
