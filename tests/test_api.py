"""The Python API's contract: what mbao.render and mbao.trace accept, return
and refuse, the one definition of their settings, and the GIL they release
(mbao.Mesh and mbao.Camera: test_mesh_and_camera.py; mbao.devices and
mbao.save_image: test_devices_and_images.py).

Each test states one promise of the public API (python/mbao, docs/spec.md). Renders
are tiny (a few dozen pixels) unless a test needs real work to measure.
"""

import inspect
import json
import math
import os
import pathlib
import pickle
import re
import subprocess
import sys
import textwrap
import threading
import warnings
import time

import numpy as np
import pytest

import mbao
from conftest import shared_scene
from meshes import box, merge, plane

STATS_KEYS = {
    "build_ms",
    "tree_reused",
    "kernel_build_ms",
    "kernel_cache",
    "kernel_options",
    "traversal_mode",
    "organisation",
    "plan",
    "upload_ms",
    "frame_ms",
    "rays_primary",
    "rays_secondary",
    "memory_bytes",
    "tiles",
    "device",
    "tree",
}
TREE_KEYS = {
    "nodes",
    "leaves",
    "empty_leaves",
    "max_depth",
    "mean_triangles_per_leaf",
    "leaf_references",
    "degenerate_triangles",
    "sah_cost",
    "build_ms",
    "memory_bytes",
}

# The package directory's parent, so that subprocesses import this same mbao.
PACKAGE_ROOT = str(pathlib.Path(mbao.__file__).resolve().parents[1])


def small_scene():
    """A box standing on a floor: a Mesh with no camera of its own."""
    return mbao.Mesh(*merge(plane(2.0), box((-0.5, 0.0, -0.5), (0.5, 1.0, 0.5))))


def run_python(code, timeout=120):
    """Runs `code` in a fresh interpreter (for calls that might crash the process)."""
    env = dict(os.environ, PYTHONPATH=PACKAGE_ROOT + os.pathsep + os.environ.get("PYTHONPATH", ""))
    return subprocess.run(
        [sys.executable, "-X", "faulthandler", "-c", textwrap.dedent(code)],
        capture_output=True,
        text=True,
        timeout=timeout,
        env=env,
    )


@pytest.fixture(scope="module")
def cornell():
    return mbao.cornell_box()


# -- render: defaults, result, stats ---------------------------------------------


def check_result(result, width, height, spp=1):
    assert isinstance(result, mbao.Result)
    assert result.ao.dtype == np.float32 and result.ao.shape == (height, width)
    assert result.mask.dtype == np.bool_ and result.mask.shape == (height, width)
    assert np.all(np.isfinite(result.ao))
    assert result.ao.min() >= 0.0 and result.ao.max() <= 1.0
    # SPEC 2: a camera sample that misses everything gives 1.0.
    assert np.all(result.ao[~result.mask] == 1.0)
    stats = result.stats
    assert STATS_KEYS <= set(stats), STATS_KEYS - set(stats)
    assert TREE_KEYS <= set(stats["tree"]), TREE_KEYS - set(stats["tree"])
    assert stats["rays_primary"] == width * height * spp
    for key in ("build_ms", "kernel_build_ms", "upload_ms", "frame_ms"):
        assert isinstance(stats[key], float) and stats[key] >= 0.0, key
    assert stats["frame_ms"] > 0.0
    assert isinstance(stats["rays_secondary"], int) and stats["rays_secondary"] >= 0
    assert isinstance(stats["memory_bytes"], int) and stats["memory_bytes"] > 0
    assert isinstance(stats["tiles"], int) and stats["tiles"] >= 1
    assert isinstance(stats["tree_reused"], bool) and stats["kernel_cache"] in ("memory", "disk", "compiled")
    assert isinstance(stats["device"], str) and stats["device"]


def test_render_cornell_box_with_defaults(cornell):
    result = mbao.render(cornell, width=32, height=32)
    check_result(result, 32, 32)
    assert result.mask.any() and (result.ao < 1.0).any()
    # Defaults: 1 bounce, 4 samples, branching: at most 4 secondary rays per primary hit.
    assert 0 < result.stats["rays_secondary"] <= 4 * result.mask.sum()


def test_render_non_square_with_spp(cornell):
    result = mbao.render(cornell, width=12, height=7, spp=3)
    check_result(result, 12, 7, spp=3)


def test_render_mesh_without_camera_frames_the_scene():
    scene = small_scene()
    assert scene.camera is None
    result = mbao.render(scene, width=32, height=32)
    check_result(result, 32, 32)
    # The framing camera looks at the centre of the bounds and sees all of them.
    assert result.mask[16, 16]
    border = np.concatenate([result.mask[0], result.mask[-1], result.mask[:, 0], result.mask[:, -1]])
    assert not border.any()
    assert (result.ao[result.mask] < 1.0).any()


def test_camera_none_means_the_scenes_own_camera(cornell):
    assert isinstance(cornell.camera, mbao.Camera)
    default = mbao.render(cornell, width=32, height=32, seed=5)
    explicit = mbao.render(cornell, camera=cornell.camera, width=32, height=32, seed=5)
    np.testing.assert_array_equal(default.ao, explicit.ao)
    np.testing.assert_array_equal(default.mask, explicit.mask)


def test_explicit_camera_is_used(cornell):
    c = cornell.camera
    away = mbao.Camera(c.eye, (c.eye[0], c.eye[1], c.eye[2] - 100.0), c.up, c.vfov_deg)  # looks out of the box
    result = mbao.render(cornell, camera=away, width=16, height=16)
    assert not result.mask.any()
    assert np.all(result.ao == 1.0)
    assert result.stats["rays_secondary"] == 0


def test_result_repr_names_size_and_device(cornell):
    result = mbao.render(cornell, width=8, height=6)
    assert "8x6" in repr(result) and result.stats["device"] in repr(result)


# -- scenes are built once ---------------------------------------------------------


def test_second_render_reuses_the_tree():
    scene = small_scene()
    first = mbao.render(scene, width=8, height=8)
    second = mbao.render(scene, width=8, height=8)
    assert first.stats["tree_reused"] is False
    assert second.stats["tree_reused"] is True
    assert second.stats["tree"] == first.stats["tree"]
    assert scene.kd_tree()["stats"] == first.stats["tree"]


def test_build_returns_the_tree_stats():
    # In a subprocess: a crash in Scene.build must fail this test, not kill the test run.
    proc = run_python(
        """
        import json, mbao
        scene = mbao.cornell_box()
        stats = scene.build()
        again = scene.build()
        result = mbao.render(scene, width=4, height=4)
        print(json.dumps({"stats": stats, "again": again, "reused": result.stats["tree_reused"],
                          "render_tree": result.stats["tree"]}))
        """
    )
    how = f"signal {-proc.returncode}" if proc.returncode < 0 else f"exit code {proc.returncode}"
    assert proc.returncode == 0, f"scene.build() crashed ({how}):\n{proc.stderr[-2000:]}"
    out = json.loads(proc.stdout.strip().splitlines()[-1])
    assert isinstance(out["stats"], dict) and TREE_KEYS <= set(out["stats"])
    assert out["stats"]["nodes"] >= 1 and out["stats"]["leaves"] >= 1
    assert out["again"] == out["stats"]  # built once, not rebuilt
    assert out["reused"] is True  # a render after build() reuses the tree
    assert out["render_tree"] == out["stats"]


def test_kd_tree_arrays(cornell):
    tree = cornell.kd_tree()
    assert {"nodes", "node_rows", "bounds", "origin", "stats"} <= set(tree)
    nodes, rows = tree["nodes"], tree["node_rows"]
    assert nodes.dtype == np.uint32 and nodes.ndim == 2 and nodes.shape[1] == 2
    assert len(rows) == tree["stats"]["nodes"] >= 1 and rows[0] == 0
    assert len(nodes) * 8 == tree["stats"]["memory_bytes"]
    leaves = rows[(nodes[rows, 0] & 3) == 3]
    counts, firsts = nodes[leaves, 0] >> 2, nodes[leaves, 1]
    assert np.all(firsts == 2 * (leaves + 1))  # each leaf's entries follow it
    words = nodes.ravel()
    entries = np.concatenate([words[first : first + count] for first, count in zip(firsts, counts)])
    assert len(entries) == tree["stats"]["leaf_references"]
    assert entries.max() < cornell.triangle_count  # no masks: no flags
    # Every triangle is in some leaf.
    assert set(entries.tolist()) == set(range(cornell.triangle_count))
    origin = np.asarray(tree["origin"])
    lo, hi = (np.asarray(corner) + origin for corner in tree["bounds"])
    scene_lo, scene_hi = (np.asarray(corner) for corner in cornell.bounds)
    assert np.all(lo <= scene_lo) and np.all(hi >= scene_hi)


# -- argument checking ---------------------------------------------------------------

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


# -- one definition of the settings --------------------------------------------------------

ENGINE_KNOBS = ("traversal", "organisation", "tile_pixels", "work_group_size", "traversal_stats")


def test_render_lists_the_users_settings_with_the_tables_defaults():
    parameters = inspect.signature(mbao.render).parameters
    specs = {spec["name"]: spec for spec in mbao._core.setting_specs()}
    assert not set(ENGINE_KNOBS) & set(parameters), "engine settings belong in engine=mbao.Engine(...)"
    for name, spec in specs.items():
        if spec["group"] == "render":
            assert parameters[name].default == spec["default"], name
            assert f"{name}: {spec['doc'].split()[0]}" in mbao.render.__doc__, f"{name} is not documented"
        else:
            assert getattr(mbao.Engine(), name) == spec["default"], name
            assert f"{name}: " in mbao.Engine.__doc__, f"{name} is not documented"
    assert {"camera", "hbao", "engine", "device", "progress"} <= set(parameters)


def test_the_defaults_are_the_cores(cornell):
    """A render with no settings and one with every default spelt out are the same render."""
    specs = mbao._core.setting_specs()
    spelt_out = {spec["name"]: spec["default"] for spec in specs if spec["group"] == "render"}
    spelt_out.update(width=6, height=5, seed=4)
    engine = mbao.Engine(**{spec["name"]: spec["default"] for spec in specs if spec["group"] == "engine"})
    a = mbao.render(cornell, engine=engine, **spelt_out)
    b = mbao.render(cornell, width=6, height=5, seed=4)
    np.testing.assert_array_equal(a.ao, b.ao)
    assert a.stats["kernel_options"] == b.stats["kernel_options"]


@pytest.mark.parametrize("cls", [mbao.HBAO, mbao.Denoise, mbao.Temporal])
def test_the_cores_settings_classes_have_real_signatures_whose_defaults_they_take(cls):
    """inspect.signature (help(), IDEs, notebooks' completion) reads a core class
    as it is called; each default is what the constructor gives."""
    parameters = inspect.signature(cls).parameters
    made = cls()
    assert parameters and all(getattr(made, name) == p.default for name, p in parameters.items())


@pytest.mark.parametrize("cls, table", [(mbao.HBAO, "hbao"), (mbao.Denoise, "denoise"), (mbao.Temporal, "temporal")])
def test_the_cores_settings_classes_are_their_tables(cls, table):
    """One table per class (cpp/render/setting_specs.h) names its parameters in
    order, gives their defaults, documents each, and makes its repr and pickle."""
    specs = mbao._core.setting_specs(table)
    parameters = inspect.signature(cls).parameters
    assert list(parameters) == [spec["name"] for spec in specs]
    assert [p.default for p in parameters.values()] == pytest.approx([spec["default"] for spec in specs])
    for spec in specs:
        assert f"{spec['name']}: {spec['doc']}" in cls.__doc__ and f"allowed {spec['range']}." in cls.__doc__
    made = cls(**{spec["name"]: spec["hi"] if spec["kind"] == "integer" else spec["lo"] + 0.5 for spec in specs})
    again = eval("mbao." + repr(made))
    assert pickle.loads(pickle.dumps(made)) is not made
    assert [getattr(again, s["name"]) for s in specs] == [getattr(made, s["name"]) for s in specs]
    assert [getattr(pickle.loads(pickle.dumps(made)), s["name"]) for s in specs] == [
        getattr(made, s["name"]) for s in specs
    ]


@pytest.mark.parametrize("table", ["render", "hbao", "bake", "denoise", "temporal"])
def test_the_spec_shows_each_settings_table_as_the_core_has_it(table):
    """docs/spec.md's tables of a render's (3.5), HBAO's (4), the bake's own
    (6), the denoiser's (7.3) and temporal accumulation's (7.4) settings are
    mbao.settings.markdown_table's, which prints the one to paste where they
    differ."""
    spec = (pathlib.Path(__file__).resolve().parents[1] / "docs" / "spec.md").read_text()
    assert mbao.settings.markdown_table(table) in spec, mbao.settings.markdown_table(table)


def test_a_camera_has_a_real_signature_and_a_repr_that_makes_it_again():
    signature = inspect.signature(mbao.Camera)
    assert list(signature.parameters) == ["eye", "target", "up", "vfov_deg", "max_distance"]
    camera = mbao.Camera((0.0, 1.0, 5.0), (0.0, 0.0, 0.0))
    assert [camera.up, camera.vfov_deg, camera.max_distance] == [
        tuple(signature.parameters["up"].default),
        signature.parameters["vfov_deg"].default,
        None,
    ]
    suggesting = mbao.Camera((0.0, 1.0, 5.0), (0.0, 0.0, 0.0), max_distance=2.5)
    again = eval("mbao." + repr(suggesting))
    assert (again.eye, again.target, again.max_distance) == (suggesting.eye, suggesting.target, 2.5)
    assert "does not use it" not in mbao.Camera.__doc__ and "max_distance_source" in mbao.Camera.__doc__


@pytest.mark.parametrize("cls, maker", [(mbao.Scene, "mbao.load"), (mbao.Device, "mbao.devices()")])
def test_classes_made_elsewhere_say_where_when_called(cls, maker):
    assert not inspect.signature(cls).parameters
    with pytest.raises(TypeError, match=re.escape(maker)):
        cls()


def test_a_mesh_keeps_its_own_signature():
    assert list(inspect.signature(mbao.Mesh).parameters) == ["vertices", "indices", "normals", "texcoords"]


def test_engine_keywords_of_render_still_work_for_one_release(cornell):
    settings = dict(width=8, height=8, bounces=2, seed=3)
    with pytest.warns(DeprecationWarning, match=r"engine=mbao.Engine\(traversal=...\)"):
        old = mbao.render(cornell, traversal="restart", **settings)
    new = mbao.render(cornell, engine=mbao.Engine(traversal="restart"), **settings)
    assert old.stats["traversal_mode"] == new.stats["traversal_mode"] == "restart"
    np.testing.assert_array_equal(old.ao, new.ao)
    with pytest.raises(TypeError, match="beside engine="):
        mbao.render(cornell, engine=mbao.Engine(), traversal="restart", **settings)


def test_an_engine_is_checked_when_it_is_made():
    with pytest.raises(ValueError, match="organisation must be one of"):
        mbao.Engine(organisation="queue")
    assert mbao.Engine(tile_pixels=np.int64(9)).tile_pixels == 9
    assert "traversal='stack'" in repr(mbao.Engine(traversal="stack"))


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


# -- backgrounds (SPEC 2) --------------------------------------------------------------------


def test_coverage_is_the_fraction_of_camera_samples_that_hit():
    """A plane's edge across the image: pixels on it are hit by some of their 16
    jittered camera samples. Coverage is that fraction in 255ths, rounded up;
    the mask is where it is above 0, and the AO of a miss is 1, as an open
    surface's."""
    scene = mbao.Mesh(*plane(1.0))
    camera = mbao.Camera(eye=(0.0, 2.0, 0.0), target=(0.0, 0.0, 0.0), up=(0, 0, 1), vfov_deg=60.0)
    spp = 16
    result = mbao.render(scene, camera=camera, width=24, height=24, spp=spp, seed=3)
    steps = {int(np.ceil(255 * hits / spp)) for hits in range(spp + 1)}
    assert set(np.unique(np.rint(result.coverage * 255)).astype(int)) <= steps
    assert 0 < np.mean((result.coverage > 0) & (result.coverage < 1))  # some pixels on the edge
    np.testing.assert_array_equal(result.mask, result.coverage > 0)
    assert np.all(result.ao[~result.mask] == 1.0) and (~result.mask).any()
    hbao = mbao.render(scene, camera=camera, width=24, height=24, method="hbao")
    np.testing.assert_array_equal(hbao.coverage, hbao.mask.astype(np.float32))


def test_save_image_writes_a_straight_alpha_in_png_and_a_coverage_channel_in_exr(tmp_path):
    import OpenImageIO as oiio

    ao = np.full((3, 4), 0.8, np.float32)
    alpha = np.array([[0.0, 1.0, 0.25, 0.5]] * 3, np.float32)
    mbao.save_image(tmp_path / "a.png", ao, alpha=alpha)
    mbao.save_image(tmp_path / "a.exr", ao, alpha=alpha)
    as_stored = oiio.ImageSpec()
    as_stored.attribute("oiio:UnassociatedAlpha", 1)  # OpenImageIO premultiplies a PNG's values on reading
    png, exr = oiio.ImageBuf(str(tmp_path / "a.png"), 0, 0, as_stored), oiio.ImageBuf(str(tmp_path / "a.exr"))
    assert png.spec().channelnames == ("Y", "A") and exr.spec().channelnames == ("Y", "coverage")
    # Straight: the value under a transparent pixel is kept, not multiplied by its alpha.
    np.testing.assert_allclose(png.get_pixels(oiio.FLOAT)[..., 0], np.rint(0.8 * 255) / 255, rtol=0, atol=1e-6)
    np.testing.assert_allclose(png.get_pixels(oiio.FLOAT)[..., 1], np.rint(alpha * 255) / 255, atol=1e-6)
    np.testing.assert_array_equal(exr.get_pixels(oiio.FLOAT)[..., 1], alpha)
    with pytest.raises(ValueError, match=r"alpha must have the image's shape \(3, 4\)"):
        mbao.save_image(tmp_path / "b.png", ao, alpha=alpha[:2])
    with pytest.raises(ValueError, match=r"alpha must be in \[0, 1\]"):
        mbao.save_image(tmp_path / "b.png", ao, alpha=alpha * 2)


# -- the radius (SPEC 1) --------------------------------------------------------------------


def test_the_radius_is_the_one_given_else_the_cameras_else_unlimited(cornell):
    camera = mbao.Camera(eye=(0, 1, 3.5), target=(0, 1, 0), max_distance=0.5)
    settings = dict(width=8, height=8, seed=2)
    given = mbao.render(cornell, camera=camera, max_distance=0.25, **settings)
    assert (given.stats["max_distance"], given.stats["max_distance_source"]) == (0.25, "settings")
    suggested = mbao.render(cornell, camera=camera, **settings)
    assert (suggested.stats["max_distance"], suggested.stats["max_distance_source"]) == (0.5, "camera")
    np.testing.assert_array_equal(suggested.ao, mbao.render(cornell, camera=camera, max_distance=0.5, **settings).ao)
    unlimited = mbao.render(cornell, camera=camera, max_distance=math.inf, **settings)
    assert unlimited.stats["max_distance_source"] == "settings" and math.isinf(unlimited.stats["max_distance"])
    none = mbao.render(cornell, **settings)  # the Cornell box's own camera suggests none
    assert none.stats["max_distance_source"] == "none" and math.isinf(none.stats["max_distance"])


def test_hbao_without_a_radius_takes_a_quarter_of_the_scenes_diagonal(cornell):
    result = mbao.render(cornell, method="hbao", width=8, height=8)
    lo, hi = (np.asarray(corner) for corner in cornell.bounds)
    assert result.stats["max_distance_source"] == "scene"
    assert result.stats["max_distance"] == pytest.approx(0.25 * np.linalg.norm(hi - lo), rel=1e-6)
    with pytest.raises(ValueError, match="finite max_distance"):
        mbao.render(cornell, method="hbao", width=8, height=8, max_distance=math.inf)


def test_a_closed_scene_with_an_unlimited_radius_is_warned_about_and_an_open_one_is_not(cornell):
    inside = mbao.Camera(eye=(0.5, 0.5, 0.5), target=(1.0, 0.6, 0.2), vfov_deg=90.0)
    closed = mbao.Mesh(*box((0, 0, 0), (1, 1, 1)))
    with pytest.warns(UserWarning, match=r"mesh: 100% of the covered pixels.*looks closed.*max_distance"):
        mbao.render(closed, camera=inside, width=16, height=16)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        mbao.render(closed, camera=inside, width=16, height=16, max_distance=0.3)  # a radius: no warning
        mbao.render(closed, camera=inside, width=8, height=8)  # too few pixels to tell
        mbao.render(cornell, width=16, height=16)  # open at the front


# -- the GIL ------------------------------------------------------------------------------


def test_render_releases_the_gil(cornell):
    settings = dict(width=128, height=128, bounces=2, samples=8)
    mbao.render(cornell, **{**settings, "width": 4, "height": 4})  # kernels built before timing
    window = {}

    def render_in_background():
        window["start"] = time.perf_counter()
        window["result"] = mbao.render(cornell, **settings)
        window["end"] = time.perf_counter()

    worker = threading.Thread(target=render_in_background)
    ticks = []
    worker.start()
    while worker.is_alive():
        ticks.append(time.perf_counter())  # pure Python work in the main thread
    worker.join()
    assert window["result"].ao.shape == (128, 128)
    start, end = window["start"], window["end"]
    duration = end - start
    assert duration > 0.02, "the render was too quick to tell"
    during = np.array([t for t in ticks if start <= t <= end])
    # The main thread kept running while the render ran...
    assert len(during) > 1000, f"main thread counted {len(during)} in {duration * 1e3:.0f} ms of rendering"
    # ... throughout, not only before the render took the GIL or after it gave it back.
    gaps = np.diff(np.concatenate([[start], during, [end]]))
    assert gaps.max() < 0.5 * duration, f"main thread stalled {gaps.max() * 1e3:.0f} of {duration * 1e3:.0f} ms"


def test_trace_checks_its_arguments(cornell):
    origins, directions = np.zeros((3, 3)), np.ones((3, 3))
    for t_max in (0.0, -1.0, np.nan, [1.0, 2.0], "far"):
        with pytest.raises(ValueError, match="t_max"):
            mbao.trace(cornell, origins, directions, t_max=t_max)
    with pytest.raises(ValueError, match="origins"):
        mbao.trace(cornell, origins[:2], directions)
    with pytest.raises(TypeError, match="any_hit"):
        mbao.trace(cornell, origins, directions, any_hit=1)
