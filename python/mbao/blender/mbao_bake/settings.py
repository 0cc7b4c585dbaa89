"""The bake's settings, one table: the operator's properties, the panel's, and
the add-on's preferences. mbao.bake's arguments keep its names and defaults
(a test holds them equal); the rest say where the result goes (SPEC 9)."""

import bpy
from bpy.props import BoolProperty, EnumProperty, FloatProperty, IntProperty, StringProperty


def bake_properties():
    """{name: property} of a bake, made anew for each class that holds them."""
    return {
        "target": EnumProperty(
            name="Target",
            default="COLOR_ATTRIBUTE",
            items=[
                ("COLOR_ATTRIBUTE", "Color Attribute", "A value per vertex, in a color attribute of each mesh"),
                ("IMAGE", "Image", "A value per texel, in an image, through the active UV map"),
            ],
        ),
        "attribute": StringProperty(
            name="Attribute", default="mbao_ao", description="The color attribute written (a float color)"
        ),
        "domain": EnumProperty(
            name="Domain",
            default="POINT",
            items=[
                ("POINT", "Vertex", "One value per vertex"),
                ("CORNER", "Face Corner", "Each corner takes its vertex's value"),
            ],
        ),
        "image": StringProperty(
            name="Image",
            default="",
            description="The image written, at its own size. Empty: the active Image Texture "
            "node of each object's active material, as Cycles' bake takes",
        ),
        "bounces": IntProperty(
            name="Bounces",
            default=1,
            soft_min=1,
            soft_max=8,
            description="Bounces of light between surfaces (b), in [1, 16] by the estimator",
        ),
        "samples": IntProperty(
            name="Samples",
            default=256,
            soft_min=2,
            soft_max=65536,
            description="Estimates per vertex or texel, in [2, 65536]",
        ),
        "rho": FloatProperty(
            name="Albedo", default=1.0, soft_min=0.0, soft_max=1.0, description="The surfaces' albedo (rho), in [0, 1]"
        ),
        "max_distance": FloatProperty(
            name="Distance",
            default=0.0,
            soft_min=0.0,
            unit="LENGTH",
            description="How far an occluder counts, in the scene's units; 0: no limit",
        ),
        "estimator": EnumProperty(
            name="Estimator",
            default="PATH",
            items=[
                ("PATH", "Path", "Paths of `bounces` segments"),
                ("BRANCHING", "Branching", "Directions at every hit"),
            ],
        ),
        "seed": IntProperty(name="Seed", default=0, min=0, description="The random numbers' seed"),
        "padding": IntProperty(
            name="Padding",
            default=4,
            soft_min=0,
            soft_max=64,
            description="Texels beyond the covered ones that take their value, in [0, 64]",
        ),
        "standard_error": BoolProperty(
            name="Standard Error",
            default=False,
            description="Keep each value's standard error too, in an attribute or "
            'image named as the result\'s, with "_standard_error"',
        ),
        "save": BoolProperty(
            name="Save Beside .blend",
            default=False,
            description="Save the image as a PNG beside the .blend file, not packed into it",
        ),
        "preview": BoolProperty(
            name="Preview Material",
            default=False,
            description="Give a baked object without a material one that shows the result",
        ),
    }


def bake_settings_of(holder):
    """{name: value} of each bake property that `holder` (the operator, the scene's settings) has."""
    return {name: getattr(holder, name) for name in bake_properties()}


BakeSettings = type("MBAO_PG_bake_settings", (bpy.types.PropertyGroup,), {"__annotations__": bake_properties()})


class Preferences(bpy.types.AddonPreferences):
    bl_idname = __package__

    run_in: EnumProperty(
        name="Run mbao",
        default="AUTO",
        items=[
            ("AUTO", "Automatic", "In Blender's process where its Python imports mbao, else as a child process"),
            ("BLENDER", "In Blender", "In a thread of Blender's own process"),
            ("CHILD", "Child Process", "In mbao's own Python, as a child process"),
        ],
    )

    def draw(self, context):
        self.layout.prop(self, "run_in")
