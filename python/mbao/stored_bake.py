"""The ambient occlusion a glTF file stores, read back (SPEC 6.5: mbao.bake_file's
_OCCLUSION vertex attribute, or occlusion textures, an artist's too), laid
out on the scene loaded from the file: mbao.load_bake."""

import contextlib
import dataclasses
import os
import tempfile
from typing import Optional

import numpy as np

from . import _core
from ._gltf import GltfDocument
from ._types import PathLike
from .scene import is_gltf_path, load

OCCLUSION = "_OCCLUSION"
# StoredBake.triangle_source of a triangle that reads its vertex values, or nothing; any other value is
# the material whose occlusion texture it reads.
VERTICES, OPEN = -1, -2
_FLOAT, _UNSIGNED_BYTE, _UNSIGNED_SHORT = 5126, 5121, 5123
_SCALAR_TYPES = {_FLOAT: "<f4", _UNSIGNED_BYTE: "<u1", _UNSIGNED_SHORT: "<u2"}
_SUFFIXES = {"image/png": ".png", "image/jpeg": ".jpg"}


@dataclasses.dataclass(frozen=True)
class OcclusionTexture:
    """A material's occlusion texture as glTF reads it: image (H, W) float32,
    the R channel in [0, 1], row 0 the image's top (v = 0); texcoord, the n of
    the TEXCOORD_n it reads; wrap, its sampler's (s, t) modes as
    scene.uv_sets names them ("repeat", "clamp-to-edge", "mirrored-repeat")."""

    image: np.ndarray
    texcoord: int
    wrap: tuple

    def sample(self, uv):
        """Bilinear samples at (K, 2) UVs, texel centres at half-integers and
        UVs outside [0, 1] mapped through the wrap modes, as alpha masks are
        sampled (SPEC 3.2)."""
        height, width = self.image.shape
        x = _reduced(uv[:, 0], self.wrap[0]) * width - 0.5
        y = _reduced(uv[:, 1], self.wrap[1]) * height - 0.5
        x0, y0 = np.floor(x), np.floor(y)
        fx, fy = x - x0, y - y0
        i0, i1 = (_wrapped(x0 + k, width, self.wrap[0]) for k in (0, 1))
        j0, j1 = (_wrapped(y0 + k, height, self.wrap[1]) for k in (0, 1))
        a00, a10, a01, a11 = (self.image[j, i].astype(np.float64) for j, i in ((j0, i0), (j0, i1), (j1, i0), (j1, i1)))
        top, bottom = a00 + fx * (a10 - a00), a01 + fx * (a11 - a01)
        return (top + fy * (bottom - top)).astype(np.float32)


def _reduced(s, mode):
    """A coordinate brought into one period of its wrap mode, so that texel indices stay small."""
    if mode == "clamp-to-edge":
        return np.clip(s, 0.0, 1.0)
    if mode == "mirrored-repeat":
        return s - 2.0 * np.floor(0.5 * s)
    return s - np.floor(s)


def _wrapped(i, n, mode):
    """Texel indices (floats holding integers) wrapped into [0, n) as the sampler says."""
    i = i.astype(np.int64)
    if mode == "clamp-to-edge":
        return np.clip(i, 0, n - 1)
    if mode == "mirrored-repeat":
        m = i % (2 * n)
        return np.where(m < n, m, 2 * n - 1 - m)
    return i % n


@dataclasses.dataclass(frozen=True, repr=False)
class StoredBake:
    """The occlusion a glTF file stores, laid out on the scene loaded from it.

    scene: that scene (mbao.load(path, texcoords=True)), whose vertices and
        triangles the arrays below follow.
    source: "vertices" where the file has an _OCCLUSION attribute, else "texture".
    vertex_values: (N,) float32 per scene vertex, its _OCCLUSION value; NaN
        where its primitive has none. None without any.
    textures: {material: OcclusionTexture}, the glTF material's index (the
        order of the file's "materials", as scene.uv_sets["materials"]), for
        the materials of triangles that have no vertex values.
    vertex_uvs: (N, 2) float32 per scene vertex, the UV its material's
        occlusion texture reads (NaN where there is none); None without textures.
    triangle_source: (M,) int32 per triangle: VERTICES (its three vertices
        have values), its material (whose texture it reads) or OPEN (nothing
        stored for it: looked up as 1).

    A triangle with vertex values reads them even where its material has an
    occlusion texture too: bake_file's vertex bake keeps the textures a file
    had (often an artist's), so the attribute is the newer bake.
    """

    scene: _core.Scene
    source: str
    vertex_values: np.ndarray
    textures: dict
    vertex_uvs: np.ndarray
    triangle_source: np.ndarray

    def __repr__(self):
        return (
            f"<mbao StoredBake from {self.source}: {len(self.textures)} textures, "
            f"{int((self.triangle_source == OPEN).sum())} of {len(self.triangle_source)} triangles open>"
        )


def load_bake(path: PathLike, scene: Optional[_core.Scene] = None) -> Optional["StoredBake"]:
    """The occlusion the glTF file at `path` stores (an _OCCLUSION attribute
    per vertex, occlusion textures per material), as a StoredBake, or None
    where it holds none (not glTF, or neither on the scene's triangles).
    scene: mbao.load(path, texcoords=True), whose uv_sets place the file's
    primitives and materials; None loads it. Raises mbao.LoadError naming the
    file and element for a bake it cannot read."""
    if not is_gltf_path(path):
        return None
    if scene is None:
        scene = load(path, texcoords=True)
    uv_sets = scene.uv_sets  # a fresh copy per access: read it once
    if uv_sets is None:
        raise ValueError(
            f"{os.fspath(path)}: load_bake needs the scene's UV sets and materials: "
            f"load it with mbao.load(path, texcoords=True)"
        )
    document = GltfDocument(path)
    indices = scene.indices
    values = _vertex_values(document, uv_sets, len(scene.vertices))
    source = np.full(len(indices), OPEN, np.int32)
    if values is not None:
        source[np.isfinite(values[indices]).all(axis=1)] = VERTICES
    textures = _occlusion_textures(document, uv_sets, np.unique(uv_sets["triangle_materials"][source == OPEN]))
    vertex_uvs = None
    if textures:
        vertex_uvs = _vertex_uvs(uv_sets, textures, len(scene.vertices))
        textured = (source == OPEN) & np.isin(uv_sets["triangle_materials"], list(textures))
        textured &= np.isfinite(vertex_uvs[indices]).all(axis=(1, 2))  # a primitive without the set stays open
        source[textured] = uv_sets["triangle_materials"][textured]
    if values is None and not textures:
        return None
    return StoredBake(scene, "vertices" if values is not None else "texture", values, textures, vertex_uvs, source)


@contextlib.contextmanager
def _reading(document, what):
    """Turns what a malformed document makes the readers raise into a LoadError naming the file and `what`."""
    try:
        yield
    except (KeyError, IndexError, TypeError, ValueError, OSError) as error:
        raise _core.LoadError(f"{document.path}: {what}: cannot read it ({type(error).__name__}: {error})") from None


def _vertex_values(document, uv_sets, vertex_count):
    """(N,) float32 per scene vertex, its primitive's _OCCLUSION value (NaN
    without one); None where no primitive has the attribute."""
    values = None
    for placed in uv_sets["primitives"]:
        what = f"mesh {placed['mesh']} primitive {placed['primitive']} {OCCLUSION}"
        with _reading(document, what):
            primitive = document.doc["meshes"][placed["mesh"]]["primitives"][placed["primitive"]]
            accessor = primitive["attributes"].get(OCCLUSION)
        if accessor is None:
            continue
        if values is None:
            values = np.full(vertex_count, np.nan, np.float32)
        first, end = placed["vertices"]
        values[first:end] = _scalars(document, accessor, end - first, what)
    return values


def _scalars(document, index, count, what):
    """Accessor `index`'s `count` SCALAR values as float32: FLOAT as they are,
    normalized unsigned bytes and shorts (which glTF allows for an
    application's attributes) as fractions of their maximum."""
    accessors = document.doc.get("accessors", [])
    if not isinstance(index, int) or not 0 <= index < len(accessors):
        raise _core.LoadError(f"{document.path}: {what} uses accessor {index!r}, which does not exist")
    entry = accessors[index]
    kind = entry.get("componentType")
    if entry.get("type") != "SCALAR" or kind not in _SCALAR_TYPES or (kind != _FLOAT and not entry.get("normalized")):
        raise _core.LoadError(
            f"{document.path}: {what} (accessor {index}) is {entry.get('type')} of component type "
            f"{kind}; mbao reads FLOAT SCALAR values (or normalized unsigned bytes or shorts)"
        )
    if entry.get("count") != count:
        raise _core.LoadError(
            f"{document.path}: {what} (accessor {index}) has {entry.get('count')} values for " f"{count} positions"
        )
    with _reading(document, f"{what} (accessor {index})"):
        values = document.elements(index).copy().view(_SCALAR_TYPES[kind]).ravel()
    if kind == _FLOAT:
        return values
    return values.astype(np.float32) / np.float32(np.iinfo(values.dtype).max)


def _occlusion_textures(document, uv_sets, materials):
    """{material: OcclusionTexture} for those of `materials` with an occlusion
    texture; an image two of them share is decoded once."""
    textures, images = {}, {}
    for material in materials.tolist():
        if material < 0 or uv_sets["materials"][material]["occlusion_texcoord"] is None:
            continue
        info = uv_sets["materials"][material]
        what = f"material {material} occlusionTexture"
        with _reading(document, what):
            texture = document.doc["materials"][material]["occlusionTexture"]["index"]
            image = document.doc["textures"][texture].get("source")
        if image is None:  # only an extension's source (KTX2, WebP, ...)
            raise _core.LoadError(f"{document.path}: {what}: texture {texture} has no PNG or JPEG source image")
        if image not in images:
            images[image] = _red_channel(document, image)
        textures[material] = OcclusionTexture(images[image], info["occlusion_texcoord"], tuple(info["wrap"]))
    return textures


def _vertex_uvs(uv_sets, textures, vertex_count):
    """(N, 2) per scene vertex, the UV set its material's occlusion texture
    reads (a vertex belongs to one primitive, hence to one material); NaN
    elsewhere."""
    uvs = np.full((vertex_count, 2), np.nan, np.float32)
    sets = uv_sets["sets"]
    for placed in uv_sets["primitives"]:
        texture = textures.get(int(uv_sets["triangle_materials"][placed["triangles"][0]]))
        if texture is not None and texture.texcoord < len(sets):
            first, end = placed["vertices"]
            uvs[first:end] = sets[texture.texcoord][first:end]
    return uvs


def _red_channel(document, index):
    """Image `index`'s first channel (R, or the grey of a grey image) as
    float32 in [0, 1], 8 or 16 bits alike, row 0 at the top."""
    import OpenImageIO as oiio

    what = f"image {index}"
    with _reading(document, what):
        data, suffix = _image_bytes(document, document.doc["images"][index])
    config = oiio.ImageSpec()
    config.attribute("oiio:UnassociatedAlpha", 1)  # R as stored, not multiplied by an alpha channel
    with tempfile.TemporaryDirectory() as folder:  # OpenImageIO's Python API reads files only
        path = os.path.join(folder, "occlusion" + suffix)
        with open(path, "wb") as file:
            file.write(data)
        buffer = oiio.ImageBuf(path, 0, 0, config)
        pixels = buffer.get_pixels(oiio.FLOAT)
        if buffer.has_error or pixels is None or pixels.ndim != 3:
            raise _core.LoadError(f"{document.path}: {what}: cannot decode it: {buffer.geterror()}")
    return np.ascontiguousarray(pixels[:, :, 0], np.float32)


def _image_bytes(document, image):
    """The encoded bytes of a glTF image (a bufferView, a data URI or a file
    beside the glTF file) and a file suffix that names its format."""
    mime = image.get("mimeType")
    if "bufferView" in image:
        view = document.doc["bufferViews"][image["bufferView"]]
        start = view.get("byteOffset", 0)
        data = document.buffer_data(view["buffer"])[start : start + view["byteLength"]]
        return data, _SUFFIXES.get(mime, ".png")
    uri = image["uri"]
    if uri.startswith("data:"):
        return document.uri_data(uri), _SUFFIXES.get(uri[5:].partition(",")[0].split(";")[0], ".png")
    suffix = os.path.splitext(document.uri_path(uri))[1]
    return document.uri_data(uri), suffix or _SUFFIXES.get(mime, ".png")
