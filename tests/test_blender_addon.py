"""The Blender add-on (SPEC 9), in Debian's Blender, headless: each test runs a
script in `blender -b` with the add-on installed by `python -m mbao blender
--install` into a folder of the test's own. The scripts assert; a failed
assertion is Blender's exit status 1 and its output here."""

import os
import subprocess
import sys
import textwrap
from pathlib import Path

import pytest

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


@pytest.fixture(scope="module")
def blender_home(tmp_path_factory):
    """A user folder of Blender's with the add-on installed and enabled, by the README's command."""
    home = tmp_path_factory.mktemp("blender")
    environment = dict(os.environ, BLENDER_USER_SCRIPTS=str(home / "scripts"), BLENDER_USER_CONFIG=str(home / "config"))
    installed = subprocess.run([sys.executable, "-m", "mbao", "blender", "--install"], env=environment,
                               capture_output=True, text=True, timeout=300)
    assert installed.returncode == 0, installed.stderr
    assert (home / "scripts" / "addons" / "mbao_bake" / "location.json").is_file()
    return environment


def blender(environment, tmp_path, body):
    """Runs PRELUDE + body in Blender, with the user's preferences (the add-on enabled)."""
    script = tmp_path / "script.py"
    script.write_text(PRELUDE + textwrap.dedent(body))
    run = subprocess.run(["blender", "-b", "--python-exit-code", "1", "--python", str(script)], env=environment,
                         cwd=tmp_path, capture_output=True, text=True, timeout=600)
    assert run.returncode == 0, run.stdout[-6000:] + run.stderr[-6000:]
    return run.stdout


def test_the_addon_registers_and_unregisters(blender_home, tmp_path):
    blender(blender_home, tmp_path, """
        import addon_utils
        assert addon_utils.check("mbao_bake") == (True, True)  # enabled by the installer, and loaded
        assert hasattr(bpy.types, "MBAO_OT_bake") and hasattr(bpy.types.Scene, "mbao_bake")
        assert bpy.types.MBAO_PT_bake.bl_context == "render"
        addon_utils.disable("mbao_bake")
        assert not hasattr(bpy.types, "MBAO_OT_bake") and not hasattr(bpy.types.Scene, "mbao_bake")
        addon_utils.enable("mbao_bake")
        assert hasattr(bpy.types, "MBAO_OT_bake")
    """)


def test_the_operators_settings_are_mbao_bakes(blender_home, tmp_path):
    """Named as mbao.bake's arguments, with its defaults: the estimator's in
    Blender's capitals, and no radius as a distance of 0."""
    blender(blender_home, tmp_path, """
        import inspect
        parameters = inspect.signature(mbao.bake).parameters
        properties = bpy.ops.mbao.bake.get_rna_type().properties
        for name in ("bounces", "samples", "rho", "seed", "padding"):
            assert properties[name].default == parameters[name].default, name
        assert properties["estimator"].default == parameters["estimator"].default.upper()
        assert parameters["max_distance"].default is None and properties["max_distance"].default == 0.0
        scene_settings = bpy.context.scene.mbao_bake.bl_rna.properties
        assert {p.identifier for p in scene_settings} - {"rna_type", "name"} == \
            {p.identifier for p in properties} - {"rna_type"}
    """)


@pytest.mark.parametrize("run_in", ["BLENDER", "CHILD"])
def test_a_vertex_bake_is_mbao_bakes_values(blender_home, tmp_path, run_in):
    """The cube baked among the plane: its color attribute holds mbao.bake's
    values of the cube's triangles, the plane occluding, bit for bit, in
    Blender's process and in a child process alike; the standard error beside."""
    blender(blender_home, tmp_path, f"""
        bpy.context.preferences.addons["mbao_bake"].preferences.run_in = {run_in!r}
        cube, plane = cube_on_a_plane()
        result = bpy.ops.mbao.bake(bounces=2, samples=32, seed=5, max_distance=3.0, standard_error=True)
        assert result == {{"FINISHED"}}, result
        vertices = np.concatenate([world_vertices(cube), world_vertices(plane)])
        indices = np.concatenate([triangles(cube), triangles(plane) + len(cube.data.vertices)])
        expected = mbao.bake(mbao.Mesh(vertices, indices), bounces=2, samples=32, seed=5, max_distance=3.0,
                             triangles=np.arange(len(triangles(cube))), progress=False)
        n = len(cube.data.vertices)
        baked = colors(cube, "mbao_ao")
        assert np.array_equal(baked[:, 0], expected.values[:n]), abs(baked[:, 0] - expected.values[:n]).max()
        assert np.array_equal(baked[:, 1], baked[:, 0]) and np.all(baked[:, 3] == 1.0)
        assert np.array_equal(colors(cube, "mbao_ao_standard_error")[:, 0], expected.standard_error[:n])
        assert baked[:, 0].min() < 0.9 and baked[:, 0].max() == 1.0  # the foot is occluded, the top open
        assert "mbao_ao" not in plane.data.color_attributes

        assert bpy.ops.mbao.bake(bounces=2, samples=32, seed=5, max_distance=3.0, attribute="corners",
                                 domain="CORNER", preview=True) == {{"FINISHED"}}
        loop_vertices = np.empty(len(cube.data.loops), np.int32)
        cube.data.loops.foreach_get("vertex_index", loop_vertices)
        assert np.array_equal(colors(cube, "corners")[:, 0], baked[loop_vertices, 0])
        nodes = cube.active_material.node_tree.nodes  # the preview: the attribute as the base colour
        assert [n.attribute_name for n in nodes if n.type == "ATTRIBUTE"] == ["corners"]
    """)


def test_a_mirrored_object_is_baked_on_its_front(blender_home, tmp_path):
    """The plane scaled by -1 along x still faces up in Blender; baked under the
    cube, it is occluded (its winding is flipped back in world space, else it
    would face down, onto nothing)."""
    blender(blender_home, tmp_path, """
        cube, plane = cube_on_a_plane(cuts=1)
        plane.scale = (-1.0, 1.0, 1.0)
        select(plane)
        assert bpy.ops.mbao.bake(samples=16) == {"FINISHED"}
        assert colors(plane, "mbao_ao")[:, 0].min() < 1.0
    """)


def test_what_is_visible_occludes_instances_included(blender_home, tmp_path):
    """A hidden cube over the plane occludes nothing; a collection's instance
    there does, as Blender shows it, though its source lies far away."""
    blender(blender_home, tmp_path, """
        cube, plane = cube_on_a_plane(cuts=1)
        cube.hide_set(True)
        select(plane)
        assert bpy.ops.mbao.bake(samples=16, max_distance=2.0) == {"FINISHED"}
        assert colors(plane, "mbao_ao")[:, 0].min() == 1.0
        shelf = bpy.data.collections.new("shelf")
        bpy.context.scene.collection.children.link(shelf)
        bpy.ops.mesh.primitive_cube_add(location=(100.0, 0.0, 1.0))
        source = bpy.context.active_object
        for collection in source.users_collection:
            collection.objects.unlink(source)
        shelf.objects.link(source)
        shelf.instance_offset = (100.0, 0.0, 0.0)
        bpy.context.view_layer.layer_collection.children["shelf"].exclude = True  # only its instance is shown
        bpy.ops.object.collection_instance_add(collection="shelf", location=(0.0, 0.0, 0.0))
        select(plane)
        assert bpy.ops.mbao.bake(samples=16, max_distance=2.0) == {"FINISHED"}
        assert colors(plane, "mbao_ao")[:, 0].min() < 1.0
    """)


def test_an_image_bake_fills_the_covered_texels_and_pads_the_rest(blender_home, tmp_path):
    """The floor, its UVs shrunk to the middle of a 32 x 32 float image, baked
    with padding 2: the image is mbao.bake's texture of the floor's UVs, bit for
    bit (covered texels, their dilation, and 1 beyond); saved as an 8-bit PNG
    beside the .blend, it reads back within the PNG's rounding."""
    blender(blender_home, tmp_path, """
        cube, plane = cube_on_a_plane(cuts=1)
        uvs = np.empty(len(plane.data.loops) * 2, np.float32)
        plane.data.uv_layers.active.data.foreach_get("uv", uvs)
        uvs = 0.25 + 0.5 * uvs
        plane.data.uv_layers.active.data.foreach_set("uv", uvs)
        plane.data.update()  # tells the depsgraph, which the add-on reads
        image = bpy.data.images.new("ao", 32, 32, float_buffer=True)
        select(plane)
        assert bpy.ops.mbao.bake(target="IMAGE", image="ao", samples=16, padding=2, preview=True) == {"FINISHED"}
        assert [n.image for n in plane.active_material.node_tree.nodes if n.type == "TEX_IMAGE"] == [image]
        pixels = np.empty(32 * 32 * 4, np.float32)
        image.pixels.foreach_get(pixels)
        pixels = pixels.reshape(32, 32, 4)

        loop_vertices = np.empty(len(plane.data.loops), np.int32)
        plane.data.loops.foreach_get("vertex_index", loop_vertices)
        corners = np.empty(len(plane.data.loop_triangles) * 3, np.int32)
        plane.data.loop_triangles.foreach_get("loops", corners)
        cube_vertices = world_vertices(cube)
        vertices = np.concatenate([world_vertices(plane)[loop_vertices], cube_vertices])
        indices = np.concatenate([corners.reshape(-1, 3), triangles(cube) + len(loop_vertices)])
        texcoords = np.concatenate([uvs.reshape(-1, 2), np.zeros((len(cube_vertices), 2))])
        expected = mbao.bake(mbao.Mesh(vertices, indices, texcoords=texcoords), target="texture", samples=16,
                             padding=2, resolution=32, triangles=np.arange(len(corners) // 3), progress=False)
        texture = expected.textures[0]
        assert np.array_equal(pixels[..., 0], texture.image)
        assert texture.coverage[8:24, 8:24].all() and texture.coverage.sum() == 16 * 16
        assert pixels[6, 16, 0] == texture.image[8, 16] and pixels[0, 0, 0] == 1.0  # padded; beyond the padding
        assert texture.image[8:24, 8:24].min() < 0.9  # the cube's foot

        bpy.ops.wm.save_as_mainfile(filepath=os.path.abspath("scene.blend"))
        select(plane)
        assert bpy.ops.mbao.bake(target="IMAGE", image="ao", samples=16, padding=2, save=True) == {"FINISHED"}
        assert image.filepath_raw == "//ao.png"
        saved = bpy.data.images.load(os.path.abspath("ao.png"))
        saved.colorspace_settings.name = "Non-Color"
        back = np.empty(32 * 32 * 4, np.float32)
        saved.pixels.foreach_get(back)
        assert np.abs(back.reshape(32, 32, 4)[..., 0] - texture.image).max() <= 0.5 / 255 + 1e-6
    """)


def test_bad_settings_are_reported_not_raised(blender_home, tmp_path):
    """Each refusal is an error report naming the problem (a RuntimeError
    "Error: ..." to a script), never a traceback from inside the add-on."""
    blender(blender_home, tmp_path, """
        cube, plane = cube_on_a_plane(cuts=1)
        refused("samples must be in [2, 65536], got 0", samples=0)
        refused("bounces", bounces=0)
        bpy.ops.object.select_all(action="DESELECT")
        refused("select a mesh object to bake")
        select(cube)
        refused("has no image to bake into", target="IMAGE")
        refused("there is no image named 'nothing'", target="IMAGE", image="nothing")
        bpy.data.images.new("ao", 8, 8)
        refused("Save Beside .blend needs the .blend saved first", target="IMAGE", image="ao", save=True)
        twin = cube.copy()  # a linked duplicate: the same mesh
        bpy.context.collection.objects.link(twin)
        select(cube, twin)
        refused("share one mesh")
        select(cube)
        cube.data.uv_layers.remove(cube.data.uv_layers[0])
        refused(f"object {cube.name} has no UV map", target="IMAGE", image="ao")
        bpy.ops.object.modifier_add(type="SUBSURF")
        refused("modifiers make", target="COLOR_ATTRIBUTE")
        assert "mbao_ao" not in cube.data.color_attributes
    """)


@pytest.mark.parametrize("run_in", ["BLENDER", "CHILD"])
def test_cancelling_leaves_the_attribute_as_it_was(blender_home, tmp_path, run_in):
    """Esc cancels the bake's job: here as the bake starts, in either place it
    runs. Nothing is written: the attribute keeps its values."""
    blender(blender_home, tmp_path, f"""
        import mbao_bake.jobs
        bpy.context.preferences.addons["mbao_bake"].preferences.run_in = {run_in!r}
        cube, plane = cube_on_a_plane()
        before = bpy.ops.mbao.bake(samples=4)
        kept = colors(cube, "mbao_ao").copy()
        started = mbao_bake.jobs.BakeJob.__init__

        def start_then_cancel(self, *arguments):
            started(self, *arguments)
            self.cancel()

        mbao_bake.jobs.BakeJob.__init__ = start_then_cancel
        assert bpy.ops.mbao.bake(samples=65536, seed=1) == {{"CANCELLED"}}
        assert np.array_equal(colors(cube, "mbao_ao"), kept)
    """)


def test_the_zip_installs_from_blenders_preferences(tmp_path):
    """`python -m mbao blender --zip` writes what Preferences > Add-ons > Install
    takes; installed and enabled so, it bakes."""
    archive = tmp_path / "mbao_bake.zip"
    written = subprocess.run([sys.executable, "-m", "mbao", "blender", "--zip", str(archive)], capture_output=True,
                             text=True, timeout=60)
    assert written.returncode == 0, written.stderr
    home = tmp_path / "home"
    environment = dict(os.environ, BLENDER_USER_SCRIPTS=str(home / "scripts"), BLENDER_USER_CONFIG=str(home / "config"))
    blender(environment, tmp_path, f"""
        bpy.ops.preferences.addon_install(filepath={str(archive)!r})
        bpy.ops.preferences.addon_enable(module="mbao_bake")
        cube, plane = cube_on_a_plane(cuts=1)
        assert bpy.ops.mbao.bake(samples=4) == {{"FINISHED"}}
        assert "mbao_ao" in cube.data.color_attributes
    """)


def test_the_command_says_what_is_wrong(tmp_path):
    run = subprocess.run([sys.executable, "-m", "mbao", "blender", "--install", "--blender", str(tmp_path / "none")],
                         capture_output=True, text=True, timeout=60)
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
    run = subprocess.run(["xvfb-run", "-a", "-s", "-screen 0 1280x800x24", "blender", "--enable-event-simulate",
                          "--python", str(script)], env=blender_home, cwd=tmp_path, capture_output=True, text=True,
                         timeout=300)
    assert "WINDOWED TEST PASSED" in run.stdout, run.stdout[-6000:] + run.stderr[-6000:]
