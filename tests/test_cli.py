"""`python -m mbao`: the command line, run as a user would, in a subprocess."""

import json
import re

import numpy as np
import pytest

import mbao
from command_line import output_lines, read_image, run_mbao, write_box_scene
from gltf_writer import GltfBuilder
from meshes import box, plane


@pytest.fixture(scope="module")
def gltf_scene(tmp_path_factory):
    return write_box_scene(tmp_path_factory.mktemp("cli_scene"))


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


def test_unknown_device_lists_the_devices(tmp_path, device):
    proc = run_mbao("render", "--device", "no-such-gpu", "--width", 4, "--height", 4, "-o", "x.png", cwd=tmp_path)
    assert proc.returncode != 0
    assert "Traceback" not in proc.stderr
    assert proc.stderr.startswith("mbao: ") and "no-such-gpu" in proc.stderr.splitlines()[0]
    assert device.name in proc.stderr
    assert not (tmp_path / "x.png").exists()
