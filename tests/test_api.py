"""The Python API's contract: what mbao.render and mbao.trace accept, return
and refuse, and the GIL they release (their settings' one definition:
test_settings_tables.py; mbao.Mesh and mbao.Camera: test_mesh_and_camera.py;
mbao.devices and mbao.save_image: test_devices_and_images.py).

Each test states one promise of the public API (python/mbao, docs/spec.md). Renders
are tiny (a few dozen pixels) unless a test needs real work to measure.
"""

import json
import math
import os
import pathlib
import subprocess
import sys
import textwrap
import threading
import warnings
import time

import numpy as np
import pytest

import mbao
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
