"""A baked glTF file: the input with everything kept, plus the bake (SPEC 6):
occlusion textures per material, or an _OCCLUSION attribute per primitive."""

import copy
import os
import tempfile

import numpy as np

from . import _checks
from ._gltf import GltfDocument
from .bake import bake
from .scene import load

FLOAT, SCALAR = 5126, "SCALAR"


def bake_file(input, output, *, target="vertices", bit_depth=8, **settings):
    """Bakes the glTF file `input` as mbao.bake does and writes `output`: the
    same document, every node, mesh, material, texture, animation, skin,
    extension and extra kept as it was, plus the bake:

    target="texture": each baked material's occlusionTexture points at a new
        PNG (linear values, AO in R copied to G and B, `bit_depth` 8 or 16 bits)
        with texCoord the UV set baked into; an existing occlusion texture is
        replaced (its strength kept), the rest of the material kept; triangles
        without a material get a new one.
    target="vertices": a float attribute _OCCLUSION (glTF's prefix for an
        application's own attributes) on every primitive; a mesh that several
        nodes place gets a copy per node, since its AO depends on where it stands.

    output is .glb where input is, else .gltf (relative URIs rewritten for its
    folder; new data in data URIs). settings: those of mbao.bake. Returns the
    mbao.Bake, with stats["replaced_occlusion"]: the materials whose occlusion
    texture was replaced.
    """
    if settings.get("texcoord") == "generate":
        raise ValueError("bake_file cannot write generated UVs yet: the file needs its vertices split along the "
                         "charts' seams; mbao.bake(..., texcoord=\"generate\") bakes into them in memory")
    bit_depth = _checks.integer("bit_depth", bit_depth)
    if bit_depth not in (8, 16):
        raise ValueError(f"bit_depth must be 8 or 16, got {bit_depth}")
    scene = load(input, texcoords=True)  # the loader's checks and errors first
    document = GltfDocument(input)
    document.check_output(output)  # before the bake, not after it
    result = bake(scene, target=target, **settings)
    if target == "texture":
        replaced = _add_occlusion_textures(document, scene, result, bit_depth)
    else:
        replaced = []
        _add_vertex_occlusion(document, scene, result)
    document.write(output)
    result.stats["replaced_occlusion"] = replaced
    return result


def _add_vertex_occlusion(document, scene, result):
    doc = document.doc
    mesh_of_node, copies = {}, {}
    for placed in scene.uv_sets["primitives"]:
        node = doc["nodes"][placed["node"]]
        if placed["node"] not in mesh_of_node:
            mesh = placed["mesh"]
            if mesh in copies.values():  # another node placed this mesh first: this one gets a copy
                mesh = document.append("meshes", copy.deepcopy(document.original["meshes"][mesh]))
                node["mesh"] = mesh
            copies[placed["node"]] = placed["mesh"]
            mesh_of_node[placed["node"]] = mesh
        first, end = placed["vertices"]
        values = np.ascontiguousarray(result.values[first:end], dtype="<f4")
        accessor = document.add_data(values.tobytes(), componentType=FLOAT, count=int(end - first), type=SCALAR,
                                     min=[float(values.min())], max=[float(values.max())])
        primitive = doc["meshes"][mesh_of_node[placed["node"]]]["primitives"][placed["primitive"]]
        primitive["attributes"]["_OCCLUSION"] = accessor


def _add_occlusion_textures(document, scene, result, bit_depth):
    doc = document.doc
    replaced = []
    without_material = None
    for material, texture in result.textures.items():
        image = document.add_data(_png(texture.image, bit_depth))
        image_index = document.append("images", {"bufferView": image, "mimeType": "image/png",
                                                 "name": f"mbao occlusion, b = {result.settings['bounces']}"})
        new_texture = {"source": image_index}
        if material >= 0:
            entry = doc["materials"][material]
            old = entry.get("occlusionTexture")
            if old is not None:
                replaced.append(material)
                sampler = doc["textures"][old["index"]].get("sampler")
                if sampler is not None:
                    new_texture["sampler"] = sampler
        else:
            entry = {"name": "mbao occlusion"}
            without_material = document.append("materials", entry)
            old = None
        occlusion = {"index": document.append("textures", new_texture), "texCoord": texture.texcoord}
        if old is not None and "strength" in old:
            occlusion["strength"] = old["strength"]
        entry["occlusionTexture"] = occlusion
    if without_material is not None:
        for placed in scene.uv_sets["primitives"]:
            primitive = doc["meshes"][placed["mesh"]]["primitives"][placed["primitive"]]
            primitive.setdefault("material", without_material)
    return replaced


def _png(image, bit_depth):
    """PNG bytes of a (H, W) image in [0, 1], linear, the value in R, G and B."""
    import OpenImageIO as oiio

    height, width = image.shape
    kind = oiio.UINT16 if bit_depth == 16 else oiio.UINT8
    buffer = oiio.ImageBuf(oiio.ImageSpec(width, height, 3, kind))
    buffer.set_pixels(oiio.ROI(0, width, 0, height, 0, 1, 0, 3),
                      np.ascontiguousarray(np.repeat(image[:, :, None], 3, axis=2), np.float32))
    with tempfile.TemporaryDirectory() as folder:  # OpenImageIO's Python API writes files only
        path = os.path.join(folder, "occlusion.png")
        if not buffer.write(path, kind):
            raise OSError(f"cannot encode the occlusion texture as PNG: {buffer.geterror()}")
        with open(path, "rb") as file:
            return file.read()
