"""docs/blender_panel.png: Blender's window with the add-on's panel, and a monkey
on a floor baked at b = 2, shown by their color attributes. Run, with the add-on installed
(`.venv/bin/python -m mbao blender --install`), as

    xvfb-run -a -s "-screen 0 1280x800x24" blender --python docs/blender_panel.py
"""

import os

import bpy

OUTPUT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "blender_panel.png")


def window_areas():
    window = bpy.context.window_manager.windows[0]
    return window, {area.type: area for area in window.screen.areas}


def scene():
    for obj in list(bpy.data.objects):
        bpy.data.objects.remove(obj)
    bpy.ops.mesh.primitive_plane_add(size=6)
    bpy.ops.object.mode_set(mode="EDIT")
    bpy.ops.mesh.subdivide(number_cuts=40)  # vertices enough to hold the monkey's shadow
    bpy.ops.object.mode_set(mode="OBJECT")
    bpy.ops.mesh.primitive_monkey_add(location=(0, 0, 0.75), rotation=(-0.5, 0, 0.4))
    bpy.ops.object.modifier_add(type="SUBSURF")
    bpy.ops.object.modifier_apply(modifier="Subdivision")
    bpy.ops.object.shade_smooth()
    settings = bpy.context.scene.mbao_bake
    settings.bounces, settings.samples, settings.max_distance = 2, 256, 1.0
    bpy.ops.object.select_all(action="SELECT")
    bpy.ops.mbao.bake(bounces=2, samples=256, max_distance=1.0)
    window, areas = window_areas()
    view = areas["VIEW_3D"]
    view.spaces.active.shading.color_type = "VERTEX"
    view.spaces.active.shading.light = "FLAT"  # the bake alone
    with bpy.context.temp_override(window=window, area=view, region=view.regions[-1]):
        bpy.ops.view3d.view_selected()
    bpy.ops.object.select_all(action="DESELECT")
    areas["PROPERTIES"].spaces.active.context = "RENDER"
    return None


def scroll_to_the_panel():
    window, areas = window_areas()
    properties = areas["PROPERTIES"]
    region = next(r for r in properties.regions if r.type == "WINDOW")
    with bpy.context.temp_override(window=window, area=properties, region=region):
        for _ in range(20):
            bpy.ops.view2d.scroll_down(deltay=200)
    return None


def shoot():
    window, _ = window_areas()
    with bpy.context.temp_override(window=window):
        bpy.ops.screen.screenshot(filepath=OUTPUT)
    bpy.ops.wm.quit_blender()


bpy.context.preferences.view.show_splash = False
bpy.app.timers.register(scene, first_interval=0.5)
bpy.app.timers.register(scroll_to_the_panel, first_interval=8.0)
bpy.app.timers.register(shoot, first_interval=10.0)
