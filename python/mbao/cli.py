"""python -m mbao: render from the command line.

    python -m mbao render [scene.glb] [--bounces 2] [--samples 4] [-o ao.png] ...
    python -m mbao bake scene.glb -o baked.glb [--target texture|vertices] ...
    python -m mbao orbit [scene.glb] -o orbit.gif [--frames 60] [--temporal] [--denoise] ...
    python -m mbao view [scene.glb] [--camera camera.json] [--bounces 2] [--host 127.0.0.1] [--port N] ...
    python -m mbao check file.glb
    python -m mbao devices
"""

import argparse
import contextlib
import pathlib
import re
import sys
import warnings

from . import _core
from .devices import devices
from . import __version__
from ._progress import progress_count, progress_reporter
from .images import check_writable, save_image
from .render import render, render_sequence
from .scene import FRAME, as_camera, load
from .settings import BAKE_SETTINGS, DENOISE_SETTINGS, ENGINE, HBAO_SETTINGS, RENDER, TEMPORAL_SETTINGS, Engine

QUIET_HELP = "no progress bar (by default one is shown on a terminal for work of more than a few seconds)"


class _Parser(argparse.ArgumentParser):
    def error(self, message):
        """One line, like every other error of the command: no usage block."""
        self.exit(2, f"mbao: {message} (see {self.prog} --help)\n")

    def in_flags(self, message):
        """`message`, which names settings as Python does (texcoord="generate",
        max_distance=..., camera=mbao.Camera(...)), with each one this command
        has as an option named as its flag (--texcoord generate)."""

        def as_flag(match):
            name, value = match.group("name"), match.group("value")
            flag = "--" + name.replace("_", "-")
            if flag not in self._option_string_actions:  # argparse's table of the command's flags
                return match.group(0)
            if value == "True":
                return flag
            return f"{flag} {_flag_value(value)}"

        return _PYTHON_SETTING.sub(as_flag, message)


# name=value as Python messages write a setting: a quoted string, a pair, mbao.Camera(...), or a bare word.
_PYTHON_SETTING = re.compile(
    r'(?<![\w.-])(?P<name>[a-z][a-z_]*)=(?P<value>"[^"]*"|\(\d+, \d+\)|mbao\.Camera\(\.\.\.\)' r"|[^\s,;)]+)"
)


def _flag_value(value):
    """A Python value as its flag takes it: "generate" as generate, (256, 128) as 256 128, a camera as its file."""
    if value == "mbao.Camera(...)":
        return "CAMERA.json"
    if value.startswith("("):
        return value[1:-1].replace(",", "")
    return value.strip('"')


def _parser():
    parser = _Parser(prog="python -m mbao", description="Multi-bounce ambient occlusion with OpenCL.")
    parser.add_argument("--version", action="version", version=f"mbao {__version__}")
    commands = parser.add_subparsers(dest="command", required=True, parser_class=_Parser)
    parser.commands = commands.choices

    r = commands.add_parser("render", help="render a scene (the built-in Cornell box by default) to an image")
    r.add_argument(
        "scene",
        nargs="?",
        help="a scene file (glTF, or OBJ, PLY, FBX, ... through Assimp); omitted: the built-in Cornell box",
    )
    r.add_argument(
        "-o", "--output", default="ao.png", help="image to write: .png (8-bit) or .exr (float) (default: %(default)s)"
    )
    r.add_argument(
        "--no-alpha",
        action="store_true",
        help="write the AO alone, without the coverage that tells the background apart (SPEC 2): a PNG's "
        "alpha, an EXR's channel 'coverage'",
    )
    r.add_argument(
        "--camera",
        help=f"camera.json (SPEC 3.1.1), or {FRAME} for one framing the whole scene "
        "(default: the scene's own camera, else one framing it)",
    )
    for spec in RENDER.values():
        _add_setting(r, spec)
    r.add_argument(
        "--denoise",
        action="store_true",
        help="filter the image with the edge-aware a-trous filter of SPEC 7.3 (spp 1, samples >= 2)",
    )
    _add_table(r, "denoise options", "for --denoise (SPEC 7.3): mbao.Denoise's settings", DENOISE_SETTINGS, "denoise_")
    _add_table(r, "HBAO options", "for --method hbao (SPEC 4): mbao.HBAO's settings", HBAO_SETTINGS, "hbao_")
    r.add_argument("--device", help="index or part of the name, see `python -m mbao devices`")
    r.add_argument("--quiet", action="store_true", help=QUIET_HELP)
    engine = r.add_argument_group("engine options", "how the work is done; none of them changes the image")
    for spec in ENGINE.values():
        _add_setting(engine, spec)

    c = commands.add_parser(
        "compare",
        formatter_class=argparse.ArgumentDefaultsHelpFormatter,
        help="the paper's Figure 2 (HBAO | 1 bounce | 2 bounces | difference) "
        "and error against time for every method",
    )
    c.add_argument(
        "scene",
        nargs="?",
        help="a scene file (glTF, or OBJ, PLY, FBX, ... through Assimp); omitted: the built-in Cornell box",
    )
    c.add_argument("-o", "--output", default="compare", help="file name prefix")
    c.add_argument(
        "--camera",
        help=f"camera.json, or {FRAME} for one framing the whole scene; None: the scene's own "
        "camera, else one framing it",
    )
    for name in ("width", "height"):
        _add_setting(c, RENDER[name], default=256)
    _add_setting(c, RENDER["samples"])
    _add_setting(c, RENDER["rho"])
    c.add_argument(
        "--max-distance",
        type=float,
        help="AO radius (HBAO's too); None: camera.json's, else a quarter of the scene's diagonal",
    )
    c.add_argument("--target-error", type=float, default=0.01, help="the reference's standard error per pixel")
    c.add_argument(
        "--sample-counts",
        type=int,
        nargs="+",
        default=[1, 2, 4, 8, 16],
        help="r of each method's renders in the study (HBAO: its directions)",
    )
    _add_setting(c, RENDER["seed"])
    c.add_argument("--quiet", action="store_true", help=QUIET_HELP)
    c.add_argument(
        "--scheduler",
        metavar="ADDRESS",
        help="a Dask scheduler (tcp://HOST:8786): the reference and the study render on its workers' "
        "devices (--device then names Figure 2's)",
    )
    c.add_argument(
        "--device",
        help="index or part of the name, see `python -m mbao devices`; None: $MBAO_DEVICE, else the first GPU, "
        "else the first device",
    )

    b = commands.add_parser(
        "bake",
        formatter_class=argparse.ArgumentDefaultsHelpFormatter,
        help="bake AO into a glTF file's occlusion textures or vertices (SPEC 6)",
    )
    b.add_argument("input", help="a scene file: glTF, or another format mbao.load reads (OBJ, PLY, FBX, ...)")
    b.add_argument(
        "-o",
        "--output",
        required=True,
        help="the baked file, everything else in it kept: .glb for a .glb input, .gltf for a .gltf one; "
        "another format is written as a new glTF, .glb or .gltf",
    )
    _add_setting(b, BAKE_SETTINGS["target"])
    b.add_argument(
        "--texcoord",
        type=_texcoord_argument,
        help="n of the UV set TEXCOORD_n, or 'generate' for a new one of charts (written as the next free "
        "TEXCOORD_n); None: the occlusion texture's, else TEXCOORD_1, else TEXCOORD_0",
    )
    b.add_argument(
        "--resolution", type=int, nargs="+", default=[1024], metavar="N", help="the texture's size: N, or WIDTH HEIGHT"
    )
    for spec in BAKE_SETTINGS.values():
        if spec["name"] != "target":
            _add_setting(b, spec)
    for name in ("bounces", "rho"):
        _add_setting(b, RENDER[name])
    b.add_argument(
        "--max-distance",
        type=float,
        help="AO radius in world units, inf for none; None: the one --camera suggests, else the one the "
        "scene's own camera suggests, else inf (SPEC 1)",
    )
    b.add_argument(
        "--camera", help="a camera.json whose max_distance is the bake's radius (nothing else of it is used)"
    )
    _add_setting(b, RENDER["seed"])
    b.add_argument("--bit-depth", type=int, choices=[8, 16], default=8, help="bits per channel of the textures")
    b.add_argument(
        "--vertex-colors",
        action="store_true",
        help="with --target vertices, also multiply the AO into COLOR_0, for viewers that show no "
        "_OCCLUSION (COLOR_0 darkens direct light too, which occlusion should not)",
    )
    b.add_argument("--quiet", action="store_true", help=QUIET_HELP)
    b.add_argument(
        "--device",
        help="index or part of the name, see `python -m mbao devices`; None: $MBAO_DEVICE, "
        "else the first GPU, else the first device",
    )
    b.add_argument(
        "--scheduler",
        metavar="ADDRESS",
        help="a Dask scheduler (tcp://HOST:8786): the bake is traced in parts on its workers' devices, "
        "the same bake bit for bit",
    )

    o = commands.add_parser("orbit", help="render a camera's turn around the scene as an animated GIF")
    o.add_argument(
        "scene",
        nargs="?",
        help="a scene file (glTF, or OBJ, PLY, FBX, ... through Assimp); omitted: the built-in Cornell box",
    )
    o.add_argument("-o", "--output", default="orbit.gif", help="the GIF to write (default: %(default)s)")
    o.add_argument(
        "--camera",
        help=f"camera.json of the first frame, or {FRAME} for one framing the whole scene "
        "(default: the scene's own camera, else one framing it); the eye turns about the "
        "vertical line through its target",
    )
    o.add_argument("--frames", type=int, default=60, help="frames in the turn (default: %(default)s)")
    o.add_argument("--degrees", type=float, default=360.0, help="the turn's angle (default: %(default)s)")
    o.add_argument("--fps", type=float, default=25.0, help="frames per second of the GIF (default: %(default)s)")
    o.add_argument(
        "--temporal",
        action="store_true",
        help="accumulate each frame with the ones before, reprojected (SPEC 7.4; spp 1, samples >= 2)",
    )
    o.add_argument(
        "--denoise",
        action="store_true",
        help="filter each frame with the edge-aware a-trous filter of SPEC 7.3 (spp 1, samples >= 2)",
    )
    _add_table(
        o, "temporal options", "for --temporal (SPEC 7.4): mbao.Temporal's settings", TEMPORAL_SETTINGS, "temporal_"
    )
    _add_table(o, "denoise options", "for --denoise (SPEC 7.3): mbao.Denoise's settings", DENOISE_SETTINGS, "denoise_")
    for spec in RENDER.values():
        _add_setting(o, spec)
    o.add_argument("--device", help="index or part of the name, see `python -m mbao devices`")
    o.add_argument("--quiet", action="store_true", help=QUIET_HELP)

    _add_view(commands)

    k = commands.add_parser(
        "check", help="validate a glTF file (the Khronos glTF-Validator) and say what ambient " "occlusion it stores"
    )
    k.add_argument("file", help="a .gltf or .glb file, a baked one or any other")

    commands.add_parser("devices", help="list the OpenCL devices")

    from .blender.install import SUPPORTED

    g = commands.add_parser(
        "blender", help=f"the Blender add-on, which bakes multi-bounce AO in Blender " f"({SUPPORTED}; SPEC 9)"
    )
    where = g.add_mutually_exclusive_group(required=True)
    where.add_argument("--install", action="store_true", help="install it into the user's add-ons and enable it")
    where.add_argument("--zip", metavar="FILE", help="write it as a zip, for Preferences > Add-ons > Install")
    g.add_argument(
        "--blender", default="blender", help="the Blender executable to install into " "(default: %(default)s)"
    )
    return parser


def _add_view(commands):
    from .viewer.view_settings import METHODS, VIEWER

    v = commands.add_parser("view", help="a live, progressive view in the browser (docs/viewer.md)")
    v.add_argument(
        "scene",
        nargs="?",
        help="a scene file (glTF, or OBJ, PLY, FBX, ... through Assimp); omitted: the built-in Cornell box",
    )
    v.add_argument(
        "--camera",
        help=f"camera.json of the home view, or {FRAME} for one framing the whole scene "
        "(default: the scene's own camera, else one framing it)",
    )
    for spec in RENDER.values():
        if spec["name"] != "method":
            _add_setting(v, spec)
    v.add_argument(
        "--method",
        choices=METHODS,
        default="raytraced",
        help="what the image shows: ray-traced AO, HBAO, HBAO with the GTAO fit (SPEC 8), or the bake "
        "the file holds, at the camera hits (default: %(default)s)",
    )
    v.add_argument("--denoise", action="store_true", help=VIEWER["denoise"]["doc"])
    v.add_argument(
        "--no-temporal",
        dest="temporal",
        action="store_false",
        help="a still view shows one frame, " "not frames accumulated (SPEC 7.4)",
    )
    v.add_argument("--frames", type=int, default=0, help=VIEWER["frames"]["doc"] + " (default: %(default)s)")
    v.add_argument(
        "--host",
        default="127.0.0.1",
        help="the address to serve on; another than loopback needs the "
        "token the printed URL carries (default: %(default)s)",
    )
    v.add_argument("--port", type=int, help="the port (default: the first free one from 8750)")
    v.add_argument("--no-browser", action="store_true", help="print the URL without opening a browser")
    v.add_argument("--device", help="index or part of the name, see `python -m mbao devices`")


def _add_setting(parser, spec, prefix="", default=None):
    """The option of one setting of a settings table, named (after `prefix`), typed and documented by it;
    `default`, where given, is the command's own default in place of the table's."""
    flag, kind = "--" + (prefix + spec["name"]).replace("_", "-"), spec["kind"]
    if kind == "flag":
        parser.add_argument(flag, action="store_true", help=spec["doc"])
        return
    allowed = f", allowed {spec['range']}" if kind in ("integer", "unsigned", "real") else ""
    value = spec["default"] if default is None else default
    shown = spec["none_means"] or "automatic" if value is None else "%(default)s"
    options = dict(default=value, help=f"{spec['doc']} (default: {shown}{allowed})")
    if kind == "choice":
        options["choices"] = spec["choices"]
    else:
        options["type"] = float if kind == "real" else int
    parser.add_argument(flag, **options)


def _add_table(parser, title, description, table, prefix):
    """An option group of one settings table, each option --PREFIX-NAME."""
    group = parser.add_argument_group(title, description)
    for spec in table.values():
        _add_setting(group, spec, prefix)


def _table_values(args, table, prefix):
    """{name: value} of a settings table from its options."""
    return {name: getattr(args, prefix + name) for name in table}


def _temporal_argument(args):
    """mbao.Temporal of the --temporal-* options where --temporal is given; checked either way."""
    settings = _core.Temporal(**_table_values(args, TEMPORAL_SETTINGS, "temporal_"))
    return settings if args.temporal else False


def _denoise_argument(args):
    """mbao.Denoise of the --denoise-* options where --denoise is given; checked either way."""
    settings = _core.Denoise(**_table_values(args, DENOISE_SETTINGS, "denoise_"))
    return settings if args.denoise else None


def _radius(stats, args):
    """The radius a render used, and where it came from (SPEC 1's rule)."""
    source = {
        "settings": "--max-distance",
        "camera": "camera.json" if args.camera else "the scene's camera",
        "scene": "a quarter of the scene's diagonal",
        "none": "no camera suggests one",
    }
    return f"{stats['max_distance']:g} ({source[stats['max_distance_source']]})"


def _texcoord_argument(text):
    if text == "generate":
        return text
    try:
        return int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"takes a set's number or 'generate', not {text!r}") from None


def _progress_argument(args):
    """progress= of a command: none with --quiet, else mbao's default (a bar on a terminal for long work)."""
    return False if args.quiet else None


def _device_argument(text):
    return int(text) if text is not None and text.isdigit() else text


def _camera_argument(args, scene):
    """--camera: a camera.json, or "frame"; none: the scene's own camera, else the framing one."""
    size = (args.width, args.height)
    return as_camera(args.camera, scene, size) if args.camera else scene.default_camera(*size)


def _render(args):
    check_writable(args.output, "-o")  # before the render, not after it
    scene = load(args.scene) if args.scene else _core.cornell_box()
    result = render(
        scene,
        camera=args.camera,
        hbao=_core.HBAO(**_table_values(args, HBAO_SETTINGS, "hbao_")),
        engine=Engine(**{name: getattr(args, name) for name in ENGINE}),
        device=_device_argument(args.device),
        denoise=_denoise_argument(args),
        progress=_progress_argument(args),
        **{name: getattr(args, name) for name in RENDER},
    )
    save_image(args.output, result.ao, alpha=None if args.no_alpha else result.coverage)
    if args.variance:
        save_image(_variance_path(args.output), result.variance)
    s = result.stats
    rays = s["rays_primary"] + s["rays_secondary"]
    tree = s["tree"]
    print(f"scene        {scene.name} ({scene.triangle_count} triangles)")
    print(f"device       {s['device']}")
    if args.method == "hbao":
        print(
            f"settings     {args.width}x{args.height}, hbao radius={_radius(s, args)}, directions={args.hbao_directions}, "
            f"steps={args.hbao_steps}, angle_bias={args.hbao_angle_bias_deg} deg, falloff={args.hbao_falloff}"
        )
    else:
        print(
            f"settings     {args.width}x{args.height}, bounces={args.bounces}, samples={args.samples}, "
            f"{args.estimator}, rho={args.rho}, max_distance={_radius(s, args)}, spp={args.spp}"
        )
    print(
        f"kd-tree      {tree['build_ms']:.1f} ms: {tree['nodes']} nodes, {tree['leaves']} leaves, "
        f"depth {tree['max_depth']}, {tree['mean_triangles_per_leaf']:.2f} triangles per leaf, SAH {tree['sah_cost']:.1f}"
    )
    print(f"kernels      {s['kernel_build_ms']:.1f} ms ({s['kernel_cache']}: {s['kernel_options']})")
    print(
        f"frame        {s['frame_ms']:.1f} ms in {s['tiles']} tile(s)"
        + (f", {s['denoise_ms']:.1f} ms of it denoising" if args.denoise else "")
    )
    print(
        f"rays         {s['rays_primary']} primary + {s['rays_secondary']} secondary = "
        f"{rays / s['frame_ms'] / 1e3:.2f} Mrays/s"
    )
    if "traversal" in s:
        t = s["traversal"]
        print(
            f"per ray      {t['nodes_per_ray']:.1f} nodes, {t['leaves_per_ray']:.1f} leaves, "
            f"{t['triangles_per_ray']:.1f} triangle tests, {t['restarts_per_ray']:.2f} restarts ({s['traversal_mode']})"
        )
    print(f"memory       {s['memory_bytes'] / 2**20:.1f} MiB on the device")
    print(f"wrote        {args.output}")
    if args.variance:
        print(f"wrote        {_variance_path(args.output)} (each pixel's variance, SPEC 7.1)")
    return 0


def _variance_path(output):
    """Where --variance goes: beside the image, as float EXR."""
    return str(pathlib.Path(output).with_suffix("")) + ".variance.exr"


def _compare(args):
    from . import compare

    scene = load(args.scene) if args.scene else _core.cornell_box()
    camera = _camera_argument(args, scene)
    with _client_of(args.scheduler) as client:
        compare.run(scene, camera, args, _device_argument(args.device), client)
    return 0


# Seconds a command waits for the Dask scheduler it is given.
_SCHEDULER_TIMEOUT_S = 10


def _client_of(scheduler):
    """A Dask client of the scheduler at that address, or none (work done here)."""
    if scheduler is None:
        return contextlib.nullcontext()
    from distributed import Client

    try:
        return Client(scheduler, timeout=_SCHEDULER_TIMEOUT_S)
    except (OSError, TimeoutError, ValueError) as error:
        raise OSError(
            f"--scheduler {scheduler}: cannot reach a Dask scheduler there within "
            f"{_SCHEDULER_TIMEOUT_S} s ({error})"
        ) from None


def _bake(args):
    from .bake_file import bake_file

    if len(args.resolution) > 2:
        raise ValueError(f"--resolution takes N or WIDTH HEIGHT, got {len(args.resolution)} numbers")
    with _client_of(args.scheduler) as client:
        result = bake_file(
            args.input,
            args.output,
            target=args.target,
            bit_depth=args.bit_depth,
            vertex_colors=args.vertex_colors,
            bounces=args.bounces,
            samples=args.samples,
            estimator=args.estimator,
            directions=args.directions,
            rho=args.rho,
            max_distance=args.max_distance,
            camera=args.camera,
            seed=args.seed,
            texcoord=args.texcoord,
            resolution=tuple(args.resolution) * (3 - len(args.resolution)),
            padding=args.padding,
            device=_device_argument(args.device),
            progress=_progress_argument(args),
            client=client,
        )
    s = result.stats
    print(f"scene        {args.input}")
    print(f"device       {s['device']}")
    print(
        f"settings     {args.target}, bounces={args.bounces}, samples={args.samples}, {args.estimator} with "
        f"r={args.directions}, rho={args.rho}, seed={args.seed}"
    )
    print(f"radius       {_radius(s, args)}")
    for material, texture in result.textures.items():
        t = texture.stats
        height, width = texture.image.shape
        into = "generated UVs" if texture.texcoord == "generated" else f"TEXCOORD_{texture.texcoord}"
        label = f"material {material:<3}" if material >= 0 else "no material "  # the triangles without one
        print(
            f"{label} {width}x{height} into {into}: {t['covered']} texels covered, "
            f"{t['dilated']} dilated, mean {texture.image[texture.coverage].mean():.3f}"
        )
    if args.vertex_colors:
        print("COLOR_0      multiplied by the AO; glTF's COLOR_0 darkens direct light too, which occlusion should not")
    for material in s["replaced_occlusion"]:
        print(f"replaced     material {material}'s occlusion texture")
    if result.values is not None:
        print(
            f"vertices     {len(result.values)}, mean {result.values.mean():.3f}, "
            f"largest standard error {result.standard_error.max():.3f}"
        )
    print(f"bake         {s['frame_ms'] / 1e3:.1f} s, {s['rays_secondary'] / s['frame_ms'] / 1e3:.2f} Mrays/s")
    print(f"wrote        {args.output}")
    return 0


def _orbit(args):
    from .orbit import check_gif, orbit_cameras, save_gif

    check_gif(args.output, args.fps, "-o")  # before the frames, not after them
    scene = load(args.scene) if args.scene else _core.cornell_box()
    first = _camera_argument(args, scene)
    sequence = render_sequence(
        scene,
        orbit_cameras(first, args.frames, args.degrees),
        temporal=_temporal_argument(args),
        denoise=_denoise_argument(args),
        device=_device_argument(args.device),
        progress=False,
        **{name: getattr(args, name) for name in RENDER},
    )
    with progress_reporter(_progress_argument(args), "orbit", "frame", args.frames) as report:
        count, frames = progress_count(report, args.frames), []
        for frame in sequence:
            frames.append(frame)
            count.advance()
    save_gif(args.output, [frame.ao for frame in frames], args.fps)
    frame_ms = [frame.stats["frame_ms"] for frame in frames]
    print(f"scene        {scene.name} ({scene.triangle_count} triangles)")
    print(f"device       {frames[0].stats['device']}")
    print(
        f"settings     {args.width}x{args.height}, bounces={args.bounces}, samples={args.samples}, {args.estimator}, "
        f"{args.frames} frames over {args.degrees:g} degrees"
        + (", temporal" if args.temporal else "")
        + (", denoised" if args.denoise else "")
    )
    print(f"frames       {sum(frame_ms) / len(frame_ms):.1f} ms each on average, {max(frame_ms):.1f} ms at most")
    print(f"wrote        {args.output} ({args.fps:g} fps)")
    return 0


def _view(args):
    import asyncio
    import signal

    from .viewer import open_viewer
    from .viewer.view_settings import VIEWER

    settings = {name: getattr(args, name) for name in list(RENDER) + list(VIEWER)}
    viewer = open_viewer(
        args.scene, camera=args.camera, device=_device_argument(args.device), host=args.host, port=args.port, **settings
    )

    async def serve():
        await viewer.start()
        print(f"scene        {viewer.scene.name} ({viewer.scene.triangle_count} triangles)")
        print(f"device       {viewer.device.name}")
        print("serving the view at (Ctrl-C stops):")
        print(viewer.url, flush=True)
        if not args.no_browser:
            _open_browser(viewer.url)
        # Through the loop, whose wakeup descriptor the signal writes to: a plain handler runs only
        # once the main thread wakes, and the signal may land on one of OpenCL's threads instead.
        stopped = asyncio.Event()
        for stop_signal in (signal.SIGINT, signal.SIGTERM):
            asyncio.get_running_loop().add_signal_handler(stop_signal, stopped.set)
        try:
            await stopped.wait()
        finally:
            await viewer.stop()

    asyncio.run(serve())
    print("mbao: stopped", file=sys.stderr)
    return 0


def _open_browser(url):
    """Opens `url` where the machine has a graphical browser; a terminal's text browser would take the terminal."""
    import os
    import webbrowser

    if sys.platform in ("darwin", "win32") or os.environ.get("DISPLAY") or os.environ.get("WAYLAND_DISPLAY"):
        webbrowser.open(url)


def _blender(args):
    from .blender import install

    if args.zip:
        print(
            f"wrote {install.write_zip(args.zip)}: install it in Blender's Preferences > Add-ons > Install, "
            f'then enable "Render: mbao"'
        )
    else:
        print(
            f"installed and enabled the add-on in {install.install(args.blender)}: see Properties > Render > "
            f"mbao Multi-Bounce AO, or call bpy.ops.mbao.bake"
        )
    return 0


def main(argv=None):
    parser = _parser()
    args = parser.parse_args(argv)
    command = parser.commands[args.command]

    def print_warning(message, category, filename, lineno, file=None, line=None):
        """A warning as one line, like the command's errors: no source line."""
        print(f"mbao: warning: {command.in_flags(str(message))}", file=sys.stderr)

    try:
        with warnings.catch_warnings():  # restores the caller's showwarning after
            warnings.showwarning = print_warning
            if args.command == "devices":
                for d in devices():
                    print(f"{d.index}: {d.platform}: {d.name} ({d.type}, {d.version})")
                return 0
            if args.command == "check":
                from .check import check

                return check(args.file)
            if args.command == "compare":
                return _compare(args)
            if args.command == "bake":
                return _bake(args)
            if args.command == "orbit":
                return _orbit(args)
            if args.command == "view":
                return _view(args)
            if args.command == "blender":
                return _blender(args)
            return _render(args)
    except (ValueError, TypeError, OSError, _core.Error) as error:
        print(f"mbao: {command.in_flags(str(error))}", file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        if args.command == "view":
            print("mbao: stopped", file=sys.stderr)
            return 0
        print("mbao: interrupted", file=sys.stderr)
        return 130  # the shell's code for a command stopped by SIGINT
