"""Writes small glTF 2.0 files for tests: .gltf (embedded or external .bin) and .glb.

Only numpy, json, struct and base64. A test describes its file through a
GltfBuilder, then writes it in any of the three containers:

    b = GltfBuilder()
    quad = b.add_mesh([b.primitive(positions, indices)])
    b.add_scene([b.add_node(mesh=quad, translation=(0, 0, -5))])
    path = b.write(tmp_path / "quad.glb")

The builder never checks what it is given, so broken files are easy to make:
pass out-of-range values (an index past the vertices, a child that is its own
ancestor, a default scene that does not exist) or edit `b.doc`, the glTF JSON
as a plain dict, before writing. `b.glb_bytes()` / `b.gltf_text()` give the
file contents for tests that want to cut or corrupt them.

Matrices are given as 4x4 numpy-style (row-major, column vectors: p' = M @ p)
and stored column-major, as glTF wants. Quaternions are (x, y, z, w).
"""

import base64
import json
import pathlib
import struct

import numpy as np

# accessor.componentType
BYTE = 5120
UNSIGNED_BYTE = 5121
SHORT = 5122
UNSIGNED_SHORT = 5123
UNSIGNED_INT = 5125
FLOAT = 5126

# primitive.mode
POINTS, LINES, LINE_LOOP, LINE_STRIP, TRIANGLES, TRIANGLE_STRIP, TRIANGLE_FAN = range(7)

NUMPY_TYPE = {
    BYTE: np.int8,
    UNSIGNED_BYTE: np.uint8,
    SHORT: np.int16,
    UNSIGNED_SHORT: np.uint16,
    UNSIGNED_INT: np.uint32,
    FLOAT: np.float32,
}
ACCESSOR_TYPE = {1: "SCALAR", 2: "VEC2", 3: "VEC3", 4: "VEC4"}

# sampler.wrapS / wrapT
REPEAT, CLAMP_TO_EDGE, MIRRORED_REPEAT = 10497, 33071, 33648

GLB_MAGIC = b"glTF"
GLB_JSON_CHUNK = 0x4E4F534A
GLB_BIN_CHUNK = 0x004E4942


def column_major(matrix):
    """A 4x4 matrix as glTF's 16 numbers, column by column."""
    return [float(x) for x in np.asarray(matrix, dtype=np.float64).reshape(4, 4).T.ravel()]


class GltfBuilder:
    """Accumulates one glTF document and one binary buffer (buffer 0)."""

    def __init__(self):
        self.doc = {
            "asset": {"version": "2.0", "generator": "mbao tests/gltf_writer.py"},
            "scenes": [],
            "nodes": [],
            "meshes": [],
            "accessors": [],
            "bufferViews": [],
            "buffers": [],
        }
        self.bin = bytearray()
        self.buffer_byte_length = None  # buffer 0's byteLength as written; None: len(self.bin)
        self.files = {}  # external files (images) written next to the glTF file

    # -- raw data ----------------------------------------------------------

    def add_buffer_view(self, data, byte_stride=None):
        """Appends bytes (4-byte aligned) to buffer 0; returns the bufferView index."""
        data = bytes(data)
        while len(self.bin) % 4:
            self.bin.append(0)
        view = {"buffer": 0, "byteOffset": len(self.bin), "byteLength": len(data)}
        if byte_stride is not None:
            view["byteStride"] = byte_stride
        self.bin += data
        return self._append("bufferViews", view)

    def add_accessor(self, buffer_view, component_type, count, components, byte_offset=0, **extra):
        """An accessor over a bufferView (None: no bufferView, as sparse accessors may have)."""
        accessor = {"componentType": component_type, "count": int(count), "type": ACCESSOR_TYPE[components]}
        if buffer_view is not None:
            accessor["bufferView"] = buffer_view
            if byte_offset:
                accessor["byteOffset"] = byte_offset
        accessor.update(extra)
        return self._append("accessors", accessor)

    def add_array(self, values, component_type=FLOAT, components=None):
        """A tightly packed accessor holding `values` ((N,) or (N, k)) in its own bufferView."""
        values = np.asarray(values)
        if components is None:
            components = 1 if values.ndim == 1 else values.shape[1]
        data = values.astype(NUMPY_TYPE[component_type]).reshape(-1)
        extra = {}
        if component_type == FLOAT and components == 3 and len(data):
            rows = data.reshape(-1, 3)  # min/max, which the spec requires for POSITION
            extra = {"min": rows.min(axis=0).tolist(), "max": rows.max(axis=0).tolist()}
        view = self.add_buffer_view(data.tobytes())
        return self.add_accessor(view, component_type, len(data) // components, components, **extra)

    def add_interleaved(self, arrays, byte_stride=None):
        """One bufferView with float32 (N, k) arrays interleaved per vertex, each
        attribute at its own byteOffset; returns one accessor index per array.
        byte_stride defaults to the packed vertex size; a larger one leaves gaps."""
        arrays = [np.asarray(a, dtype=np.float32) for a in arrays]
        count = len(arrays[0])
        offsets = np.cumsum([0] + [4 * a.shape[1] for a in arrays])
        stride = byte_stride or int(offsets[-1])
        data = bytearray(stride * count)
        for v in range(count):
            for a, offset in zip(arrays, offsets):
                start = v * stride + int(offset)
                data[start : start + 4 * a.shape[1]] = a[v].tobytes()
        view = self.add_buffer_view(data, byte_stride=stride)
        return [
            self.add_accessor(view, FLOAT, count, a.shape[1], byte_offset=int(offset))
            for a, offset in zip(arrays, offsets)
        ]

    def add_sparse(self, count, indices, values, base=None, index_type=UNSIGNED_SHORT):
        """A float VECk accessor of `count` elements: `base` ((count, k) array, or
        None for all zeros and no bufferView) with rows `indices` replaced by `values`."""
        values = np.asarray(values, dtype=np.float32)
        components = values.shape[1]
        base_view = None
        if base is not None:
            base_view = self.add_buffer_view(np.asarray(base, dtype=np.float32).tobytes())
        index_view = self.add_buffer_view(np.asarray(indices).astype(NUMPY_TYPE[index_type]).tobytes())
        value_view = self.add_buffer_view(values.tobytes())
        sparse = {
            "count": len(indices),
            "indices": {"bufferView": index_view, "componentType": index_type},
            "values": {"bufferView": value_view},
        }
        return self.add_accessor(base_view, FLOAT, count, components, sparse=sparse)

    # -- meshes, nodes, scenes, cameras ------------------------------------

    def primitive(
        self,
        positions=None,
        indices=None,
        normals=None,
        index_type=UNSIGNED_INT,
        mode=None,
        position_accessor=None,
        normal_accessor=None,
        texcoords=None,
        texcoord_type=FLOAT,
        texcoord_set=0,
        material=None,
    ):
        """A primitive dict (not yet in a mesh). positions/normals are (N, 3)
        arrays, or pass ready accessors; indices a flat or (M, 3) array stored
        as index_type, or None for a non-indexed primitive. mode None: omitted (TRIANGLES).
        texcoords: (N, 2) in [0, 1] for FLOAT, stored normalized for integer types."""
        if position_accessor is None:
            position_accessor = self.add_array(np.asarray(positions).reshape(-1, 3))
        primitive = {"attributes": {"POSITION": position_accessor}}
        if normal_accessor is None and normals is not None:
            normal_accessor = self.add_array(np.asarray(normals).reshape(-1, 3))
        if normal_accessor is not None:
            primitive["attributes"]["NORMAL"] = normal_accessor
        if indices is not None:
            primitive["indices"] = self.add_array(np.asarray(indices).reshape(-1), index_type)
        if mode is not None:
            primitive["mode"] = mode
        if texcoords is not None:
            primitive["attributes"][f"TEXCOORD_{texcoord_set}"] = self.add_texcoords(texcoords, texcoord_type)
        if material is not None:
            primitive["material"] = material
        return primitive

    def add_texcoords(self, texcoords, component_type=FLOAT):
        texcoords = np.asarray(texcoords, dtype=np.float64).reshape(-1, 2)
        if component_type == FLOAT:
            return self.add_array(texcoords, FLOAT)
        scale = np.iinfo(NUMPY_TYPE[component_type]).max
        accessor = self.add_array(np.round(texcoords * scale), component_type)
        self.doc["accessors"][accessor]["normalized"] = True
        return accessor

    # -- materials and textures ------------------------------------------------

    def add_image(self, encoded, mime_type="image/png", where="bufferView", file_name=None):
        """An image from encoded bytes, stored in a bufferView of buffer 0, as a
        data URI, or as an external file (written next to the glTF file)."""
        if where == "bufferView":
            image = {"bufferView": self.add_buffer_view(encoded), "mimeType": mime_type}
        elif where == "data-uri":
            image = {"uri": f"data:{mime_type};base64," + base64.b64encode(bytes(encoded)).decode("ascii")}
        else:
            self.files[file_name] = bytes(encoded)
            image = {"uri": file_name}
        return self._append("images", image)

    def add_texture(self, image, wrap_s=None, wrap_t=None):
        texture = {"source": image}
        if wrap_s is not None or wrap_t is not None:
            sampler = {key: value for key, value in (("wrapS", wrap_s), ("wrapT", wrap_t)) if value is not None}
            texture["sampler"] = self._append("samplers", sampler)
        return self._append("textures", texture)

    def add_material(self, alpha_mode=None, alpha_cutoff=None, base_color_factor=None, texture=None, texcoord_set=None):
        pbr = {}
        if base_color_factor is not None:
            pbr["baseColorFactor"] = [float(x) for x in base_color_factor]
        if texture is not None:
            pbr["baseColorTexture"] = {"index": texture}
            if texcoord_set is not None:
                pbr["baseColorTexture"]["texCoord"] = texcoord_set
        material = {"pbrMetallicRoughness": pbr}
        if alpha_mode is not None:
            material["alphaMode"] = alpha_mode
        if alpha_cutoff is not None:
            material["alphaCutoff"] = float(alpha_cutoff)
        return self._append("materials", material)

    def add_mesh(self, primitives):
        return self._append("meshes", {"primitives": list(primitives)})

    def add_node(
        self, mesh=None, camera=None, matrix=None, translation=None, rotation=None, scale=None, children=None, name=None
    ):
        """A node; rotation is a quaternion (x, y, z, w); children are node indices."""
        node = {}
        if name is not None:
            node["name"] = name
        if mesh is not None:
            node["mesh"] = mesh
        if camera is not None:
            node["camera"] = camera
        if matrix is not None:
            node["matrix"] = column_major(matrix)
        for key, value in (("translation", translation), ("rotation", rotation), ("scale", scale)):
            if value is not None:
                node[key] = [float(x) for x in value]
        if children is not None:
            node["children"] = list(children)
        return self._append("nodes", node)

    def add_scene(self, nodes, default=False):
        index = self._append("scenes", {"nodes": list(nodes)})
        if default:
            self.doc["scene"] = index
        return index

    def add_perspective_camera(self, yfov, znear=0.01, zfar=None, aspect_ratio=None, extras=None):
        perspective = {"yfov": float(yfov), "znear": float(znear)}
        if zfar is not None:
            perspective["zfar"] = float(zfar)
        if aspect_ratio is not None:
            perspective["aspectRatio"] = float(aspect_ratio)
        camera = {"type": "perspective", "perspective": perspective}
        if extras is not None:
            camera["extras"] = extras
        return self._append("cameras", camera)

    def add_orthographic_camera(self, xmag=1.0, ymag=1.0, znear=0.01, zfar=100.0):
        orthographic = {"xmag": xmag, "ymag": ymag, "znear": znear, "zfar": zfar}
        return self._append("cameras", {"type": "orthographic", "orthographic": orthographic})

    # -- output --------------------------------------------------------------

    def document(self, buffer_uri=None):
        """The JSON document; buffer 0 gets `buffer_uri` (None: no uri, as in .glb)."""
        doc = json.loads(json.dumps(self.doc))  # a deep copy; the builder stays reusable
        if self.bin:
            buffer = {"byteLength": len(self.bin) if self.buffer_byte_length is None else self.buffer_byte_length}
            if buffer_uri is not None:
                buffer["uri"] = buffer_uri
            doc["buffers"] = [buffer]
        else:
            doc.pop("buffers", None)
        return {key: value for key, value in doc.items() if value != []}

    def gltf_text(self, bin_name=None):
        """.gltf JSON, the buffer embedded as a data URI, or referring to the file bin_name."""
        uri = bin_name or "data:application/octet-stream;base64," + base64.b64encode(bytes(self.bin)).decode("ascii")
        return json.dumps(self.document(uri), indent=1)

    def glb_bytes(self):
        """The binary container: header, JSON chunk (space padded), BIN chunk (zero padded)."""
        json_chunk = json.dumps(self.document()).encode("utf-8")
        json_chunk += b" " * (-len(json_chunk) % 4)
        chunks = struct.pack("<II", len(json_chunk), GLB_JSON_CHUNK) + json_chunk
        if self.bin:
            bin_chunk = bytes(self.bin) + b"\0" * (-len(self.bin) % 4)
            chunks += struct.pack("<II", len(bin_chunk), GLB_BIN_CHUNK) + bin_chunk
        return GLB_MAGIC + struct.pack("<II", 2, 12 + len(chunks)) + chunks

    def write_gltf(self, path):
        """A self-contained .gltf (buffer as a base64 data URI)."""
        path = pathlib.Path(path)
        path.write_text(self.gltf_text())
        return path

    def write_gltf_external(self, path, bin_name=None):
        """A .gltf with its buffer in a .bin file next to it."""
        path = pathlib.Path(path)
        bin_name = bin_name or path.stem + ".bin"
        (path.parent / bin_name).write_bytes(bytes(self.bin))
        path.write_text(self.gltf_text(bin_name))
        return path

    def write_glb(self, path):
        path = pathlib.Path(path)
        path.write_bytes(self.glb_bytes())
        return path

    def write(self, path, container=None):
        """Writes `path` as container "gltf", "gltf+bin" or "glb" (default: by
        suffix), and the external files next to it."""
        container = container or ("glb" if str(path).endswith(".glb") else "gltf")
        writers = {"gltf": self.write_gltf, "gltf+bin": self.write_gltf_external, "glb": self.write_glb}
        for name, data in self.files.items():
            (pathlib.Path(path).parent / name).write_bytes(data)
        return writers[container](path)

    def _append(self, key, item):
        self.doc.setdefault(key, []).append(item)
        return len(self.doc[key]) - 1


CONTAINERS = ("gltf", "gltf+bin", "glb")


def png_bytes(pixels, tmp_dir):
    """A PNG of `pixels` ((H, W) grey or (H, W, C) with C = 2 grey-alpha, 3 RGB,
    4 RGBA), 8-bit for uint8 data and 16-bit for uint16, encoded by OpenImageIO."""
    import OpenImageIO as oiio

    pixels = np.asarray(pixels)
    if pixels.ndim == 2:
        pixels = pixels[:, :, None]
    height, width, channels = pixels.shape
    bits = oiio.UINT16 if pixels.dtype == np.uint16 else oiio.UINT8
    path = pathlib.Path(tmp_dir) / f"image-{width}x{height}x{channels}-{pixels.dtype}.png"
    image = oiio.ImageBuf(oiio.ImageSpec(width, height, channels, bits))
    scale = 65535.0 if pixels.dtype == np.uint16 else 255.0
    image.set_pixels(oiio.ROI(0, width, 0, height, 0, 1, 0, channels), (pixels / scale).astype(np.float32))
    assert image.write(str(path), bits), image.geterror()
    return path.read_bytes()


def file_name(stem, container):
    """A file name with the right suffix for a container of CONTAINERS."""
    return stem + (".glb" if container == "glb" else ".gltf")
