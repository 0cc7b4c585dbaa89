"""What mbao.render refuses, and what it takes that looks extreme: each bad
argument is refused by name with its allowed range, scenes and cameras may be
paths, devices are named by index or name, and seeds, radii and bounce counts
take their whole ranges."""

import math
import pathlib

import numpy as np
import pytest

import mbao
from conftest import shared_scene
from meshes import box


@pytest.fixture(scope="module")
def cornell():
    return mbao.cornell_box()


# (arguments, exception, regular expression the message must match)
BAD_ARGUMENTS = [
    (dict(width=0), ValueError, r"width.*\[1, 16384\]"),
    (dict(width=20000), ValueError, r"width.*\[1, 16384\]"),
    (dict(width=2.5), TypeError, r"width"),
    (dict(width=True), TypeError, r"width"),
    (dict(height=0), ValueError, r"height.*\[1, 16384\]"),
    (dict(height=20000), ValueError, r"height.*\[1, 16384\]"),
    (dict(height=2.5), TypeError, r"height"),
    (dict(height=True), TypeError, r"height"),
    (dict(bounces=0), ValueError, r"bounces.*\[1, 16\]"),
    (dict(bounces=17), ValueError, r"bounces.*\[1, 16\]"),
    (dict(samples=0), ValueError, r"samples.*\[1, "),
    (dict(spp=0), ValueError, r"spp.*\[1, "),
    (dict(rho=-0.1), ValueError, r"rho.*\[0, 1\]"),
    (dict(rho=1.5), ValueError, r"rho.*\[0, 1\]"),
    (dict(rho=math.nan), ValueError, r"rho.*\[0, 1\]"),
    (dict(rho="1"), TypeError, r"rho"),
    (dict(max_distance=0), ValueError, r"max_distance.*> ?0"),
    (dict(max_distance=-1), ValueError, r"max_distance.*> ?0"),
    (dict(max_distance=math.nan), ValueError, r"max_distance.*> ?0"),
    (dict(estimator="foo"), ValueError, r"estimator.*branching.*path"),
    (dict(estimator=3), TypeError, r"estimator"),
    (dict(normals="smooth"), ValueError, r"normals.*shading.*geometric"),
    (dict(engine=dict(traversal="kd")), ValueError, r"traversal.*auto.*pushdown.*restart.*short-stack.*stack.*lanes"),
    (dict(engine=dict(organisation="queue")), ValueError, r"organisation.*megakernel.*wavefront"),
    (dict(engine=dict(organisation="wavefront"), estimator="path"), ValueError, r"wavefront.*branching.*path"),
    (
        dict(engine=dict(traversal="lanes", organisation="megakernel")),
        ValueError,
        r"lanes.*wavefront.*not \"megakernel\"",
    ),
    (dict(engine=dict(traversal="lanes"), estimator="path"), ValueError, r"lanes.*branching estimator only"),
    (dict(engine=dict(traversal_stats=1)), TypeError, r"traversal_stats"),
    (dict(seed=-1), ValueError, r"seed.*(2\*\*64|2\^64)"),
    (dict(seed=2**64), ValueError, r"seed.*(2\*\*64|2\^64)"),
    (dict(seed=1.5), TypeError, r"seed"),
    (dict(camera=5), TypeError, r"camera"),
    (dict(engine=dict(tile_pixels=0)), ValueError, r"tile_pixels"),
    (dict(engine=dict(work_group_size=0)), ValueError, r"work_group_size"),
    (dict(engine="stack"), TypeError, r"engine.*mbao.Engine"),
    (dict(traversl="stack"), TypeError, r"traversl.*width.*engine=mbao.Engine"),
    (dict(device=1.5), TypeError, r"device"),
]


@pytest.mark.parametrize(
    "arguments, error, message",
    BAD_ARGUMENTS,
    ids=[",".join(f"{k}={v!r}" for k, v in a.items()) for (a, _, _) in BAD_ARGUMENTS],
)
def test_bad_argument_is_refused_by_name(cornell, arguments, error, message):
    settings = dict(width=1, height=1)
    settings.update(arguments)
    with pytest.raises(error, match=message):
        if isinstance(settings.get("engine"), dict):
            settings["engine"] = mbao.Engine(**settings["engine"])
        mbao.render(cornell, **settings)


def test_scene_must_be_a_scene_or_a_path():
    vertices, indices = box((0, 0, 0), (1, 1, 1))
    with pytest.raises(TypeError, match="scene.*path"):
        mbao.render(vertices, width=1, height=1)
    with pytest.raises(mbao.LoadError, match="no_such_scene.glb"):
        mbao.render("no_such_scene.glb", width=1, height=1)
    with pytest.raises(mbao.LoadError, match="no_such_camera.json"):
        mbao.render(mbao.cornell_box(), camera="no_such_camera.json", width=1, height=1)


@pytest.mark.parametrize("as_path", [str, pathlib.Path])
def test_paths_are_taken_where_a_scene_or_a_camera_is(as_path):
    folder = shared_scene("cornell_box")
    scene, camera = mbao.load(folder / "scene.glb"), mbao.Camera.load(str(folder / "camera.json"))
    settings = dict(width=12, height=10, bounces=2, seed=5)
    expected = mbao.render(scene, camera=camera, **settings)
    by_path = mbao.render(as_path(folder / "scene.glb"), camera=as_path(folder / "camera.json"), **settings)
    np.testing.assert_array_equal(by_path.ao, expected.ao)
    reference = mbao.reference(
        as_path(folder / "scene.glb"),
        camera=as_path(folder / "camera.json"),
        width=6,
        height=5,
        target_error=1.0,
        min_passes=2,
        samples=4,
        progress=False,
    )
    assert reference.settings["scene"] == scene.name and reference.ao.shape == (5, 6)
    rows = mbao.convergence(
        as_path(folder / "scene.glb"), ["b1"], reference, sample_counts=(1,), progress=False, plot=False
    )
    assert len(rows) == 1
    t, triangle, _ = mbao.trace(as_path(folder / "scene.glb"), [camera.eye], [np.subtract(camera.target, camera.eye)])
    np.testing.assert_array_equal(
        triangle, mbao.trace(scene, [camera.eye], [np.subtract(camera.target, camera.eye)])[1]
    )


def test_bad_device_index_lists_the_devices(cornell, device):
    with pytest.raises(ValueError, match="device") as info:
        mbao.render(cornell, width=1, height=1, device=99)
    assert "99" in str(info.value) and device.name in str(info.value)


def test_unknown_device_name_lists_the_devices(cornell, device):
    with pytest.raises(ValueError, match="device") as info:
        mbao.render(cornell, width=1, height=1, device="no-such-gpu")
    assert "no-such-gpu" in str(info.value) and device.name in str(info.value)


def test_more_than_16_bounces_are_fine_with_the_path_estimator(cornell):
    result = mbao.render(cornell, width=1, height=1, bounces=17, estimator="path")
    assert result.ao.shape == (1, 1)


def test_infinite_max_distance_is_fine(cornell):
    result = mbao.render(cornell, width=2, height=2, max_distance=math.inf)
    assert result.ao.shape == (2, 2)


@pytest.mark.parametrize("seed", [0, 2**32, 2**63, 2**64 - 1, np.uint64(2**64 - 1)])
def test_seed_takes_any_value_in_0_to_2_pow_64(cornell, seed):
    result = mbao.render(cornell, width=1, height=1, seed=seed)
    assert result.ao.shape == (1, 1)


def test_exploding_branching_work_points_to_the_path_estimator(cornell):
    with pytest.raises(ValueError, match="path"):
        mbao.render(cornell, width=1, height=1, samples=64, bounces=6)
