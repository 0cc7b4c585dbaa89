"""A baked glTF file: the input with everything kept, plus the bake (SPEC 6):
occlusion textures per material, or an _OCCLUSION attribute per primitive."""

import copy
import os
import tempfile
from typing import Any

import numpy as np

from . import _checks
from ._gltf import WRAP_CODES, GltfDocument
from ._types import PathLike
from .bake import Bake, bake
from .scene import is_gltf_path, load, load_with_base_colors

FLOAT, SCALAR, TRIANGLES = 5126, "SCALAR", 4
_NUMPY_TYPES = {5120: "<i1", 5121: "<u1", 5122: "<i2", 5123: "<u2", 5125: "<u4", 5126: "<f4"}


def bake_file(
    input: PathLike,
    output: PathLike,
    *,
    target: str = "vertices",
    bit_depth: int = 8,
    vertex_colors: bool = False,
    **settings: Any,
) -> Bake:
    """Bakes the glTF file `input` as mbao.bake does and writes `output`: the
    same document, every node, mesh, material, texture, animation, skin,
    extension and extra kept as it was, plus the bake:

    target="texture": each baked material's occlusionTexture points at a new
        PNG (linear values, AO in R copied to G and B, `bit_depth` 8 or 16 bits)
        with texCoord the UV set baked into; an existing occlusion texture is
        replaced (its strength kept), the rest of the material kept; triangles
        without a material get a new one. With texcoord="generate" the new UV
        set is added as the next free TEXCOORD_n, the vertices on the charts'
        seams split (every attribute copied along), the triangles in their order.
    target="vertices": a float attribute _OCCLUSION (glTF's prefix for an
        application's own attributes) on every primitive; a mesh that several
        nodes place gets a copy per node, since its AO depends on where it stands.
        vertex_colors=True also multiplies the AO into COLOR_0 (made where a
        primitive has none), for viewers that show no _OCCLUSION; but glTF's
        COLOR_0 darkens direct light too, which occlusion should not.

    output is .glb where input is, else .gltf (relative URIs rewritten for its
    folder; new data in data URIs). An input of another format mbao.load reads
    (OBJ, PLY, FBX, ...) is written as glTF, .glb or .gltf as output says: its
    triangles in world space as one mesh, a primitive per mesh the file placed
    with its material (by name, with its base colour and image) and UV sets,
    its normals where every vertex
    has one, plus the bake (its alpha masks cut the bake's rays all the same);
    one without UV sets bakes textures with texcoord="generate". settings:
    those of mbao.bake. Returns the mbao.Bake, with
    stats["replaced_occlusion"]: the materials whose occlusion texture was
    replaced.
    """
    vertex_colors = _checks.boolean("vertex_colors", vertex_colors)
    if vertex_colors and target != "vertices":
        raise ValueError('vertex_colors=True multiplies a per-vertex bake into COLOR_0: it needs target="vertices"')
    bit_depth = _checks.integer("bit_depth", bit_depth)
    if bit_depth not in (8, 16):
        raise ValueError(f"bit_depth must be 8 or 16, got {bit_depth}")
    if is_gltf_path(input):
        scene = load(input, texcoords=True)  # the loader's checks and errors first
        document = GltfDocument(input)
        document.check_output(output)  # before the bake, not after it
        result = bake(scene, target=target, **settings)
    else:
        baked = load_with_base_colors(input)
        if target == "texture" and settings.get("texcoord") != "generate" and not baked.uv_sets["sets"]:
            raise ValueError(f'{os.fspath(input)}: it has no UV sets; bake it with texcoord="generate"')
        document, scene = _converted(baked, input, output)
        result = bake(baked, target=target, **settings)
    meshes = _MeshesPerNode(document)
    if target == "texture":
        generated_sets = {}
        if settings.get("texcoord") == "generate":
            generated_sets = _add_generated_uvs(document, scene, result, meshes)
        replaced = _add_occlusion_textures(document, scene, result, bit_depth, generated_sets, meshes)
    else:
        replaced = []
        _add_vertex_occlusion(document, scene, result, meshes, vertex_colors)
    document.write(output)
    result.stats["replaced_occlusion"] = replaced
    return result


def _converted(scene, input, output):
    """A glTF document of `scene` (a file of another format: its triangles in
    world space, one mesh of a primitive per mesh the file placed, with its
    material, its normals where every vertex has one and its UV sets) in the
    output's container, and that document loaded as a scene: what the bake is
    written into, vertex for vertex and triangle for triangle."""
    normals = scene.normals
    if normals is not None and not np.allclose(np.linalg.norm(normals, axis=1), 1.0, atol=1e-3):
        normals = None  # a vertex without a normal: glTF's NORMAL has one for every vertex
    glb = os.fspath(output).lower().endswith(".glb")
    document = GltfDocument.of_mesh(input, scene.vertices, scene.indices, normals, glb, scene.uv_sets)
    document.check_output(output)
    with tempfile.TemporaryDirectory() as folder:
        path = os.path.join(folder, "converted.glb" if glb else "converted.gltf")
        document.write(path)
        return document, load(path, texcoords=True)


class _MeshesPerNode:
    """The mesh each node places in the output: the file's for the first node
    that places it, a copy of the file's for each node after (a bake depends on
    where the mesh stands)."""

    def __init__(self, document):
        self.document = document
        self.of_node, self.placed = {}, set()

    def primitive(self, placed):
        """The output's primitive for one of scene.uv_sets["primitives"]."""
        node, mesh = placed["node"], placed["mesh"]
        if node not in self.of_node:
            if mesh in self.placed:
                copied = copy.deepcopy(self.document.original["meshes"][mesh])
                self.document.doc["nodes"][node]["mesh"] = self.document.append("meshes", copied)
            self.placed.add(mesh)
            self.of_node[node] = self.document.doc["nodes"][node]["mesh"]
        return self.document.doc["meshes"][self.of_node[node]]["primitives"][placed["primitive"]]


def _add_vertex_occlusion(document, scene, result, meshes, vertex_colors):
    for placed in scene.uv_sets["primitives"]:
        first, end = placed["vertices"]
        values = np.ascontiguousarray(result.values[first:end], dtype="<f4")
        accessor = document.add_data(
            values.tobytes(),
            componentType=FLOAT,
            count=int(end - first),
            type=SCALAR,
            min=[float(values.min())],
            max=[float(values.max())],
        )
        attributes = meshes.primitive(placed)["attributes"]
        if vertex_colors:
            colors = _colors(document, attributes.get("COLOR_0"), len(values))
            colors[:, :3] *= values[:, None]
            attributes["COLOR_0"] = document.add_data(
                np.ascontiguousarray(colors, "<f4").tobytes(),
                componentType=FLOAT,
                count=len(values),
                type=f"VEC{colors.shape[1]}",
            )
        attributes["_OCCLUSION"] = accessor


def _colors(document, accessor, count):
    """COLOR_0's values as floats in [0, 1] ((count, 3) or (count, 4)), white where there is none."""
    if accessor is None:
        return np.ones((count, 3), np.float32)
    entry = document.doc["accessors"][accessor]
    components = int(entry["type"][-1])
    values = document.elements(accessor).copy().view(_NUMPY_TYPES[entry["componentType"]]).reshape(count, components)
    if entry["componentType"] == FLOAT:
        return values.astype(np.float32)
    return values.astype(np.float32) / np.float32(np.iinfo(values.dtype).max)  # normalized unsigned bytes or shorts


def _add_generated_uvs(document, scene, result, meshes):
    """Each baked primitive's vertices split where the generated charts' seams
    need two UVs for one vertex (every attribute and morph target copied along,
    the triangles in their order), and the UVs added as TEXCOORD_n, n the first
    set no primitive of the material has; a primitive with fewer sets gets the
    UVs in those below n too, as glTF's sets are numbered without gaps.
    Returns {material: n}."""
    corner_uvs = np.zeros((scene.triangle_count, 3, 2), np.float32)
    for texture in result.textures.values():
        corner_uvs[texture.triangles] = texture.texcoords
    triangle_materials = scene.uv_sets["triangle_materials"]
    placed_primitives = scene.uv_sets["primitives"]
    by_material = {}
    for placed in placed_primitives:
        material = int(triangle_materials[placed["triangles"][0]])
        by_material.setdefault(material, []).append(placed)
    sets = {
        material: max(_uv_sets_of(document.original, placed) for placed in group)
        for material, group in by_material.items()
    }
    for material, group in by_material.items():
        for placed in group:
            _split_along_seams(document, meshes.primitive(placed), placed, scene, corner_uvs, sets[material])
    return sets


def _uv_sets_of(doc, placed):
    attributes = doc["meshes"][placed["mesh"]]["primitives"][placed["primitive"]]["attributes"]
    return sum(1 for name in attributes if name.startswith("TEXCOORD_"))


def _split_along_seams(document, primitive, placed, scene, corner_uvs, new_set):
    first_vertex, _ = placed["vertices"]
    first, end = placed["triangles"]
    local = (scene.indices[first:end].astype(np.int64) - first_vertex).ravel()
    uvs = corner_uvs[first:end].reshape(-1, 2)
    # One output vertex per (file vertex, UV) pair, in the order the corners first use them.
    keys = np.column_stack([local.astype(np.float64), uvs.astype(np.float64)])
    _, first_use, corner_vertex = np.unique(keys, axis=0, return_index=True, return_inverse=True)
    order = np.argsort(first_use)
    renumbered = np.empty_like(order)
    renumbered[order] = np.arange(len(order))
    corner_vertex = renumbered[corner_vertex.ravel()]
    source = local[first_use[order]]
    new_uvs = uvs[first_use[order]]

    def gathered(accessor):
        entry = document.doc["accessors"][accessor]
        rows = document.elements(accessor)[source]
        fields = {key: entry[key] for key in ("componentType", "type", "normalized") if key in entry}
        if "min" in entry:  # required for POSITION: the bounds of the rows kept
            values = rows.copy().view(_NUMPY_TYPES[entry["componentType"]]).reshape(len(source), -1)
            fields.update(min=values.min(axis=0).tolist(), max=values.max(axis=0).tolist())
        return document.add_data(rows.tobytes(), count=len(source), **fields)

    attributes = primitive["attributes"]
    for name in list(attributes):
        attributes[name] = gathered(attributes[name])
    for target in primitive.get("targets", []):
        for name in list(target):
            target[name] = gathered(target[name])
    uv_accessor = document.add_data(
        np.ascontiguousarray(new_uvs, "<f4").tobytes(), componentType=FLOAT, count=len(source), type="VEC2"
    )
    for n in range(new_set + 1):
        attributes.setdefault(f"TEXCOORD_{n}", uv_accessor)
    attributes[f"TEXCOORD_{new_set}"] = uv_accessor
    indices = np.ascontiguousarray(corner_vertex, "<u4")
    primitive["indices"] = document.add_data(indices.tobytes(), componentType=5125, count=len(indices), type=SCALAR)
    primitive["mode"] = TRIANGLES  # the indices written are a list, whether the file's made a strip or a fan


def _add_occlusion_textures(document, scene, result, bit_depth, generated_sets, meshes):
    doc = document.doc
    replaced = []
    without_material = None
    for material, texture in result.textures.items():
        image = document.add_data(_png(texture.image, bit_depth))
        image_index = document.append(
            "images",
            {"bufferView": image, "mimeType": "image/png", "name": f"mbao occlusion, b = {result.settings['bounces']}"},
        )
        if material >= 0:
            entry = doc["materials"][material]
            old = entry.get("occlusionTexture")
            if old is not None:
                replaced.append(material)
        else:
            entry = {"name": "mbao occlusion"}
            without_material = document.append("materials", entry)
            old = None
        new_texture = {"source": image_index}
        sampler = _sampler(document, old, texture.stats["wrap"])
        if sampler is not None:
            new_texture["sampler"] = sampler
        texcoord = generated_sets[material] if texture.texcoord == "generated" else texture.texcoord
        occlusion = {"index": document.append("textures", new_texture), "texCoord": texcoord}
        if old is not None and "strength" in old:
            occlusion["strength"] = old["strength"]
        entry["occlusionTexture"] = occlusion
    if without_material is not None:
        for placed in scene.uv_sets["primitives"]:
            meshes.primitive(placed).setdefault("material", without_material)
    return replaced


def _sampler(document, old_occlusion, wrap):
    """The sampler of a new occlusion texture, whose texels were baked with `wrap`:
    the replaced texture's where it wraps so (its filters kept), else a new one;
    none (REPEAT) where nothing else is asked for."""
    doc = document.doc
    if old_occlusion is not None:
        sampler = doc["textures"][old_occlusion["index"]].get("sampler")
        modes = doc["samplers"][sampler] if sampler is not None else {}
        if (modes.get("wrapS", 10497), modes.get("wrapT", 10497)) == tuple(WRAP_CODES[m] for m in wrap):
            return sampler
    if tuple(wrap) == ("repeat", "repeat"):
        return None
    return document.append("samplers", {"wrapS": WRAP_CODES[wrap[0]], "wrapT": WRAP_CODES[wrap[1]]})


def _png(image, bit_depth):
    """PNG bytes of a (H, W) image in [0, 1], linear, the value in R, G and B."""
    import OpenImageIO as oiio

    height, width = image.shape
    kind = oiio.UINT16 if bit_depth == 16 else oiio.UINT8
    buffer = oiio.ImageBuf(oiio.ImageSpec(width, height, 3, kind))
    buffer.set_pixels(
        oiio.ROI(0, width, 0, height, 0, 1, 0, 3),
        np.ascontiguousarray(np.repeat(image[:, :, None], 3, axis=2), np.float32),
    )
    with tempfile.TemporaryDirectory() as folder:  # OpenImageIO's Python API writes files only
        path = os.path.join(folder, "occlusion.png")
        if not buffer.write(path, kind):
            raise OSError(f"cannot encode the occlusion texture as PNG: {buffer.geterror()}")
        with open(path, "rb") as file:
            return file.read()
