"""mbao's Blender add-on: multi-bounce ambient occlusion baked into a color
attribute or an image (SPEC 9), by mbao.bake. Install it with
`python -m mbao blender --install`."""

bl_info = {
    "name": "mbao",
    "description": "Bake multi-bounce ambient occlusion into color attributes or images",
    "author": "the mbao developers",
    "version": (0, 1, 0),
    "blender": (3, 4, 0),
    "location": "Properties > Render > mbao Multi-Bounce AO",
    "category": "Render",
}

import bpy  # noqa: E402 (Blender reads bl_info before anything is imported)

from .operator import MBAO_OT_bake  # noqa: E402
from .panel import MBAO_PT_bake  # noqa: E402
from .settings import BakeSettings, Preferences  # noqa: E402

CLASSES = (Preferences, BakeSettings, MBAO_OT_bake, MBAO_PT_bake)


def register():
    for cls in CLASSES:
        bpy.utils.register_class(cls)
    bpy.types.Scene.mbao_bake = bpy.props.PointerProperty(type=BakeSettings)


def unregister():
    del bpy.types.Scene.mbao_bake
    for cls in reversed(CLASSES):
        bpy.utils.unregister_class(cls)
