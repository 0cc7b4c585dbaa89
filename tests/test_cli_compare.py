"""`python -m mbao compare`: the seed paper's Figure 2 and the study of error against frame time, here
and on a Dask cluster."""

import csv
import json

import pytest

import mbao
from command_line import output_lines, read_image, run_mbao, write_box_scene


@pytest.fixture(scope="module")
def gltf_scene(tmp_path_factory):
    return write_box_scene(tmp_path_factory.mktemp("cli_scene"))


def test_compare_writes_figure_2_the_error_plot_and_its_table(tmp_path, gltf_scene):
    scene, camera, _ = gltf_scene
    proc = run_mbao("compare", scene, "--camera", camera, "--width", 16, "--height", 12, "--max-distance", 1.0,
                    "--target-error", 0.05, "--sample-counts", 1, 2, "--quiet", "-o", "study", cwd=tmp_path)  # fmt: skip
    assert proc.returncode == 0, proc.stderr
    assert output_lines(proc.stdout)["radius"] == "1 (--max-distance)"
    for name in ("study_figure2.png", "study_error_vs_time.png"):
        spec, _ = read_image(tmp_path / name)
        assert spec.width > 400 and spec.height > 100
    lines = (tmp_path / "study_error_vs_time.csv").read_text().splitlines()
    assert lines[0] == "method,cost,frame_ms,rmse,bias,block_rmse,noise_floor"
    methods = [line.split(",")[0] for line in lines[1:]]
    assert methods == [
        m for m in ("hbao", "b1", "b2 branching", "b2 path", "b1 + gtao fit", "hbao + gtao fit") for _ in (1, 2)
    ] + [
        "b2 branching + denoise"
    ]  # from r = 2 only


def test_compare_on_a_dask_scheduler_has_the_local_errors(tmp_path, gltf_scene, dask_client):
    scene, camera, _ = gltf_scene
    common = [
        "compare",
        scene,
        "--camera",
        camera,
        "--width",
        16,
        "--height",
        12,
        "--max-distance",
        1.0,
        "--target-error",
        0.05,
        "--sample-counts",
        1,
        2,
        "--quiet",
    ]
    tables = {}
    for name, extra in (("here", []), ("cluster", ["--scheduler", dask_client.scheduler.address])):
        proc = run_mbao(*common, "-o", name, *extra, cwd=tmp_path)
        assert proc.returncode == 0, proc.stderr
        rows = list(csv.DictReader((tmp_path / f"{name}_error_vs_time.csv").open()))
        tables[name] = [{k: v for k, v in row.items() if k != "frame_ms"} for row in rows]
    assert tables["cluster"] == tables["here"]


def test_compare_names_a_scheduler_it_cannot_reach(tmp_path):
    proc = run_mbao("compare", "--width", 8, "--height", 8, "--quiet", "--scheduler", "tcp://127.0.0.1:9", cwd=tmp_path)
    assert proc.returncode == 2
    assert "--scheduler tcp://127.0.0.1:9: cannot reach a Dask scheduler there" in proc.stderr


def test_compares_figures_name_the_scene_and_keep_their_panels_one_size():
    import matplotlib

    matplotlib.use("Agg")
    from mbao import compare

    class Named:
        def __init__(self, name):
            self.name = name

    assert compare.short_name(Named("../shared/scenes/sibenik/scene.glb")) == "sibenik"
    assert compare.short_name(Named("/data/bunny.ply.glb")) == "bunny.ply"
    assert compare.short_name(Named("cornell_box")) == "cornell_box"
    figure = compare.figure2(
        mbao.cornell_box(), None, 0.5, width=16, height=12, samples=2, rho=1.0, seed=0, device=None
    )
    panels = figure.axes[:4]
    widths = {round(ax.get_position().width, 6) for ax in panels}
    heights = {round(ax.get_position().height, 6) for ax in panels}
    assert len(widths) == 1 and len(heights) == 1, (widths, heights)
    assert figure._suptitle.get_text().startswith("cornell_box, 16x12")


def test_compare_takes_the_radius_from_camera_json(tmp_path, gltf_scene):
    scene, camera, _ = gltf_scene
    with_radius = tmp_path / "camera.json"
    with_radius.write_text(json.dumps({**json.loads(camera.read_text()), "max_distance": 0.7}))
    proc = run_mbao("compare", scene, "--camera", with_radius, "--width", 8, "--height", 8, "--target-error", 0.2,
                    "--sample-counts", 1, "--quiet", cwd=tmp_path)  # fmt: skip
    assert proc.returncode == 0, proc.stderr
    assert output_lines(proc.stdout)["radius"] == "0.7 (camera.json)"
