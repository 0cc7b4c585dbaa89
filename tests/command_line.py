"""Running `python -m mbao` as a user would, in a subprocess, and reading what it writes."""

import json
import os
import pathlib
import subprocess
import sys

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


def write_box_scene(folder):
    """A box on a floor as a .gltf file in `folder`, a camera.json looking at it, and one looking away."""
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
