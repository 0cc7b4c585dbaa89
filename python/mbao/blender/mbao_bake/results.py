"""A finished bake written into Blender (SPEC 9): a color attribute per object,
or an image, each whole at once, so that nothing is left half-written."""

import bpy
import numpy as np

STANDARD_ERROR_SUFFIX = "_standard_error"


def write(bake_input, result, settings):
    """Writes `result` where `settings` say; returns what was written, for the report."""
    image = bake_input.image
    if image is not None:
        written = _write_images(image, result, settings)
    else:
        written = _write_attributes(bake_input.targets, result, settings)
    if settings["preview"]:
        for part in bake_input.targets:
            _preview_material(
                part.obj,
                _source_node("ShaderNodeTexImage", image=image)
                if image is not None
                else _source_node("ShaderNodeAttribute", attribute_name=settings["attribute"]),
            )
    return written


def check_writable(bake_input, settings, blend_path):
    """Refuses, before any ray is traced, what the result could not be written to."""
    if bake_input.image is not None and settings["save"] and not blend_path:
        raise ValueError("Save Beside .blend needs the .blend saved first")
    if bake_input.image is None and not settings["attribute"]:
        raise ValueError("name the color attribute to bake into")


def _write_attributes(targets, result, settings):
    name, domain = settings["attribute"], settings["domain"]
    for part in targets:
        mesh = part.obj.data
        values = slice(part.first, part.first + part.count)
        _set_color_attribute(mesh, name, domain, result["values"][values])
        if settings["standard_error"]:
            _set_color_attribute(mesh, name + STANDARD_ERROR_SUFFIX, domain, result["standard_error"][values])
    return f"color attribute {name!r} of {len(targets)} object{'s' if len(targets) != 1 else ''}"


def _set_color_attribute(mesh, name, domain, per_vertex):
    if domain == "CORNER":
        corner_vertices = np.empty(len(mesh.loops), np.int32)
        mesh.loops.foreach_get("vertex_index", corner_vertices)
        per_vertex = per_vertex[corner_vertices]
    attribute = mesh.color_attributes.get(name)
    if attribute is not None and (attribute.domain != domain or attribute.data_type != "FLOAT_COLOR"):
        mesh.color_attributes.remove(attribute)
        attribute = None
    if attribute is None:
        attribute = mesh.color_attributes.new(name, "FLOAT_COLOR", domain)
    attribute.data.foreach_set("color", _rgba(per_vertex).ravel())
    mesh.color_attributes.active_color = attribute
    mesh.update()


def _rgba(values):
    rgba = np.ones(values.shape + (4,), np.float32)
    rgba[..., :3] = values[..., None]
    return rgba


def _write_images(image, result, settings):
    _set_pixels(image, result["values"], settings)
    written = f"image {image.name!r}"
    if settings["standard_error"]:
        error_name = image.name + STANDARD_ERROR_SUFFIX
        error_image = bpy.data.images.get(error_name)
        if error_image is None or tuple(error_image.size) != tuple(image.size):
            if error_image is not None:
                bpy.data.images.remove(error_image)
            error_image = bpy.data.images.new(error_name, image.size[0], image.size[1], float_buffer=True)
        _set_pixels(error_image, result["standard_error"], settings)
        written += f" and {error_name!r}"
    return written


def _set_pixels(image, values, settings):
    """Rows from v = 0 up, as Blender keeps pixels and as the bake's rows run.
    The values are data, not colours: stored as they are (SPEC 9)."""
    image.colorspace_settings.name = "Non-Color"
    image.pixels.foreach_set(_rgba(values).ravel())
    image.update()
    if settings["save"]:
        image.filepath_raw = f"//{bpy.path.clean_name(image.name)}.png"
        image.file_format = "PNG"
        image.save()
    else:
        image.pack()


def _preview_material(obj, source_node):
    """A material showing the bake, for an object that has none."""
    if any(slot.material is not None for slot in obj.material_slots):
        return
    material = bpy.data.materials.new(f"{obj.name} AO")
    material.use_nodes = True
    nodes, links = material.node_tree.nodes, material.node_tree.links
    shader = nodes.get("Principled BSDF")
    links.new(source_node(nodes).outputs["Color"], shader.inputs["Base Color"])
    obj.data.materials.append(material)


def _source_node(node_type, **settings):
    """What makes a preview material's source node: a node of `node_type` with `settings`."""

    def node_in(nodes):
        node = nodes.new(node_type)
        for name, value in settings.items():
            setattr(node, name, value)
        return node

    return node_in
