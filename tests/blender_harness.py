"""Running scripts in Debian's Blender for the add-on's tests (SPEC 9): each
runs in `blender -b` with the add-on installed by `python -m mbao blender
--install` into a folder of the test module's own. The scripts assert; a
failed assertion is Blender's exit status 1 and its output in the test's."""

import os
import subprocess
import sys
import textwrap
from pathlib import Path


PYTHON_DIR = Path(__file__).resolve().parents[1] / "python"

# What every script starts with: mbao itself (for the values the add-on must
# match) and a scene of a subdivided cube standing on a plane.
PRELUDE = f"""
import os
import sys
import bpy
import numpy as np
sys.path.insert(0, {str(PYTHON_DIR)!r})
import mbao

bpy.ops.wm.read_homefile(use_empty=True)


def cube_on_a_plane(cuts=3):
    bpy.ops.mesh.primitive_plane_add(size=10)
    plane = bpy.context.active_object
    bpy.ops.mesh.primitive_cube_add(location=(0.5, -0.25, 1.0), rotation=(0.0, 0.0, 0.3))
    cube = bpy.context.active_object
    bpy.ops.object.mode_set(mode="EDIT")
    bpy.ops.mesh.subdivide(number_cuts=cuts)
    bpy.ops.object.mode_set(mode="OBJECT")
    select(cube)
    return cube, plane


def select(*objects):
    bpy.ops.object.select_all(action="DESELECT")
    for obj in objects:
        obj.select_set(True)
    bpy.context.view_layer.objects.active = objects[0]


def world_vertices(obj):
    co = np.empty(len(obj.data.vertices) * 3, np.float32)
    obj.data.vertices.foreach_get("co", co)
    matrix = np.array(obj.matrix_world, dtype=np.float64)
    return co.reshape(-1, 3).astype(np.float64) @ matrix[:3, :3].T + matrix[:3, 3]


def triangles(obj):
    obj.data.calc_loop_triangles()
    out = np.empty(len(obj.data.loop_triangles) * 3, np.int32)
    obj.data.loop_triangles.foreach_get("vertices", out)
    return out.reshape(-1, 3)


def colors(obj, name):
    attribute = obj.data.color_attributes[name]
    out = np.empty(len(attribute.data) * 4, np.float32)
    attribute.data.foreach_get("color", out)
    return out.reshape(-1, 4)


def refused(message, **settings):
    try:
        bpy.ops.mbao.bake(**settings)
    except RuntimeError as error:
        text = str(error)
        assert text.startswith("Error: mbao") or text.startswith("Error: "), text
        assert message in text and "Traceback" not in text, text
        return
    raise AssertionError(f"baking with {{settings}} was not refused")
"""


def installed_home(home):
    """The environment of a Blender whose user folder is `home`, the add-on
    installed and enabled there by the README's command."""
    environment = dict(os.environ, BLENDER_USER_SCRIPTS=str(home / "scripts"), BLENDER_USER_CONFIG=str(home / "config"))
    installed = subprocess.run(
        [sys.executable, "-m", "mbao", "blender", "--install"],
        env=environment,
        capture_output=True,
        text=True,
        timeout=300,
    )
    assert installed.returncode == 0, installed.stderr
    assert (home / "scripts" / "addons" / "mbao_bake" / "location.json").is_file()
    return environment


def blender(environment, tmp_path, body):
    """Runs PRELUDE + body in Blender, with the user's preferences (the add-on enabled)."""
    script = tmp_path / "script.py"
    script.write_text(PRELUDE + textwrap.dedent(body))
    run = subprocess.run(
        ["blender", "-b", "--python-exit-code", "1", "--python", str(script)],
        env=environment,
        cwd=tmp_path,
        capture_output=True,
        text=True,
        timeout=600,
    )
    assert run.returncode == 0, run.stdout[-6000:] + run.stderr[-6000:]
    return run.stdout
