"""The same scene in millimetres or kilometres, at the origin or far from it,
renders the same image (issue 6), up to the limit of float32 vertices.

The renderer works relative to a corner of the scene where it lies far from the
origin (Scene.kd_tree()["origin"]), so its own rounding scales with the scene's
size. What it cannot undo is the rounding of vertices to float32 before they reach it: far from the origin they
lie on a coarse grid, and mbao warns once that grid exceeds 1e-3 of the scene.

"The same image" is judged against the estimator's own noise. With the same
seed both renders use the same random numbers, so they differ only where
rounding sends a ray the other way; each such difference is at most one
pixel's noise. The checks: identical coverage masks; a mean difference within
4 standard errors of the paired per-pixel differences (no systematic shift);
and a root-mean-square difference below the per-pixel noise of the estimator,
measured as the spread between two renders with different seeds (the
transformed image is closer to the original than a rerun would be).
"""

import warnings

import numpy as np
import pytest

import mbao

SIZE = 48
CORNELL = mbao.cornell_box()
EXTENT = float(np.max(np.subtract(*CORNELL.bounds[::-1])))
RADIUS = 300.0  # mm: the AO radius of the comparisons, scaled with the scene
# Off every axis, so that no coordinate stays small.
DIRECTION = np.array([1.0, 0.6, -0.3])


def moved(scale, shift_extents):
    """The Cornell box and its camera scaled about the origin, then moved by
    shift_extents scene extents along DIRECTION, computed in float64."""
    offset = DIRECTION * shift_extents * EXTENT * scale
    camera = CORNELL.camera
    vertices = CORNELL.vertices.astype(np.float64) * scale + offset
    eye = np.asarray(camera.eye, np.float64) * scale + offset
    target = np.asarray(camera.target, np.float64) * scale + offset
    return vertices, mbao.Camera(eye.tolist(), target.tolist(), camera.up, camera.vfov_deg)


def render(vertices, camera, scale=1.0, seed=0, **settings):
    mesh = mbao.Mesh(vertices, CORNELL.indices)
    return mbao.render(mesh, camera=camera, width=SIZE, height=SIZE, max_distance=RADIUS * scale, seed=seed, **settings)


def assert_same_image(result, original, noise):
    assert np.array_equal(result.mask, original.mask)
    difference = (result.ao - original.ao)[original.mask].astype(np.float64)
    standard_error = difference.std() / np.sqrt(difference.size)
    assert (
        abs(difference.mean()) <= 4.0 * standard_error
    ), f"mean difference {difference.mean():.2e} is more than 4 standard errors ({standard_error:.2e})"
    rms = np.sqrt(np.mean(difference**2))
    assert rms < noise, f"rms difference {rms:.4f} is not below the estimator's per-pixel noise {noise:.4f}"


SETTINGS = [
    dict(bounces=1, estimator="branching"),
    dict(bounces=2, estimator="branching"),
    dict(bounces=3, estimator="path"),
]


@pytest.fixture(scope="module", params=SETTINGS, ids=lambda s: f"b{s['bounces']}-{s['estimator']}")
def original(request):
    """The untransformed render and its per-pixel noise."""
    vertices, camera = moved(1.0, 0.0)
    first = render(vertices, camera, **request.param)
    rerun = render(vertices, camera, seed=1, **request.param)
    spread = (first.ao - rerun.ao)[first.mask]
    # Two independent renders differ by sqrt(2) times one render's noise.
    noise = np.sqrt(np.mean(spread.astype(np.float64) ** 2) / 2.0)
    return request.param, first, noise


# The ends of the sizes mbao takes: 1e-17 and 1e18 across.
@pytest.mark.parametrize("scale", [1e-4, 1e4, 1e-17 / EXTENT, 1e18 / EXTENT])
def test_scaled_scene_renders_the_same_image(original, scale):
    settings, image, noise = original
    vertices, camera = moved(scale, 0.0)
    assert_same_image(render(vertices, camera, scale, **settings), image, noise)


@pytest.mark.parametrize("scale, shift", [(1.0, 1e3), (1.0, 1e4), (1e-4, 1e3), (1e4, 1e3)])
def test_scene_far_from_the_origin_renders_the_same_image(original, scale, shift):
    settings, image, noise = original
    vertices, camera = moved(scale, shift)
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # no placement warning this near
        result = render(vertices, camera, scale, **settings)
    assert_same_image(result, image, noise)


@pytest.mark.parametrize("shift", [1e5, 1e6])
def test_scene_whose_float32_vertices_are_coarse_gets_a_warning(shift):
    vertices, _ = moved(1.0, shift)
    with pytest.warns(UserWarning, match=r"mesh is .* across but lies up to .* float32 vertex coordinates are"):
        mesh = mbao.Mesh(vertices, CORNELL.indices)
    assert len(mesh.warnings) == 1


def test_loaded_scene_names_its_file_in_the_warning(tmp_path):
    """A file whose node places its mesh a million extents away."""
    from gltf_writer import GltfBuilder

    b = GltfBuilder()
    mesh = b.add_mesh([b.primitive(positions=CORNELL.vertices, indices=CORNELL.indices)])
    b.add_scene([b.add_node(mesh=mesh, translation=(DIRECTION * 1e6 * EXTENT).tolist())])
    path = b.write(tmp_path / "far.glb")
    with pytest.warns(UserWarning, match=r"far\.glb.*float32"):
        mbao.load(path)


@pytest.mark.parametrize("shift", [1e6, 1e7])
def test_far_from_the_origin_the_renderer_adds_nothing_to_float32_rounding(original, shift):
    """The scene as float32 stores it a million extents away, rendered there
    and rendered moved back to the origin (exactly, in float64): the same
    image. Beyond the warning, the error is the input's, not mbao's."""
    settings, _, noise = original
    far_vertices, far_camera = moved(1.0, shift)
    far_vertices = far_vertices.astype(np.float32)
    eye, target = (np.asarray(p, np.float32) for p in (far_camera.eye, far_camera.target))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # the placement warning is expected here
        far = render(
            far_vertices, mbao.Camera(eye.tolist(), target.tolist(), far_camera.up, far_camera.vfov_deg), **settings
        )
    offset = DIRECTION * shift * EXTENT
    near_camera = mbao.Camera((eye - offset).tolist(), (target - offset).tolist(), far_camera.up, far_camera.vfov_deg)
    near = render(far_vertices.astype(np.float64) - offset, near_camera, **settings)
    assert_same_image(far, near, noise)


def test_the_render_origin_is_a_corner_on_far_axes_and_zero_on_near_ones():
    """Per axis: the near edge where the scene lies farther from 0 than it is
    wide (every vertex then moves exactly), else 0."""
    assert mbao.Mesh(CORNELL.vertices, CORNELL.indices).kd_tree()["origin"] == (0.0, 0.0, 0.0)
    vertices, _ = moved(1.0, 1e3)
    mesh = mbao.Mesh(vertices, CORNELL.indices)
    lo, hi = mesh.bounds
    # DIRECTION is (+, +, -): the lower edge on x and y, the upper one on z.
    assert mesh.kd_tree()["origin"] == (lo[0], lo[1], hi[2])
    half_away = mbao.Mesh(CORNELL.vertices + [0.5 * EXTENT, 0, 0], CORNELL.indices)
    assert half_away.kd_tree()["origin"] == (0.0, 0.0, 0.0)  # nearer to 0 than it is wide


@pytest.mark.parametrize("scale", [1e-22, 1e17])
def test_a_scene_too_small_or_too_large_for_exact_float32_ray_tests_is_refused(scale):
    """Not rendered silently wrong: the Cornell box 5.6e-20 across hit 877 of its
    941 pixels, all with AO 1, and 5.6e19 across 119 with AO near 1."""
    vertices, _ = moved(scale, 0.0)
    size = f"{EXTENT * scale:g}".replace("+", r"\+")
    with pytest.raises(ValueError, match=rf"the scene is {size} across; .* exact for scenes 1e-17 to 1e\+18 across"):
        mbao.Mesh(vertices, CORNELL.indices)


def test_scene_wider_than_float32_can_span_is_rejected():
    vertices = np.array([[-3e38, 0, 0], [3e38, 0, 0], [0, 1, 0]])
    with pytest.raises(ValueError, match="wider than float32"):
        mbao.Mesh(vertices, [[0, 1, 2]])


def same_plane(a, b):
    corners = CORNELL.vertices[CORNELL.indices[[a, b]]].astype(np.float64)
    normal = np.cross(corners[0, 1] - corners[0, 0], corners[0, 2] - corners[0, 0])
    normal /= np.linalg.norm(normal)
    return np.allclose((corners[1] - corners[0, 0]) @ normal, 0.0, atol=1e-3)


def test_trace_far_from_the_origin_finds_the_same_hits():
    """Rays given in world coordinates far away hit what the same rays hit at
    the origin: the tree and the rays share the scene's frame. At 1e3 extents
    float32 rounds vertices and origins to a grid of `spacing`; rays whose hit
    lies within 16 grid steps of an edge, or that meet their triangle at a
    grazing angle, may legitimately change, so only the others are compared,
    to the accuracy that grid allows. Where triangles overlap in one plane
    (the Cornell light in the ceiling) either may be reported."""
    offset = DIRECTION * 1e3 * EXTENT
    far_vertices = (CORNELL.vertices.astype(np.float64) + offset).astype(np.float32)
    spacing = float(np.spacing(np.abs(far_vertices).max()))
    near = mbao.Mesh(CORNELL.vertices, CORNELL.indices)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        far = mbao.Mesh(far_vertices, CORNELL.indices)
    rng = np.random.default_rng(7)
    origins = rng.uniform(50, 500, size=(4000, 3))
    directions = rng.normal(size=(4000, 3))
    directions /= np.linalg.norm(directions, axis=1, keepdims=True)
    t_near, triangle_near, barycentrics = mbao.trace(near, origins, directions)
    t_far, triangle_far, _ = mbao.trace(far, (origins + offset).astype(np.float32), directions)

    hit = triangle_near >= 0
    corners = CORNELL.vertices[CORNELL.indices[triangle_near[hit]]].astype(np.float64)
    normal = np.cross(corners[:, 1] - corners[:, 0], corners[:, 2] - corners[:, 0])
    double_area = np.linalg.norm(normal, axis=1)
    weights = np.column_stack([1.0 - barycentrics[hit].sum(axis=1), barycentrics[hit]])
    opposite_edges = np.stack([corners[:, (i + 2) % 3] - corners[:, (i + 1) % 3] for i in range(3)], axis=1)
    distance_to_edges = (weights * double_area[:, None] / np.linalg.norm(opposite_edges, axis=2)).min(axis=1)
    cosine = np.abs(np.einsum("ij,ij->i", normal / double_area[:, None], directions[hit]))
    clear = (distance_to_edges > 16 * spacing) & (cosine > 0.1)
    assert clear.sum() > 1000  # enough rays are compared for the test to mean something

    far_triangle, near_triangle = triangle_far[hit][clear], triangle_near[hit][clear]
    assert np.all(far_triangle >= 0)
    assert all(same_plane(a, b) for a, b in zip(far_triangle, near_triangle) if a != b)
    np.testing.assert_array_less(np.abs(t_far[hit] - t_near[hit])[clear], 4 * spacing / cosine[clear])
