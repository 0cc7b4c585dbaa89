"""render_sequence(temporal=...): SPEC 7.4's accumulation of a sequence's
frames, checked against the frames rendered one by one, against the
reprojection computed here from traced rays, and against the spread of
independent sequences."""

import math

import numpy as np
import pytest

import mbao
from analytic import spec_image_position, spec_ray_directions
from meshes import box, merge, plane

SIZE = 64


def sequence(scene, cameras, **settings):
    return list(mbao.render_sequence(scene, cameras, **settings))


def test_a_still_camera_averages_its_frames_as_a_progressive_render_does():
    """Reprojection into the same camera is the identity: frame k is the mean of
    the renders with seeds seed .. seed + k, and each pixel that hit has k + 1
    frames of history."""
    settings = dict(width=SIZE, height=SIZE, bounces=2, seed=5)
    frames = sequence(mbao.cornell_box(), [None] * 4, **settings)
    raw = [mbao.render(mbao.cornell_box(), **dict(settings, seed=5 + k)) for k in range(4)]
    for k, frame in enumerate(frames):
        mean = np.mean([r.ao for r in raw[: k + 1]], axis=0)
        np.testing.assert_allclose(frame.ao, mean, atol=1e-6)
        np.testing.assert_array_equal(frame.history_length, np.where(frame.mask, k + 1, 0))


def test_the_history_is_capped_at_max_length():
    """Past N frames, each new one weighs 1/N: a = a' + (c - a') / N."""
    settings = dict(width=32, height=32, bounces=1, seed=2)
    frames = sequence(mbao.cornell_box(), [None] * 4, temporal=mbao.Temporal(max_length=2), **settings)
    raw = [mbao.render(mbao.cornell_box(), **dict(settings, seed=2 + k)).ao for k in range(4)]
    expected = raw[0]
    for k in range(1, 4):
        expected = expected + (raw[k] - expected) / 2
    np.testing.assert_allclose(frames[3].ao, expected, atol=1e-6)
    assert frames[3].history_length.max() == 2


def test_without_temporal_each_frame_is_its_own_render():
    settings = dict(width=32, height=32, bounces=1, seed=8)
    frames = sequence(mbao.cornell_box(), [None] * 2, temporal=False, **settings)
    np.testing.assert_array_equal(frames[1].ao, mbao.render(mbao.cornell_box(), **dict(settings, seed=9)).ao)
    assert frames[1].history_length is None and frames[1].stats["temporal_ms"] == 0.0


def test_the_error_falls_as_one_over_the_square_root_of_the_frames():
    """Two sequences of a still camera on disjoint seeds: the mean square of
    their difference is 2 sigma^2 / k after k frames, so 16 frames have a
    sixteenth of one frame's, and the accumulated variance u predicts it.
    Tolerance: 4 standard errors of the means over the pixels (independent
    pixels; frames 1 and 16 of a sequence correlate positively, which only
    narrows the spread of the difference)."""
    settings = dict(width=SIZE, height=SIZE, bounces=2, variance=True)
    a = sequence(mbao.cornell_box(), [None] * 16, seed=0, **settings)
    b = sequence(mbao.cornell_box(), [None] * 16, seed=1000, **settings)
    mask = a[0].mask
    first, last = ((a[k].ao - b[k].ao)[mask] ** 2 for k in (0, 15))
    error = [x.std() / math.sqrt(x.size) for x in (first, last)]
    assert abs(16 * last.mean() - first.mean()) <= 4 * math.hypot(16 * error[1], error[0])
    predicted = (a[15].variance + b[15].variance)[mask]
    assert abs(last.mean() - predicted.mean()) <= 4 * error[1]


# A box standing on a floor, and two cameras above it: the second, moved to
# the right, sees floor behind the box that the first did not, some of it where
# the first saw the box's top, parallel to the floor and a unit above it.
BOX_FACES = 6  # box() lists each face's two triangles 6 apart; the floor's come after them
BOX_TOP, FLOOR = 3, BOX_FACES


def _box_on_floor():
    vertices, indices = merge(box((-0.5, 0.0, -0.5), (0.5, 1.0, 0.5)), plane(4.0))
    return mbao.Mesh(vertices, indices)


FIRST = mbao.Camera((0.0, 2.0, 3.0), (0.0, 0.4, 0.0), vfov_deg=50.0)
SECOND = mbao.Camera((0.6, 2.2, 3.1), (0.6, 0.5, 0.0), vfov_deg=50.0)


def _face(triangle):
    """The flat face each triangle lies on: one of the box's 6, or the floor; -1 for a miss."""
    return np.where(triangle < 0, -1, np.where(triangle < 2 * BOX_FACES, triangle % BOX_FACES, BOX_FACES))


def _camera_hits(scene, camera):
    """Each pixel centre's hit point and face (SPEC 3.1), traced."""
    directions = spec_ray_directions(camera, SIZE, SIZE).reshape(-1, 3)
    origins = np.broadcast_to(np.asarray(camera.eye, float), directions.shape)
    t, triangle, _ = mbao.trace(scene, origins, directions)
    points = origins + np.where(np.isfinite(t), t, 1.0)[:, None] * directions  # a miss: any point ahead
    return points, _face(triangle)


def _reprojected_taps(scene):
    """For each pixel of the second camera: the first camera's 2 x 2 pixels
    around its point, their bilinear weights (one pixel where the point is
    within 1e-2 pixels of its centre), and whether all four are in the image
    and clearly chosen: not where the point lies within 1e-3 pixels of a row or
    column of centres or of that snapping distance, where the kernel's single
    precision may choose others."""
    points, faces = _camera_hits(scene, SECOND)
    x, y = spec_image_position(FIRST, SIZE, SIZE, points)
    snap = (np.abs(x - np.round(x)) <= 1e-2) & (np.abs(y - np.round(y)) <= 1e-2)
    x0, y0 = np.where(snap, np.round(x), np.floor(x)), np.where(snap, np.round(y), np.floor(y))
    fx, fy = np.where(snap, 0.0, x - x0), np.where(snap, 0.0, y - y0)
    off_centres = [np.abs(c - np.round(c)) for c in (x, y)]
    clear = np.all([(d > 1e-3) & (np.abs(d - 1e-2) > 1e-3) for d in off_centres], axis=0)
    inside = clear & (x0 >= 0) & (y0 >= 0) & (x0 + 1 < SIZE) & (y0 + 1 < SIZE)
    taps, weights = [], []
    for dy in (0, 1):
        for dx in (0, 1):
            taps.append(np.clip(y0 + dy, 0, SIZE - 1).astype(int) * SIZE + np.clip(x0 + dx, 0, SIZE - 1).astype(int))
            weights.append((fx if dx else 1.0 - fx) * (fy if dy else 1.0 - fy))
    return faces, np.array(taps), np.array(weights), inside


def test_a_moving_camera_keeps_the_history_of_the_surface_it_saw_and_starts_afresh_where_it_did_not():
    """On flat faces at right angles or a unit apart, a tap is valid (SPEC 7.4)
    exactly where it saw the same face. Where all four taps saw another face
    (the floor behind the box, hidden from the first camera: the normals differ,
    or on the box's top the planes), the second frame has no history: it is its
    own render. Where all four saw the pixel's face, it is the blend of its
    render with the first frame's bilinear lookup."""
    scene = _box_on_floor()
    settings = dict(width=SIZE, height=SIZE, bounces=1, seed=3)
    frames = sequence(scene, [FIRST, SECOND], **settings)
    first = mbao.render(scene, camera=FIRST, **settings).ao.ravel()
    second = mbao.render(scene, camera=SECOND, **dict(settings, seed=4)).ao.ravel()
    faces, taps, weights, inside = _reprojected_taps(scene)
    first_faces = _camera_hits(scene, FIRST)[1]
    same = first_faces[taps] == faces
    hit = faces >= 0
    disoccluded = hit & inside & ~same.any(axis=0)
    kept = hit & inside & same.all(axis=0)
    behind_the_top = disoccluded & (faces == FLOOR) & (first_faces[taps] == BOX_TOP).all(axis=0)
    assert behind_the_top.sum() >= 20 and disoccluded.sum() >= 50 and kept.sum() >= 1000  # the geometry's numbers
    history, ao = frames[1].history_length.ravel(), frames[1].ao.ravel()
    np.testing.assert_array_equal(history[disoccluded], 1)
    np.testing.assert_array_equal(ao[disoccluded], second[disoccluded])
    np.testing.assert_array_equal(history[kept], 2)
    looked_up = (weights * first[taps]).sum(axis=0)
    np.testing.assert_allclose(ao[kept], (looked_up + second)[kept] / 2, atol=1e-4)  # float projection


def test_a_sequence_is_a_function_of_its_seed_and_settings():
    settings = dict(width=32, height=32, bounces=2, seed=6, denoise=True)
    one, two = (sequence(mbao.cornell_box(), [None, None], **settings) for _ in range(2))
    for a, b in zip(one, two):
        np.testing.assert_array_equal(a.ao, b.ao)


@pytest.mark.parametrize(
    "arguments, error, message",
    [
        (dict(temporal="yes"), TypeError, "temporal must be True, False or an mbao.Temporal"),
        (dict(spp=2), ValueError, "temporal accumulation needs spp=1"),
        (dict(samples=1), ValueError, "temporal accumulation weighs values by their variance"),
        (dict(method="hbao"), ValueError, "HBAO has none"),
    ],
)
def test_bad_sequences_are_refused(arguments, error, message):
    with pytest.raises(error, match=message):
        sequence(mbao.cornell_box(), [None], width=16, height=16, **arguments)


def test_arguments_are_checked_when_the_sequence_is_made_not_at_its_first_frame():
    with pytest.raises(TypeError, match="temporal must be"):
        mbao.render_sequence(mbao.cornell_box(), [None], temporal=1)
    with pytest.raises(TypeError, match="unexpected keyword argument 'bounce'"):
        mbao.render_sequence(mbao.cornell_box(), [None], bounce=2)


def test_max_length_is_checked():
    with pytest.raises(ValueError, match=r"max_length must be in \[1, 65536\]"):
        mbao.Temporal(max_length=0)
