"""The Blender add-on installed and used as a user does (SPEC 9; docs/blender.md):
the command and the zip install it, it registers and unregisters, the docs'
script runs, and from Blender's UI (a window, under Xvfb) it bakes beside the
UI and Esc cancels."""

import os
import subprocess
import sys
from pathlib import Path

from blender_harness import blender


def test_the_addon_registers_and_unregisters(blender_home, tmp_path):
    blender(
        blender_home,
        tmp_path,
        """
        import addon_utils
        assert addon_utils.check("mbao_bake") == (True, True)  # enabled by the installer, and loaded
        assert hasattr(bpy.types, "MBAO_OT_bake") and hasattr(bpy.types.Scene, "mbao_bake")
        assert bpy.types.MBAO_PT_bake.bl_context == "render"
        addon_utils.disable("mbao_bake")
        assert not hasattr(bpy.types, "MBAO_OT_bake") and not hasattr(bpy.types.Scene, "mbao_bake")
        addon_utils.enable("mbao_bake")
        assert hasattr(bpy.types, "MBAO_OT_bake")
    """,
    )


def test_the_zip_installs_from_blenders_preferences(tmp_path):
    """`python -m mbao blender --zip` writes what Preferences > Add-ons > Install
    takes; installed and enabled so, it bakes."""
    archive = tmp_path / "mbao_bake.zip"
    written = subprocess.run(
        [sys.executable, "-m", "mbao", "blender", "--zip", str(archive)], capture_output=True, text=True, timeout=60
    )
    assert written.returncode == 0, written.stderr
    home = tmp_path / "home"
    environment = dict(os.environ, BLENDER_USER_SCRIPTS=str(home / "scripts"), BLENDER_USER_CONFIG=str(home / "config"))
    blender(
        environment,
        tmp_path,
        f"""
        bpy.ops.preferences.addon_install(filepath={str(archive)!r})
        bpy.ops.preferences.addon_enable(module="mbao_bake")
        cube, plane = cube_on_a_plane(cuts=1)
        assert bpy.ops.mbao.bake(samples=4) == {{"FINISHED"}}
        assert "mbao_ao" in cube.data.color_attributes
    """,
    )


def test_the_command_says_what_is_wrong(tmp_path):
    run = subprocess.run(
        [sys.executable, "-m", "mbao", "blender", "--install", "--blender", str(tmp_path / "none")],
        capture_output=True,
        text=True,
        timeout=60,
    )
    assert run.returncode == 2
    assert f"no Blender at '{tmp_path / 'none'}'" in run.stderr
    run = subprocess.run([sys.executable, "-m", "mbao", "blender"], capture_output=True, text=True, timeout=60)
    assert run.returncode == 2 and "one of the arguments --install --zip is required" in run.stderr


def test_the_docs_script_runs_in_blender(blender_home, tmp_path):
    """docs/blender.md's script, as pasted into Blender's Python."""
    text = (Path(__file__).resolve().parents[1] / "docs" / "blender.md").read_text()
    script = text.split("```python blender\n")[1].split("```")[0]
    said = blender(blender_home, tmp_path, script)
    assert "vertices baked" in said and "Info: mbao: baked color attribute 'mbao_ao' of 1 object" in said


# Run in a Blender with a window (under Xvfb), its events simulated: the
# operator as the panel's button runs it, beside the UI, then Esc.
WINDOWED = """
import sys
import time
import traceback

import bpy
import numpy as np

import mbao_bake.jobs

jobs = []
started = mbao_bake.jobs.BakeJob.__init__


def recorded(self, *arguments):
    started(self, *arguments)
    jobs.append(self)


mbao_bake.jobs.BakeJob.__init__ = recorded
state = {"ticks": 0, "step": "cancel"}


def colors(obj, name):
    attribute = obj.data.color_attributes[name]
    out = np.empty(len(attribute.data) * 4, np.float32)
    attribute.data.foreach_get("color", out)
    return out


def invoke(**settings):
    window = bpy.context.window_manager.windows[0]
    view = next(area for area in window.screen.areas if area.type == "VIEW_3D")
    with bpy.context.temp_override(window=window, area=view, region=view.regions[-1]):
        assert bpy.ops.mbao.bake("INVOKE_DEFAULT", **settings) == {"RUNNING_MODAL"}
    state.update(ticks=0, since=time.monotonic())


def setup():
    for obj in list(bpy.data.objects):
        bpy.data.objects.remove(obj)
    bpy.ops.mesh.primitive_plane_add(size=10)
    bpy.ops.mesh.primitive_monkey_add(location=(0, 0, 1))
    bpy.ops.object.shade_smooth()
    invoke(samples=65536, bounces=2)
    bpy.app.timers.register(checked(tick), first_interval=0.05)


def tick():
    state["ticks"] += 1
    monkey = bpy.data.objects["Suzanne"]
    job = jobs[-1]
    if state["step"] == "cancel":
        if state["ticks"] == 3:
            window = bpy.context.window_manager.windows[0]
            window.event_simulate(type="ESC", value="PRESS")
            window.event_simulate(type="ESC", value="RELEASE")
            state["escaped"] = time.monotonic()
        if state["ticks"] > 3 and job.done:
            assert job.cancelled and job.result is None
            assert time.monotonic() - state["escaped"] < 10.0, "Esc took longer than a tile to stop the bake"
            assert "mbao_ao" not in monkey.data.color_attributes
            state["step"] = "bake"
            invoke(samples=4096, bounces=2, seed=3)
        return 0.05
    if "mbao_ao" not in monkey.data.color_attributes:
        return 0.05
    assert state["ticks"] >= 2, "the UI's timers did not run while the bake ran"
    assert len(jobs) == 2 and not jobs[-1].cancelled
    assert bpy.ops.mbao.bake(samples=4096, bounces=2, seed=3, attribute="direct") == {"FINISHED"}
    assert np.array_equal(colors(monkey, "mbao_ao"), colors(monkey, "direct"))
    print("WINDOWED TEST PASSED", flush=True)
    bpy.ops.wm.quit_blender()


def checked(step):
    def run():
        try:
            return step()
        except Exception:
            traceback.print_exc()
            sys.stdout.flush()
            import os
            os._exit(1)
    return run


bpy.app.timers.register(checked(setup), first_interval=0.5)
"""


def test_from_the_ui_it_bakes_beside_it_and_esc_cancels(blender_home, tmp_path):
    """In a Blender with a window: the operator invoked as the panel's button
    does it runs modal, the UI's timers tick while it bakes, Esc stops it with
    nothing written, and a bake left to finish writes what a script's does."""
    script = tmp_path / "windowed.py"
    script.write_text(WINDOWED)
    run = subprocess.run(
        [
            "xvfb-run",
            "-a",
            "-s",
            "-screen 0 1280x800x24",
            "blender",
            "--enable-event-simulate",
            "--python",
            str(script),
        ],
        env={**blender_home, "TMPDIR": str(tmp_path)},  # where Blender saves quit.blend as it quits
        cwd=tmp_path,
        capture_output=True,
        text=True,
        timeout=300,
    )
    assert "WINDOWED TEST PASSED" in run.stdout, run.stdout[-6000:] + run.stderr[-6000:]
