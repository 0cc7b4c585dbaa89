"""The panel in Properties > Render: the scene's bake settings and the button."""

import bpy

from .settings import bake_properties


class MBAO_PT_bake(bpy.types.Panel):
    bl_label = "mbao Multi-Bounce AO"
    bl_space_type = "PROPERTIES"
    bl_region_type = "WINDOW"
    bl_context = "render"

    def draw(self, context):
        layout = self.layout
        layout.use_property_split = True
        settings = context.scene.mbao_bake
        layout.prop(settings, "target")
        if settings.target == "COLOR_ATTRIBUTE":
            layout.prop(settings, "attribute")
            layout.prop(settings, "domain")
        else:
            layout.prop_search(settings, "image", bpy.data, "images")
            layout.prop(settings, "padding")
            layout.prop(settings, "save")
        for name in ("bounces", "samples", "rho", "max_distance", "estimator", "seed", "standard_error", "preview"):
            layout.prop(settings, name)
        button = layout.operator("mbao.bake", icon="RENDER_STILL")
        for name in bake_properties():
            setattr(button, name, getattr(settings, name))
