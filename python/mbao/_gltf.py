"""A glTF file as its JSON document and binary data, edited and written back
with everything it holds kept as it was (glTF 2.0's container: .glb's chunks,
or .gltf with external or data-URI buffers and images)."""

import base64
import copy
import json
import os
import struct
from urllib.parse import quote, unquote

import numpy as np

from . import _core
from ._warnings import warn

_GLB_MAGIC, _JSON_CHUNK, _BIN_CHUNK = 0x46546C67, 0x4E4F534A, 0x004E4942
_COMPONENT_BYTES = {5120: 1, 5121: 1, 5122: 2, 5123: 2, 5125: 4, 5126: 4}
_COMPONENTS = {"SCALAR": 1, "VEC2": 2, "VEC3": 3, "VEC4": 4, "MAT2": 4, "MAT3": 9, "MAT4": 16}
_INDEX_TYPES = {5121: "<u1", 5123: "<u2", 5125: "<u4"}


class GltfDocument:
    """doc: the JSON document (a dict); new binary data goes into `added`, a
    buffer of its own that write() places: the GLB's binary chunk (buffer 0)
    for .glb, a data URI for .gltf."""

    def __init__(self, path):
        self.path = os.fspath(path)
        with open(self.path, "rb") as file:
            data = file.read()
        self.glb = data[:4] == struct.pack("<I", _GLB_MAGIC)
        self.bin = b""
        self.doc = self._read_glb(data) if self.glb else self._read_json(data)
        self.original = copy.deepcopy(self.doc)
        self.added = bytearray()
        self._added_views = []

    @classmethod
    def of_mesh(cls, path, vertices, indices, normals, glb, uv_sets=None):
        """A document of one mesh placed by one node, its data in buffer 0
        (the GLB's binary chunk, or a data URI): what bake_file writes a file
        of another format as (`path` names it in messages). normals: (N, 3)
        unit vectors or None. uv_sets: the scene's (scene.uv_sets) or None:
        with them, a primitive per loaded primitive, in their order, with its
        material (the file's materials, by name, with their base colours
        where read) and its UV sets as TEXCOORD_0, 1, ... up to the first it
        lacks; without them, one primitive and no material."""
        self = cls.__new__(cls)
        self.path, self.glb = os.fspath(path), glb
        vertices = np.ascontiguousarray(vertices, "<f4")
        indices = np.asarray(indices, np.int64)
        placed = (uv_sets or {}).get("primitives") or [dict(vertices=(0, len(vertices)), triangles=(0, len(indices)))]
        binary, views, accessors = bytearray(), [], []
        primitives = [
            _primitive_of(part, vertices, indices, normals, uv_sets, binary, views, accessors) for part in placed
        ]
        buffer = {}
        self.doc = {
            "asset": {"version": "2.0", "generator": "mbao"},
            "scene": 0,
            "scenes": [{"nodes": [0]}],
            "nodes": [{"mesh": 0}],
            "meshes": [{"primitives": primitives}],
            "buffers": [buffer],
            "bufferViews": views,
            "accessors": accessors,
        }
        if uv_sets is not None and uv_sets["materials"]:
            self.doc["materials"] = [{"name": material["name"]} for material in uv_sets["materials"]]
            _add_base_colors(self.doc, uv_sets["materials"], primitives, binary, views, self.path)
        buffer["byteLength"] = len(binary)
        if not glb:
            buffer["uri"] = "data:application/octet-stream;base64," + base64.b64encode(bytes(binary)).decode("ascii")
        self.bin = bytes(binary) if glb else b""
        self.original = copy.deepcopy(self.doc)
        self.added, self._added_views = bytearray(), []
        return self

    def _read_json(self, data):
        try:
            return json.loads(data)
        except (UnicodeDecodeError, json.JSONDecodeError) as error:
            raise _core.LoadError(f"{self.path}: not glTF JSON: {error}") from None

    def _read_glb(self, data):
        if len(data) < 20:
            raise _core.LoadError(f"{self.path}: a GLB file of {len(data)} bytes is shorter than its headers")
        _, version, length = struct.unpack_from("<3I", data)
        if version != 2 or length > len(data):
            raise _core.LoadError(f"{self.path}: GLB version {version}, length {length} of {len(data)} bytes")
        chunks, offset = {}, 12
        while offset + 8 <= length:
            size, kind = struct.unpack_from("<2I", data, offset)
            chunks.setdefault(kind, data[offset + 8 : offset + 8 + size])
            offset += 8 + size + (-size % 4)
        if _JSON_CHUNK not in chunks:
            raise _core.LoadError(f"{self.path}: the GLB file has no JSON chunk")
        self.bin = chunks.get(_BIN_CHUNK, b"")
        return self._read_json(chunks[_JSON_CHUNK])

    def buffer_data(self, index):
        """The bytes of buffer `index`: the GLB's binary chunk, a data URI's or an external file's."""
        uri = self.doc["buffers"][index].get("uri")
        return self.bin if uri is None else self.uri_data(uri)

    def uri_data(self, uri):
        """The bytes a buffer's or an image's URI names: a data URI's, or a file's relative to this one."""
        if uri.startswith("data:"):
            return base64.b64decode(uri.partition(",")[2])
        with open(self.uri_path(uri), "rb") as file:
            return file.read()

    def uri_path(self, uri):
        """The file a relative URI names."""
        return os.path.join(os.path.dirname(os.path.abspath(self.path)), unquote(uri))

    def elements(self, index):
        """Accessor `index`'s elements as raw bytes, one row each ((count, element size) uint8),
        strides and sparse substitutions resolved: what a copy of it with other rows needs."""
        accessor = self.doc["accessors"][index]
        size = _COMPONENT_BYTES[accessor["componentType"]] * _COMPONENTS[accessor["type"]]
        count = accessor["count"]
        rows = np.zeros((count, size), np.uint8)
        if "bufferView" in accessor:
            rows[:] = self._view_rows(accessor["bufferView"], accessor.get("byteOffset", 0), count, size)
        sparse = accessor.get("sparse")
        if sparse:
            indices = sparse["indices"]
            index_type = np.dtype(_INDEX_TYPES[indices["componentType"]])
            where = (
                self._view_rows(
                    indices["bufferView"], indices.get("byteOffset", 0), sparse["count"], index_type.itemsize
                )
                .copy()
                .view(index_type)
                .ravel()
            )
            values = sparse["values"]
            rows[where] = self._view_rows(values["bufferView"], values.get("byteOffset", 0), sparse["count"], size)
        return rows

    def _view_rows(self, view_index, offset, count, size):
        view = self.doc["bufferViews"][view_index]
        data = np.frombuffer(self.buffer_data(view["buffer"]), np.uint8)
        stride = view.get("byteStride", size)
        start = view.get("byteOffset", 0) + offset
        end = start + (count - 1) * stride + size if count else start
        if end > min(len(data), view.get("byteOffset", 0) + view["byteLength"]):
            raise _core.LoadError(
                f"{self.path}: bufferView {view_index} is too short for {count} elements of "
                f"{size} bytes from byte {offset}"
            )
        return np.lib.stride_tricks.as_strided(data[start:], (count, size), (stride, 1), writeable=False)

    def append(self, key, item):
        """Adds `item` to the top-level array `key`; returns its index."""
        self.doc.setdefault(key, []).append(item)
        return len(self.doc[key]) - 1

    def add_data(self, data, **accessor):
        """A bufferView over `data` (4-byte aligned) in the added buffer; with
        accessor fields (componentType, count, type, ...), an accessor on it too.
        Returns the accessor's index, else the bufferView's."""
        self.added.extend(b"\0" * (-len(self.added) % 4))
        view = self.append("bufferViews", {"buffer": None, "byteOffset": len(self.added), "byteLength": len(data)})
        self._added_views.append(view)
        self.added.extend(data)
        if not accessor:
            return view
        return self.append("accessors", dict(bufferView=view, **accessor))

    def write(self, path):
        """Writes the document to `path`, .glb or .gltf as the input was (the
        container is not converted); relative URIs are rewritten for its folder."""
        path = self.check_output(path)
        glb = self.glb
        doc = copy.deepcopy(self.doc)
        self._rebase_uris(doc, os.path.dirname(os.path.abspath(path)))
        if glb:
            binary = self._glb_binary(doc)
        else:
            binary = None
            if self.added:
                buffer = self._place_added(
                    doc,
                    {
                        "uri": "data:application/octet-stream;base64,"
                        + base64.b64encode(bytes(self.added)).decode("ascii")
                    },
                )
                doc["buffers"][buffer]["byteLength"] = len(self.added)
        text = json.dumps(doc, separators=(",", ":")).encode("utf-8")
        with open(path, "wb") as file:
            if not glb:
                file.write(text)
                return
            text += b" " * (-len(text) % 4)
            chunks = struct.pack("<2I", len(text), _JSON_CHUNK) + text
            if binary is not None:
                chunks += struct.pack("<2I", len(binary), _BIN_CHUNK) + binary
            file.write(struct.pack("<3I", _GLB_MAGIC, 2, 12 + len(chunks)) + chunks)

    def check_output(self, path):
        """`path` as a str, or a ValueError where write() could not write it there."""
        path = os.fspath(path)
        extension = ".glb" if self.glb else ".gltf"
        if not path.lower().endswith(extension):
            raise ValueError(
                f"output {path!r} must be a {extension} file, as the input {self.path!r} is "
                f"(mbao does not convert between .glb and .gltf)"
            )
        if os.path.abspath(path) == os.path.abspath(self.path):
            raise ValueError(f"output {path!r} is the input; write the baked file beside it")
        folder = os.path.dirname(os.path.abspath(path))
        if not os.access(folder, os.W_OK):
            raise ValueError(f"output {path!r}: cannot write in {folder!r}")
        return path

    def _glb_binary(self, doc):
        """The binary chunk: the input's with the added data after it, in buffer 0."""
        if not self.added:
            return self.bin or None
        base = len(self.bin) + (-len(self.bin) % 4)
        binary = bytes(self.bin) + b"\0" * (base - len(self.bin)) + bytes(self.added)
        binary += b"\0" * (-len(binary) % 4)
        buffers = doc.setdefault("buffers", [])
        if not buffers or "uri" in buffers[0]:
            # No GLB-stored buffer yet: ours becomes buffer 0, the others move up one.
            buffers.insert(0, {})
            for view in doc.get("bufferViews", []):
                if view["buffer"] is not None:
                    view["buffer"] += 1
            base = 0
            binary = bytes(self.added) + b"\0" * (-len(self.added) % 4)
        buffers[0]["byteLength"] = len(binary)
        for view in self._added_views:
            doc["bufferViews"][view]["buffer"] = 0
            doc["bufferViews"][view]["byteOffset"] += base
        return binary

    def _place_added(self, doc, buffer):
        index = len(doc.setdefault("buffers", []))
        doc["buffers"].append(buffer)
        for view in self._added_views:
            doc["bufferViews"][view]["buffer"] = index
        return index

    def _rebase_uris(self, doc, folder):
        """Relative URIs of buffers and images, made relative to the output's folder."""
        source = os.path.dirname(os.path.abspath(self.path))
        if os.path.normcase(source) == os.path.normcase(folder):
            return
        for item in doc.get("buffers", []) + doc.get("images", []):
            uri = item.get("uri")
            if uri and not uri.startswith("data:") and "://" not in uri:
                moved = os.path.relpath(os.path.join(source, unquote(uri)), folder)
                item["uri"] = quote(moved.replace(os.sep, "/"))


WRAP_CODES = {"repeat": 10497, "clamp-to-edge": 33071, "mirrored-repeat": 33648}


def _add_base_colors(doc, materials, primitives, binary, views, path):
    """Each material's base colour (uv_sets' "base_color", where read) as its pbrMetallicRoughness: the factor,
    and the image, its bytes appended to binary and views, where every primitive of the material has the UV set
    it is looked up in (else a warning names the material and the set)."""
    for index, material in enumerate(materials):
        color = material.get("base_color")
        if color is None:
            continue
        pbr = doc["materials"][index]["pbrMetallicRoughness"] = {"baseColorFactor": list(color["factor"])}
        if color["image"] is None:
            continue
        uv_set = f"TEXCOORD_{color['texcoord']}"
        lacking = [p for p in primitives if p.get("material") == index and uv_set not in p["attributes"]]
        if lacking:
            warn(
                f"{path}: material '{material['name']}''s base colour image is looked up in {uv_set}, "
                f"which {len(lacking)} of its primitives lack; the file is written without the image"
            )
            continue
        views.append({"buffer": 0, "byteOffset": len(binary), "byteLength": len(color["image"])})
        binary.extend(color["image"])
        binary.extend(b"\0" * (-len(binary) % 4))
        mime_type = "image/png" if color["image"][:4] == b"\x89PNG" else "image/jpeg"  # png_or_jpeg's two
        image = _appended(doc, "images", {"bufferView": len(views) - 1, "mimeType": mime_type})
        texture = {"source": image}
        if tuple(color["wrap"]) != ("repeat", "repeat"):
            texture["sampler"] = _appended(
                doc, "samplers", {"wrapS": WRAP_CODES[color["wrap"][0]], "wrapT": WRAP_CODES[color["wrap"][1]]}
            )
        pbr["baseColorTexture"] = {"index": _appended(doc, "textures", texture), "texCoord": color["texcoord"]}


def _appended(doc, key, item):
    doc.setdefault(key, []).append(item)
    return len(doc[key]) - 1


def _primitive_of(part, vertices, indices, normals, uv_sets, binary, views, accessors):
    """A primitive of the vertices and triangles `part` places (GltfDocument.of_mesh), its arrays appended to
    binary, views and accessors."""
    first, end = part["vertices"]
    triangles = indices[slice(*part["triangles"])] - first
    positions = vertices[first:end]
    arrays = [
        (
            "POSITION",
            positions,
            dict(type="VEC3", min=positions.min(axis=0).tolist(), max=positions.max(axis=0).tolist()),
        )
    ]
    if normals is not None:
        arrays.append(("NORMAL", normals[first:end], dict(type="VEC3")))
    for n, uv in enumerate(uv_sets["sets"] if uv_sets is not None else []):
        if not np.isfinite(uv[first:end]).all():
            break  # glTF numbers a primitive's sets without gaps
        arrays.append((f"TEXCOORD_{n}", uv[first:end], dict(type="VEC2")))
    arrays.append(("indices", triangles.astype("<u4").ravel(), dict(type="SCALAR")))
    primitive = {"attributes": {}, "mode": 4}
    for name, array, accessor in arrays:
        array = np.ascontiguousarray(array, "<u4" if name == "indices" else "<f4")
        views.append({"buffer": 0, "byteOffset": len(binary), "byteLength": array.nbytes})
        binary.extend(array.tobytes())
        binary.extend(b"\0" * (-len(binary) % 4))
        component = 5125 if name == "indices" else 5126
        accessors.append(dict(bufferView=len(views) - 1, componentType=component, count=len(array), **accessor))
        if name == "indices":
            primitive["indices"] = len(accessors) - 1
        else:
            primitive["attributes"][name] = len(accessors) - 1
    if uv_sets is not None and len(triangles) and uv_sets["triangle_materials"][part["triangles"][0]] >= 0:
        primitive["material"] = int(uv_sets["triangle_materials"][part["triangles"][0]])
    return primitive
