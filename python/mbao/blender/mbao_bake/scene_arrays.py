"""Blender's scene as the arrays of one mbao.Mesh (SPEC 9): the selected mesh
objects to bake and everything else visible as occluders (instances of
collections and particles too), each evaluated (modifiers applied) and in
world space."""

import dataclasses

import bpy
import numpy as np

# The object types that evaluate to a mesh: each can occlude.
GEOMETRY_TYPES = {"MESH", "CURVE", "SURFACE", "META", "FONT"}


class BakeInputError(ValueError):
    """What the scene or the settings lack for a bake, in words for the user."""


@dataclasses.dataclass
class Part:
    """One object's share of the arrays: its vertices (per vertex) or its face
    corners (per texel) are rows first .. first + count - 1."""

    obj: bpy.types.Object
    first: int
    count: int


@dataclasses.dataclass
class BakeInput:
    arrays: dict  # vertices, indices, normals, texcoords (per texel only), triangles
    targets: list  # a Part per object baked
    image: object  # the image baked into, or None per vertex


@dataclasses.dataclass
class _Evaluated:
    """An object's evaluated mesh as arrays, in world space."""

    positions: np.ndarray  # (V, 3)
    normals: np.ndarray  # (V, 3), zero where a face beside the vertex is flat-shaded
    triangles: np.ndarray  # (T, 3) vertex indices, counter-clockwise seen from the front in world space
    corners: np.ndarray  # (T, 3) face-corner (loop) indices of the same triangles
    corner_vertices: np.ndarray  # (L,) each face corner's vertex
    uvs: object  # (L, 2) the active UV map's, or None where the mesh has none


def bake_input(context, settings):
    """The arrays of a bake of the selected mesh objects among the visible ones,
    or BakeInputError naming what is missing."""
    targets = [obj for obj in context.selected_objects if obj.type == "MESH"]
    if not targets:
        raise BakeInputError("select a mesh object to bake")
    _refuse_shared_meshes(targets)
    depsgraph = context.evaluated_depsgraph_get()
    per_texel = settings["target"] == "IMAGE"
    image = _image_of(targets, settings["image"]) if per_texel else None
    placed = [(obj, obj.evaluated_get(depsgraph), obj.matrix_world) for obj in targets]
    placed += [(None, evaluated, matrix) for evaluated, matrix in _occluders(depsgraph, targets)]
    pieces, parts, triangles, base, first = [], [], [], 0, 0
    for obj, evaluated_object, matrix in placed:
        evaluated = _evaluated(evaluated_object, matrix)
        baked = obj is not None
        if baked:
            _refuse_unbakeable(obj, evaluated, per_texel)
            piece = _per_corner(evaluated) if per_texel else _per_vertex(evaluated)
            parts.append(Part(obj, base, len(piece["vertices"])))
            triangles.append(np.arange(first, first + len(piece["indices"]), dtype=np.uint32))
        else:
            piece = _occluding(evaluated, per_texel)
        piece["indices"] = piece["indices"] + base
        pieces.append(piece)
        base += len(piece["vertices"])
        first += len(piece["indices"])
    arrays = {name: np.concatenate([p[name] for p in pieces]) for name in pieces[0]}
    if not arrays["normals"].any():  # all flat-shaded: the geometric normals, as mbao takes no normals
        arrays["normals"] = None
    arrays["triangles"] = np.concatenate(triangles)
    return BakeInput(arrays, parts, image)


def _occluders(depsgraph, targets):
    """(evaluated object, world matrix) of everything visible but the targets
    themselves: objects, and the instances of collections and particles."""
    found = []
    for instance in depsgraph.object_instances:
        obj = instance.object
        if obj.type not in GEOMETRY_TYPES:
            continue
        if not instance.is_instance and (obj.original in targets or not instance.show_self):
            continue
        found.append((obj, instance.matrix_world.copy()))  # an instance's data lasts only its iteration
    return found


def _refuse_shared_meshes(targets):
    by_mesh = {}
    for obj in targets:
        by_mesh.setdefault(obj.data.name, []).append(obj.name)
    shared = next((names for names in by_mesh.values() if len(names) > 1), None)
    if shared:
        raise BakeInputError(
            f"objects {', '.join(shared)} share one mesh, which can hold only one bake: select one "
            f"of them, or make the mesh single-user"
        )


def _refuse_unbakeable(obj, evaluated, per_texel):
    if len(evaluated.triangles) == 0:
        raise BakeInputError(f"object {obj.name} has no faces to bake")
    if per_texel and evaluated.uvs is None:
        raise BakeInputError(
            f"object {obj.name} has no UV map to bake the image into: add one, or bake to a " f"color attribute"
        )
    if not per_texel and len(evaluated.positions) != len(obj.data.vertices):
        raise BakeInputError(
            f"object {obj.name}'s modifiers make {len(evaluated.positions)} vertices of its "
            f"{len(obj.data.vertices)}, so its vertices cannot hold their values: apply the "
            f"modifiers, or bake to an image"
        )


def _image_of(targets, name):
    """The image a per-texel bake writes: the one named, else the active Image
    Texture node's of the objects' active materials (one image for all)."""
    if name:
        image = bpy.data.images.get(name)
        if image is None:
            raise BakeInputError(f"there is no image named {name!r}")
    else:
        images = {_active_node_image(obj) for obj in targets}
        if None in images:
            obj = next(obj for obj in targets if _active_node_image(obj) is None)
            raise BakeInputError(
                f"object {obj.name} has no image to bake into: name one in Image, or make an Image "
                f"Texture node with an image active in its material"
            )
        if len(images) > 1:
            raise BakeInputError(
                "the selected objects' active Image Texture nodes show different images; bake "
                "them one image at a time, or name one image in Image"
            )
        image = images.pop()
    if image.size[0] == 0 or image.size[1] == 0:
        raise BakeInputError(f"image {image.name} has no pixels (its file cannot be read?)")
    return image


def _active_node_image(obj):
    material = obj.active_material
    if material is None or not material.use_nodes:
        return None
    node = material.node_tree.nodes.active
    return node.image if node is not None and node.type == "TEX_IMAGE" else None


def _evaluated(evaluated, matrix):
    """An evaluated object's mesh as arrays, placed by `matrix`."""
    mesh = evaluated.to_mesh()
    try:
        mesh.calc_loop_triangles()
        return _arrays_of(mesh, np.array(matrix, dtype=np.float64))
    finally:
        evaluated.to_mesh_clear()


def _arrays_of(mesh, matrix):
    positions = _read(mesh.vertices, "co", 3)
    normals = _read(mesh.vertices, "normal", 3)
    triangles = _read(mesh.loop_triangles, "vertices", 3, np.int64)
    corners = _read(mesh.loop_triangles, "loops", 3, np.int64)
    corner_vertices = _read(mesh.loops, "vertex_index", 1, np.int64)[:, 0]
    smooth_faces = _read(mesh.polygons, "use_smooth", 1, bool)[:, 0]
    triangle_faces = _read(mesh.loop_triangles, "polygon_index", 1, np.int64)[:, 0]
    # A vertex keeps its normal only where every face beside it is smooth-shaded.
    flat = np.zeros(len(positions), bool)
    flat[triangles[~smooth_faces[triangle_faces]].ravel()] = True
    linear, offset = matrix[:3, :3], matrix[:3, 3]
    normals = normals @ np.linalg.inv(linear)  # by the inverse transpose, row vectors
    normals /= np.maximum(np.linalg.norm(normals, axis=1, keepdims=True), 1e-300)
    normals[flat] = 0.0
    if np.linalg.det(linear) < 0:  # mirrored: its front faces are wound the other way in world space
        triangles, corners = triangles[:, ::-1], corners[:, ::-1]
    uv_layer = mesh.uv_layers.active
    uvs = _read(uv_layer.data, "uv", 2) if uv_layer is not None else None
    return _Evaluated(positions @ linear.T + offset, normals, triangles, corners, corner_vertices, uvs)


# The array type foreach_get fills for each type asked for: Blender's own.
_BLENDER_TYPES = {np.float64: np.float32, np.int64: np.int32, bool: bool}


def _read(collection, attribute, width, dtype=np.float64):
    """A Blender collection's attribute as a (len, width) array, by foreach_get."""
    flat = np.empty(len(collection) * width, dtype=_BLENDER_TYPES[dtype])
    if len(collection):
        collection.foreach_get(attribute, flat)
    return flat.reshape(-1, width).astype(dtype)


def _per_vertex(evaluated):
    return {"vertices": evaluated.positions, "indices": evaluated.triangles, "normals": evaluated.normals}


def _occluding(evaluated, per_texel):
    """An occluder's arrays: its vertices as they are, with UVs of no area where the bake is per texel
    (it is baked nowhere, but the mesh's UVs are one per vertex)."""
    piece = _per_vertex(evaluated)
    if per_texel:
        piece["texcoords"] = np.zeros((len(evaluated.positions), 2))
    return piece


def _per_corner(evaluated):
    """A vertex per face corner, so that a UV seam splits vertices as it splits corners."""
    at = evaluated.corner_vertices
    uvs = evaluated.uvs if evaluated.uvs is not None else np.zeros((len(at), 2))
    return {
        "vertices": evaluated.positions[at],
        "indices": evaluated.corners,
        "normals": evaluated.normals[at],
        "texcoords": uvs,
    }
