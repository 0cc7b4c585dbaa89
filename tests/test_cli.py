"""`python -m mbao`: the command line, run as a user would, in a subprocess."""

import json
import csv
import os
import pathlib
import re
import subprocess
import sys

import numpy as np
import pytest

import mbao
from gltf_writer import GltfBuilder
from meshes import box, merge, plane

# The package directory's parent, so that the subprocess runs this same mbao.
PACKAGE_ROOT = str(pathlib.Path(mbao.__file__).resolve().parents[1])


def run_mbao(*args, cwd):
    env = dict(os.environ, PYTHONPATH=PACKAGE_ROOT + os.pathsep + os.environ.get("PYTHONPATH", ""))
    return subprocess.run(
        [sys.executable, "-m", "mbao", *map(str, args)], capture_output=True, text=True, timeout=120, cwd=cwd, env=env
    )


def read_image(path):
    import OpenImageIO as oiio

    image = oiio.ImageBuf(str(path))
    assert not image.has_error, image.geterror()
    return image.spec(), image.get_pixels(oiio.FLOAT)


def output_lines(stdout):
    """The report, as {first word: rest of the line}."""
    lines = {}
    for line in stdout.splitlines():
        if line.strip():
            key, _, rest = line.partition(" ")
            lines[key] = rest.strip()
    return lines


@pytest.fixture(scope="module")
def gltf_scene(tmp_path_factory):
    """A box on a floor as a .gltf file, and a camera.json looking at it."""
    folder = tmp_path_factory.mktemp("cli_scene")
    vertices, indices = merge(plane(2.0), box((-0.5, 0.0, -0.5), (0.5, 1.0, 0.5)))
    b = GltfBuilder()
    mesh = b.add_mesh([b.primitive(vertices, indices)])
    b.add_scene([b.add_node(mesh=mesh)], default=True)
    scene = b.write(folder / "scene.gltf")
    camera = folder / "camera.json"
    camera.write_text(json.dumps({"eye": [2.0, 2.5, 3.0], "target": [0, 0.3, 0], "up": [0, 1, 0], "vfov_deg": 40}))
    away = folder / "away.json"  # looks up into the empty sky
    away.write_text(json.dumps({"eye": [0, 3, 0], "target": [0, 10, 0], "up": [0, 0, 1], "vfov_deg": 30}))
    return scene, camera, away


def test_render_cornell_box_to_png(tmp_path, device):
    proc = run_mbao("render", "--width", 32, "--height", 24, "--bounces", 2, "-o", "out.png", cwd=tmp_path)
    assert proc.returncode == 0, proc.stderr
    spec, pixels = read_image(tmp_path / "out.png")
    assert (spec.width, spec.height, spec.nchannels) == (32, 24, 2) and spec.channelnames == ("Y", "A")
    assert spec.format == "uint8"
    ao = pixels[..., 0]
    assert (ao < 1.0).any() and (ao > 0.0).any()  # the box, with some occlusion
    # The alpha is the mask: one camera sample per pixel.
    expected = mbao.render(mbao.cornell_box(), width=32, height=24, bounces=2)
    np.testing.assert_array_equal(pixels[..., 1], expected.mask.astype(np.float32))
    assert not expected.mask.all()  # the box's open front shows background
    report = output_lines(proc.stdout)
    for key in ("scene", "device", "settings", "kd-tree", "kernels", "frame", "rays", "memory", "wrote"):
        assert key in report, f"no {key!r} line in:\n{proc.stdout}"
    assert report["scene"].startswith("cornell_box")
    assert device.name in report["device"]
    assert "32x24" in report["settings"] and "bounces=2" in report["settings"]
    assert re.search(r"\d+ nodes", report["kd-tree"])
    assert re.match(r"[\d.]+ ms", report["frame"])
    assert re.match(rf"{32 * 24} primary \+ [1-9]\d* secondary", report["rays"])
    assert "out.png" in report["wrote"]
    assert proc.stderr == ""


def test_render_denoised_with_its_variance_beside(tmp_path):
    """--denoise filters the image (SPEC 7.3); --variance writes each pixel's
    variance, here the filtered one, as float EXR beside it."""
    proc = run_mbao(
        "render",
        "--width",
        32,
        "--height",
        24,
        "--bounces",
        2,
        "--denoise",
        "--variance",
        "-o",
        "out.png",
        cwd=tmp_path,
    )
    assert proc.returncode == 0, proc.stderr
    report = output_lines(proc.stdout)
    assert re.search(r"[\d.]+ ms of it denoising", report["frame"])
    spec, variance = read_image(tmp_path / "out.variance.exr")
    assert (spec.width, spec.height, spec.nchannels) == (32, 24, 1) and spec.format == "float"
    expected = mbao.render(mbao.cornell_box(), width=32, height=24, bounces=2, denoise=True, variance=True)
    np.testing.assert_array_equal(variance[..., 0], expected.variance)
    assert (expected.variance > 0).any()


def test_render_gltf_with_camera_to_exr(tmp_path, gltf_scene):
    scene, camera, away = gltf_scene
    proc = run_mbao("render", scene, "--camera", camera, "--width", 20, "--height", 16, "-o", "out.exr", cwd=tmp_path)
    assert proc.returncode == 0, proc.stderr
    spec, pixels = read_image(tmp_path / "out.exr")
    assert (spec.width, spec.height, spec.nchannels) == (20, 16, 2) and spec.channelnames == ("Y", "coverage")
    assert spec.format == "float"
    assert pixels.min() >= 0.0 and pixels.max() <= 1.0
    assert pixels[..., 0].min() < 0.9  # the floor by the box is occluded
    assert "(14 triangles)" in output_lines(proc.stdout)["scene"]

    # The camera file is what decides the view: looking away, every pixel is open sky.
    proc = run_mbao("render", scene, "--camera", away, "--width", 20, "--height", 16, "-o", "away.exr", cwd=tmp_path)
    assert proc.returncode == 0, proc.stderr
    _, pixels = read_image(tmp_path / "away.exr")
    assert np.all(pixels[..., 0] == 1.0) and np.all(pixels[..., 1] == 0.0)  # open sky, and no geometry

    proc = run_mbao("render", scene, "--camera", away, "--width", 20, "--height", 16, "--no-alpha", "-o", "ao.png",
                    cwd=tmp_path)  # fmt: skip
    assert proc.returncode == 0, proc.stderr
    assert read_image(tmp_path / "ao.png")[0].nchannels == 1
    assert re.match(r"320 primary \+ 0 secondary", output_lines(proc.stdout)["rays"])


def test_every_render_option_is_accepted(tmp_path, gltf_scene):
    scene, camera, _ = gltf_scene
    proc = run_mbao(
        "render", scene, "--camera", camera, "-o", "ao.exr",
        "--width", 10, "--height", 8, "--bounces", 3, "--samples", 2, "--estimator", "path", "--rho", 0.5,
        "--max-distance", 1.5, "--spp", 2, "--seed", 7, "--normals", "geometric", "--traversal", "restart",
        "--organisation", "megakernel", "--device", 0, "--max-rays", 10**6,
        cwd=tmp_path,
    )  # fmt: skip
    assert proc.returncode == 0, proc.stderr
    settings = output_lines(proc.stdout)["settings"]
    for part in ("10x8", "bounces=3", "samples=2", "path", "rho=0.5", "max_distance=1.5", "spp=2"):
        assert part in settings, f"{part!r} not in {settings!r}"
    assert re.match(rf"{10 * 8 * 2} primary", output_lines(proc.stdout)["rays"])
    assert read_image(tmp_path / "ao.exr")[0].width == 10


def test_help_gives_every_setting_its_default_and_the_engine_options_a_group(tmp_path):
    proc = run_mbao("render", "--help", cwd=tmp_path)
    assert proc.returncode == 0, proc.stderr
    text = " ".join(proc.stdout.split())  # argparse wraps the help at the terminal's width
    render_part, engine_part = text.split("engine options:")
    for spec in mbao._core.setting_specs():
        flag = "--" + spec["name"].replace("_", "-")
        assert flag in (render_part if spec["group"] == "render" else engine_part), flag
    for default in (
        "(default: 512, allowed [1, 16384])",
        "(default: 1, allowed [1, 65536])",
        "(default: 4, allowed [1, 1048576])",
        "(default: 0, allowed [0, 2^64))",
    ):
        assert default in render_part, default


def test_orbit_writes_the_sequence_as_a_looping_gif(tmp_path):
    """Each GIF frame is the sequence's frame in 8-bit greys; frames alike in a
    row may be merged by Pillow, but the loop's length is frames / fps."""
    from PIL import Image, ImageSequence

    proc = run_mbao(
        "orbit",
        "--frames",
        6,
        "--fps",
        20,
        "--width",
        24,
        "--height",
        16,
        "--bounces",
        2,
        "--temporal",
        "-o",
        "turn.gif",
        cwd=tmp_path,
    )
    assert proc.returncode == 0, proc.stderr
    assert output_lines(proc.stdout)["wrote"].startswith("turn.gif")
    gif = Image.open(tmp_path / "turn.gif")
    assert gif.size == (24, 16) and gif.info["loop"] == 0
    frames = [(np.asarray(frame.convert("L")), frame.info["duration"]) for frame in ImageSequence.Iterator(gif)]
    assert sum(duration for _, duration in frames) == 6 * 50
    first = mbao.cornell_box().default_camera(24, 16)
    expected = next(mbao.render_sequence(mbao.cornell_box(), [first], width=24, height=16, bounces=2))
    np.testing.assert_array_equal(frames[0][0], np.round(expected.ao * 255).astype(np.uint8))


def test_orbit_cameras_turn_the_eye_about_the_target():
    from mbao.orbit import orbit_cameras

    start = mbao.Camera((0.0, 1.0, 2.0), (0.0, 1.0, 0.0), vfov_deg=45.0, max_distance=3.0)
    quarter_turns = orbit_cameras(start, 4)
    np.testing.assert_allclose(
        [c.eye for c in quarter_turns], [(0, 1, 2), (2, 1, 0), (0, 1, -2), (-2, 1, 0)], atol=1e-6
    )
    assert all(c.target == start.target and c.vfov_deg == 45.0 and c.max_distance == 3.0 for c in quarter_turns)
    with pytest.raises(ValueError, match="frames must be an integer >= 1"):
        orbit_cameras(start, 0)


def test_version(tmp_path):
    proc = run_mbao("--version", cwd=tmp_path)
    assert proc.returncode == 0 and proc.stdout.strip() == f"mbao {mbao.__version__}"


@pytest.mark.parametrize("command", ["render", "compare", "orbit"])
def test_every_option_with_a_default_says_it_in_help(tmp_path, command):
    from mbao.cli import _parser

    subparser = _parser()._subparsers._group_actions[0].choices[command]
    proc = run_mbao(command, "--help", cwd=tmp_path)
    assert proc.returncode == 0, proc.stderr
    text = " ".join(proc.stdout.split()).split(" options: ", 1)[1]  # past the usage line
    for action in subparser._actions:
        if action.option_strings and action.default not in (None, False, "==SUPPRESS=="):
            entry = text.split(action.option_strings[-1], 1)[1].split(" --", 1)[0]
            assert "default: " in entry, f"{action.option_strings[-1]} has default {action.default!r}: {entry!r}"


def test_an_output_without_a_writer_is_refused_by_its_option_before_rendering(tmp_path):
    proc = run_mbao("render", "--width", 4, "--height", 4, "--bounces", 16, "--samples", 8, "--max-rays", 2**62,
                    "-o", "noext", cwd=tmp_path)  # fmt: skip
    assert proc.returncode == 2
    assert proc.stderr.startswith("mbao: -o 'noext'") and "(none)" in proc.stderr and ".png" in proc.stderr
    assert "rays" not in proc.stdout  # refused before the render, which would take hours


def test_render_says_where_its_radius_came_from(tmp_path, gltf_scene):
    scene, camera, _ = gltf_scene
    suggesting = tmp_path / "suggesting.json"
    suggesting.write_text(json.dumps(dict(json.loads(camera.read_text()), max_distance=0.75)))

    def radius(*args):
        proc = run_mbao("render", *args, "--width", 6, "--height", 5, "-o", "x.exr", cwd=tmp_path)
        assert proc.returncode == 0, proc.stderr
        return re.search(r"max_distance=(.*), spp", output_lines(proc.stdout)["settings"]).group(1)

    assert radius(scene, "--camera", suggesting) == "0.75 (camera.json)"
    assert radius(scene, "--camera", suggesting, "--max-distance", 2) == "2 (--max-distance)"
    assert radius(scene, "--camera", camera) == "inf (no camera suggests one)"


def test_a_closed_scene_is_warned_about_in_one_line(tmp_path):
    b = GltfBuilder()
    b.add_scene([b.add_node(mesh=b.add_mesh([b.primitive(*box((0, 0, 0), (1, 1, 1)))]))], default=True)
    scene = b.write(tmp_path / "closed.gltf")
    inside = tmp_path / "inside.json"
    inside.write_text(json.dumps({"eye": [0.5, 0.5, 0.5], "target": [1.0, 0.6, 0.2], "up": [0, 1, 0], "vfov_deg": 90}))
    proc = run_mbao("render", scene, "--camera", inside, "--width", 16, "--height", 16, "-o", "x.png", cwd=tmp_path)
    assert proc.returncode == 0, proc.stderr
    lines = proc.stderr.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("mbao: warning: ") and "looks closed" in lines[0], proc.stderr
    assert "(--max-distance ...)" in lines[0]


def test_a_bakes_errors_and_warnings_name_flags_not_python_arguments(tmp_path):
    """Mirrored UVs are refused with the flags that bake such a file; generated
    charts packed closer than --padding name the --resolution that keeps it."""
    from meshes import icosphere

    vertices, indices = plane(1.0, divisions=4)
    b = GltfBuilder()
    mirrored = b.primitive(vertices, indices, texcoords=np.abs(vertices[:, [0, 2]]))
    b.add_scene([b.add_node(mesh=b.add_mesh([mirrored]))], default=True)
    refused = run_mbao(
        "bake",
        b.write(tmp_path / "mirrored.glb"),
        "-o",
        "out.glb",
        "--target",
        "texture",
        "--resolution",
        16,
        "--samples",
        2,
        cwd=tmp_path,
    )
    assert refused.returncode == 2 and "(--texcoord generate)" in refused.stderr, refused.stderr
    assert "(--target vertices)" in refused.stderr and "=" not in refused.stderr.split("them;")[1]

    b = GltfBuilder()
    b.add_scene([b.add_node(mesh=b.add_mesh([b.primitive(*icosphere(1.0, subdivisions=2))]))], default=True)
    packed = run_mbao(
        "bake",
        b.write(tmp_path / "sphere.glb"),
        "-o",
        "out.glb",
        "--target",
        "texture",
        "--texcoord",
        "generate",
        "--resolution",
        16,
        "--samples",
        2,
        cwd=tmp_path,
    )
    assert packed.returncode == 0, packed.stderr
    assert re.search(
        r"^mbao: warning: .* not --padding 4, .*; --resolution \d+ keeps them 4 apart$", packed.stderr, re.MULTILINE
    ), packed.stderr


def test_same_settings_give_the_same_image_as_the_api(tmp_path, gltf_scene):
    scene, camera, _ = gltf_scene
    proc = run_mbao("render", scene, "--camera", camera, "--width", 12, "--height", 9, "--seed", 3, "--bounces", 2,
                    "-o", "cli.exr", cwd=tmp_path)  # fmt: skip
    assert proc.returncode == 0, proc.stderr
    expected = mbao.render(mbao.load(scene), camera=mbao.Camera.load(camera), width=12, height=9, seed=3, bounces=2)
    np.testing.assert_array_equal(read_image(tmp_path / "cli.exr")[1][..., 0], expected.ao)


@pytest.mark.parametrize("command", ["render", "orbit"])
def test_camera_frame_renders_from_the_framing_camera(tmp_path, gltf_scene, command):
    scene, _, _ = gltf_scene
    output = "frame.exr" if command == "render" else "frame.gif"
    proc = run_mbao(
        command,
        scene,
        "--camera",
        "frame",
        "--width",
        12,
        "--height",
        9,
        "-o",
        output,
        *(["--frames", 2] if command == "orbit" else []),
        cwd=tmp_path,
    )
    assert proc.returncode == 0, proc.stderr
    if command == "render":
        loaded = mbao.load(scene)
        expected = mbao.render(loaded, camera=loaded.framing_camera(12, 9), width=12, height=9)
        np.testing.assert_array_equal(read_image(tmp_path / output)[1][..., 0], expected.ao)


def test_hbao_from_the_command_line_equals_the_api(tmp_path, gltf_scene):
    scene, camera, _ = gltf_scene
    proc = run_mbao("render", scene, "--camera", camera, "--width", 12, "--height", 9, "--method", "hbao",
                    "--max-distance", 0.8, "--hbao-directions", 4, "--hbao-steps", 3, "--hbao-angle-bias-deg", 5,
                    "--hbao-falloff", 0.5, "-o", "hbao.exr", cwd=tmp_path)  # fmt: skip
    assert proc.returncode == 0, proc.stderr
    assert "hbao radius=0.8 (--max-distance), directions=4, steps=3" in output_lines(proc.stdout)["settings"]
    expected = mbao.render(
        mbao.load(scene),
        camera=mbao.Camera.load(camera),
        width=12,
        height=9,
        method="hbao",
        max_distance=0.8,
        hbao=mbao.HBAO(directions=4, steps=3, angle_bias_deg=5, falloff=0.5),
    )
    np.testing.assert_array_equal(read_image(tmp_path / "hbao.exr")[1][..., 0], expected.ao)


@pytest.mark.parametrize("command, tables", [("render", ["hbao", "denoise"]), ("orbit", ["temporal", "denoise"])])
def test_the_commands_settings_options_are_the_settings_classes_tables(tmp_path, command, tables):
    """One --TABLE-NAME option per setting of mbao.HBAO's, mbao.Denoise's and
    mbao.Temporal's tables, with its meaning, default and range."""
    help_text = " ".join(run_mbao(command, "--help", cwd=tmp_path).stdout.split())
    for table in tables:
        for spec in mbao._core.setting_specs(table):
            flag = f"--{table}-" + spec["name"].replace("_", "-")
            assert re.search(
                re.escape(flag)
                + r" \S+ "
                + re.escape(spec["doc"])
                + r" \(default: "
                + re.escape(str(spec["default"]))
                + ", allowed "
                + re.escape(spec["range"]),
                help_text,
            ), flag


def test_denoise_options_reach_the_filter_and_are_checked_without_denoise(tmp_path):
    proc = run_mbao(
        "render",
        "--width",
        16,
        "--height",
        12,
        "--denoise",
        "--denoise-iterations",
        2,
        "--denoise-sigma-normal",
        0,
        "-o",
        "out.exr",
        cwd=tmp_path,
    )
    assert proc.returncode == 0, proc.stderr
    expected = mbao.render(mbao.cornell_box(), width=16, height=12, denoise=mbao.Denoise(iterations=2, sigma_normal=0))
    np.testing.assert_array_equal(read_image(tmp_path / "out.exr")[1][..., 0], expected.ao)
    refused = run_mbao("render", "--denoise-iterations", 0, "-o", "out.png", cwd=tmp_path)
    assert refused.returncode != 0 and "denoise iterations must be in [1, 14], got 0" in refused.stderr


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


def test_devices_lists_the_devices(tmp_path, device):
    proc = run_mbao("devices", cwd=tmp_path)
    assert proc.returncode == 0, proc.stderr
    lines = [line for line in proc.stdout.splitlines() if line.strip()]
    assert len(lines) == len(mbao.devices()) >= 1
    assert any(line.startswith(f"{device.index}: ") and device.name in line for line in lines), proc.stdout


@pytest.mark.parametrize(
    "args, message",
    [
        (["render", "no_such_scene.glb"], r"no_such_scene\.glb"),
        (["render", "--bounces", "0"], r"bounces"),
        (["render", "--estimator", "foo"], r"estimator.*foo"),
        (["render", "--rho", "2"], r"rho"),
        (["render", "--camera", "no_such_camera.json"], r"no_such_camera\.json"),
        (["render", "--bounces", "3", "--samples", "8", "--max-rays", "1000"], r"--max-rays 1000.*--estimator path"),
        (["orbit", "--frames", "2"], r"-o 'x\.png': an orbit is written as \.gif"),
    ],
    ids=["missing scene", "bounces 0", "unknown estimator", "rho 2", "missing camera", "past max rays", "orbit to png"],
)
def test_bad_input_gives_a_one_line_message(tmp_path, args, message):
    proc = run_mbao(*args, "--width", 4, "--height", 4, "-o", "x.png", cwd=tmp_path)
    assert proc.returncode != 0
    assert "Traceback" not in proc.stderr
    lines = proc.stderr.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("mbao: "), f"stderr is not one 'mbao: ...' line:\n{proc.stderr}"
    assert re.search(message, lines[0]), lines[0]
    assert not (tmp_path / "x.png").exists()


@pytest.mark.parametrize(
    "args, message",
    [
        (["--fps", "0"], r"fps must be in \(0, 100\]"),
        (["--temporal", "--samples", "1"], r"temporal accumulation .* samples >= 2"),
    ],
    ids=["0 fps", "temporal with r = 1"],
)
def test_a_bad_orbit_gives_a_one_line_message_and_no_gif(tmp_path, args, message):
    proc = run_mbao("orbit", *args, "--frames", 2, "--width", 4, "--height", 4, "-o", "x.gif", cwd=tmp_path)
    assert proc.returncode != 0 and "Traceback" not in proc.stderr
    assert re.fullmatch("mbao: " + message + r".*\n", proc.stderr), proc.stderr
    assert not (tmp_path / "x.gif").exists()


def test_unknown_device_lists_the_devices(tmp_path, device):
    proc = run_mbao("render", "--device", "no-such-gpu", "--width", 4, "--height", 4, "-o", "x.png", cwd=tmp_path)
    assert proc.returncode != 0
    assert "Traceback" not in proc.stderr
    assert proc.stderr.startswith("mbao: ") and "no-such-gpu" in proc.stderr.splitlines()[0]
    assert device.name in proc.stderr
    assert not (tmp_path / "x.png").exists()
