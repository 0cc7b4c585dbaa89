"""Pickling: scenes, meshes, cameras, settings and results travel to other
processes (multiprocessing, joblib, Dask) and come back as they were; an
unpickled scene renders the same image, bit for bit."""

import pickle

import numpy as np
import pytest

import mbao
from conftest import shared_scene


def round_trip(value):
    return pickle.loads(pickle.dumps(value, protocol=pickle.HIGHEST_PROTOCOL))


@pytest.fixture(scope="module")
def sponza():
    """Alpha masks, UV sets and materials: all a loaded scene holds but a camera."""
    return mbao.load(shared_scene("sponza") / "scene.glb", texcoords=True)


def test_a_scene_keeps_everything_it_holds(sponza):
    again = round_trip(sponza)
    assert type(again) is mbao.Scene and again.name == sponza.name and again.warnings == sponza.warnings
    for name in ("vertices", "indices", "normals"):
        np.testing.assert_array_equal(getattr(again, name), getattr(sponza, name))
    assert again.alpha_masks == sponza.alpha_masks and again.bounds == sponza.bounds
    assert sponza.camera is None and again.camera is None
    uv, uv_again = sponza.uv_sets, again.uv_sets
    assert uv_again["materials"] == uv["materials"] and uv_again["primitives"] == uv["primitives"]
    np.testing.assert_array_equal(uv_again["triangle_materials"], uv["triangle_materials"])
    for a, b in zip(uv_again["sets"], uv["sets"], strict=True):
        np.testing.assert_array_equal(a, b)


def test_a_scene_keeps_its_camera():
    cornell = mbao.cornell_box()
    assert repr(round_trip(cornell).camera) == repr(cornell.camera)


def test_an_unpickled_scene_renders_the_same_image(sponza):
    settings = dict(width=40, height=30, bounces=2, seed=7, max_distance=300.0)
    np.testing.assert_array_equal(mbao.render(round_trip(sponza), **settings).ao, mbao.render(sponza, **settings).ao)


def test_a_mesh_keeps_its_arrays_and_uvs():
    rng = np.random.default_rng(1)
    mesh = mbao.Mesh(
        rng.random((6, 3)), [[0, 1, 2], [3, 4, 5]], normals=rng.random((6, 3)), texcoords=rng.random((6, 2))
    )
    again = round_trip(mesh)
    assert type(again) is mbao.Mesh
    for name in ("vertices", "indices", "normals", "texcoords"):
        np.testing.assert_array_equal(getattr(again, name), getattr(mesh, name))
    settings = dict(width=16, height=16, seed=2)
    np.testing.assert_array_equal(mbao.render(again, **settings).ao, mbao.render(mesh, **settings).ao)


def test_cameras_and_settings():
    camera = mbao.Camera((1.0, 2.0, 3.0), (0.0, 0.5, 0.0), up=(0.0, 0.0, 1.0), vfov_deg=35.0, max_distance=4.0)
    again = round_trip(camera)
    assert (again.eye, again.target, again.up, again.vfov_deg, again.max_distance) == (
        camera.eye,
        camera.target,
        camera.up,
        camera.vfov_deg,
        camera.max_distance,
    )
    assert round_trip(mbao.Camera((0.0, 0.0, 1.0), (0.0, 0.0, 0.0))).max_distance is None
    for settings in (
        mbao.HBAO(directions=5, steps=3, angle_bias_deg=20.0, falloff=0.5),
        mbao.Denoise(iterations=3, sigma_plane=2.0, sigma_normal=64, sigma_value=1.5),
        mbao.Temporal(max_length=9),
    ):
        assert repr(round_trip(settings)) == repr(settings)


def test_results_and_bakes():
    result = mbao.render(mbao.cornell_box(), width=16, height=16, bounces=2, variance=True)
    again = round_trip(result)
    np.testing.assert_array_equal(again.ao, result.ao)
    np.testing.assert_array_equal(again.variance, result.variance)
    assert again.stats == result.stats
    baked = mbao.bake(mbao.cornell_box(), samples=4, progress=False)
    again = round_trip(baked)
    np.testing.assert_array_equal(again.values, baked.values)
    assert again.settings == baked.settings


def test_a_pickle_of_another_layout_is_refused_by_name():
    state = mbao.cornell_box().__getstate__()
    scene = mbao.Scene.__new__(mbao.Scene)
    with pytest.raises(ValueError, match="made by another version of mbao"):
        scene.__setstate__((state[0] + 1,) + state[1:])
