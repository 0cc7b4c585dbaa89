"""A bake split by its pixels' positions, here or on a Dask cluster, is the
whole bake, bit for bit (SPEC 6.6)."""

import gc
import importlib

import numpy as np
import pytest

import mbao
from mbao import _core
from mbao.devices import resolve
from mbao.scene import as_scene
from mbao.settings import RENDER, checked, engine_values
from meshes import box_grid, disk, merge, plane

SETTINGS = dict(bounces=2, samples=16, seed=3, progress=False)


def test_any_split_of_a_bakes_positions_is_the_whole_bake():
    scene = mbao.cornell_box()
    given = dict(
        bounces=2,
        estimator="path",
        rho=1.0,
        max_distance=float("inf"),
        normals="shading",
        seed=3,
        max_rays=_core.DEFAULT_MAX_RAYS,
    )
    values = dict(
        {name: checked(RENDER[name], value) for name, value in given.items()}, samples=4, **engine_values(mbao.Engine())
    )
    every_other = np.arange(0, scene.triangle_count, 2, dtype=np.uint32)
    whole, whole_error, _ = _core.bake_vertices(scene, every_other, resolve(None), values, 16, None)
    positions = _core.vertex_bake_positions(scene, every_other, 16)
    for cuts in ([0, positions], [0, 7, positions // 2 + 3, positions], [0, 1, 2, positions - 1, positions]):
        mean, second_moment = np.empty(positions, np.float32), np.empty(positions, np.float32)
        for first, end in zip(cuts, cuts[1:]):
            mean[first:end], second_moment[first:end], _ = _core.trace_vertex_bake(
                scene, every_other, resolve(None), values, 16, first, end, None
            )
        values_, errors = _core.finish_vertex_bake(scene, every_other, 16, mean, second_moment)
        np.testing.assert_array_equal(values_, whole)
        np.testing.assert_array_equal(errors, whole_error)


@pytest.fixture
def small_parts(monkeypatch):
    """Parts of 64 positions, so that small bakes go out in many."""
    monkeypatch.setattr(importlib.import_module("mbao.bake"), "_MIN_POSITIONS_PER_PART", 64)


@pytest.mark.filterwarnings("ignore:.*looks closed")
def test_a_vertex_bake_on_a_cluster_is_the_local_one(dask_client, small_parts):
    scene = mbao.Mesh(*box_grid(3))
    here = mbao.bake(scene, **SETTINGS)
    parts = []
    there = mbao.bake(scene, client=dask_client, **dict(SETTINGS, progress=lambda done, total: parts.append(total)))
    assert len(parts) > 1 and parts[-1] == len(parts)  # in several parts, each reported
    np.testing.assert_array_equal(there.values, here.values)
    np.testing.assert_array_equal(there.standard_error, here.standard_error)
    assert there.stats["rays_secondary"] == here.stats["rays_secondary"]


@pytest.mark.parametrize("texcoord", [0, "generate"])
@pytest.mark.filterwarnings("ignore:.*left out of the bake")  # with the floor's UVs the disk has no UV area
def test_a_texture_bake_on_a_cluster_is_the_local_one(dask_client, small_parts, texcoord):
    """A floor under a disk: the floor's own UVs, or a generated set of both."""
    half_size = 1.5
    floor, floor_indices = plane(half_size, divisions=6)
    vertices, indices = merge((floor, floor_indices), disk(0.8, 1.0, 32))
    texcoords = np.zeros((len(vertices), 2))
    texcoords[: len(floor)] = (np.asarray(floor)[:, [0, 2]] + half_size) / (2 * half_size)
    scene = mbao.Mesh(vertices, indices, texcoords=texcoords)
    settings = dict(SETTINGS, target="texture", resolution=32, texcoord=texcoord)
    here = mbao.bake(scene, **settings)
    there = mbao.bake(scene, client=dask_client, **settings)
    assert here.textures.keys() == there.textures.keys()
    for index, texture in here.textures.items():
        np.testing.assert_array_equal(there.textures[index].image, texture.image)
        np.testing.assert_array_equal(there.textures[index].standard_error, texture.standard_error)


def test_a_worker_builds_each_texture_bakes_layout_once():
    """Every part of a texture bake that a worker traces walks the layout the
    first part built from the bake's recipe; the layout goes with the recipe."""
    bake = importlib.import_module("mbao.bake")
    floor, floor_indices = plane(1.0, divisions=4)
    texcoords = (np.asarray(floor)[:, [0, 2]] + 1.0) / 2.0
    mesh = mbao.Mesh(floor, floor_indices, texcoords=texcoords)
    scene = as_scene(mesh)
    material = bake._texture_materials(mesh, bake._baked_triangles(mesh, None), 0, None)[0]

    def recipe():
        return bake._TexelRecipe(material.texcoords, material.triangles, 16, 16, material.wrap)

    this_bake, next_bake = recipe(), recipe()
    layout = bake._layout_on_worker(scene, this_bake)
    assert layout.covered_count == 16 * 16
    assert bake._layout_on_worker(scene, this_bake) is layout
    assert bake._layout_on_worker(scene, next_bake) is not layout
    del this_bake, next_bake, layout
    gc.collect()
    assert len(bake._layouts_on_worker) == 0
