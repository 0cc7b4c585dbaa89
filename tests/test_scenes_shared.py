"""The shared test scenes (../shared/scenes, when present beside the checkout) load and render, and the
repository's copy of the Cornell box is still the shared file."""

import hashlib

import numpy as np
import pytest

import mbao
from conftest import REPO, SHARED_SCENES, shared_scene

CORNELL_SHA256 = "14f470b5cf62f5949ce05301423f98e97666403fee4c66c7d2724b83897d8211"


def test_the_committed_cornell_box_is_the_published_one():
    data = (REPO / "tests" / "data" / "cornell_box.glb").read_bytes()
    assert hashlib.sha256(data).hexdigest() == CORNELL_SHA256
    scene = mbao.load(REPO / "tests" / "data" / "cornell_box.glb")
    built_in = mbao.cornell_box()
    np.testing.assert_array_equal(scene.vertices, built_in.vertices)
    np.testing.assert_array_equal(scene.indices, built_in.indices)


def test_the_shared_cornell_box_is_the_committed_copy():
    folder = shared_scene("cornell_box")
    assert hashlib.sha256((folder / "scene.glb").read_bytes()).hexdigest() == CORNELL_SHA256


SCENES = sorted(p.name for p in SHARED_SCENES.glob("*") if (p / "scene.glb").exists()) or ["(none)"]


@pytest.mark.parametrize("name", SCENES)
def test_shared_scene_loads_and_renders_with_its_camera(name):
    folder = shared_scene(name)
    scene = mbao.load(folder / "scene.glb")
    camera = mbao.Camera.load(folder / "camera.json")
    result = mbao.render(scene, camera=camera, width=16, height=12, samples=2)
    assert result.mask.mean() > 0.2  # the camera looks at the scene
    assert 0.0 <= result.ao.min() and result.ao.max() <= 1.0
    assert result.ao[result.mask].mean() < 1.0  # something occludes something


def test_a_closed_scene_takes_the_radius_its_camera_suggests():
    """Sibenik is a closed cathedral: with an unlimited radius every AO ray hits
    something and the image is 0; its camera.json suggests 5, which render
    takes when no radius is given (SPEC 1)."""
    folder = shared_scene("sibenik")
    scene = mbao.load(folder / "scene.glb")
    settings = dict(camera=folder / "camera.json", width=24, height=24, samples=4, seed=1)
    suggested = mbao.render(scene, **settings)
    assert suggested.stats["max_distance"] == 5.0 and suggested.stats["max_distance_source"] == "camera"
    covered = suggested.ao[suggested.mask]
    # Far from 0: the mean exceeds the issue's 0.3 by more than 4 standard errors of the pixels' mean.
    assert covered.mean() - 4 * covered.std() / np.sqrt(covered.size) > 0.3
    with pytest.warns(UserWarning, match="looks closed"):
        unlimited = mbao.render(scene, max_distance=float("inf"), **settings)
    assert unlimited.stats["max_distance_source"] == "settings"
    np.testing.assert_array_equal(unlimited.ao[unlimited.mask], 0.0)
