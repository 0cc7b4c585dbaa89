"""Small scene files in the formats Assimp reads, for the tests and the fuzzer's seeds."""

import struct


def write_obj(path, vertices, triangles, normals=None):
    lines = [f"v {x!r} {y!r} {z!r}" for x, y, z in vertices.tolist()]
    if normals is None:
        lines += [f"f {a + 1} {b + 1} {c + 1}" for a, b, c in triangles.tolist()]
    else:
        lines += [f"vn {x!r} {y!r} {z!r}" for x, y, z in normals.tolist()]
        lines += [f"f {a + 1}//{a + 1} {b + 1}//{b + 1} {c + 1}//{c + 1}" for a, b, c in triangles.tolist()]
    path.write_text("\n".join(lines) + "\n")


def write_ply(path, vertices, triangles, binary):
    header = (
        f"ply\nformat {'binary_little_endian' if binary else 'ascii'} 1.0\nelement vertex {len(vertices)}\n"
        "property float x\nproperty float y\nproperty float z\n"
        f"element face {len(triangles)}\nproperty list uchar int vertex_indices\nend_header\n"
    )
    if binary:
        body = vertices.astype("<f4").tobytes() + b"".join(struct.pack("<B3i", 3, *t) for t in triangles.tolist())
        path.write_bytes(header.encode() + body)
    else:
        rows = [f"{x!r} {y!r} {z!r}" for x, y, z in vertices.tolist()] + [
            f"3 {a} {b} {c}" for a, b, c in triangles.tolist()
        ]
        path.write_text(header + "\n".join(rows) + "\n")


# A triangle under two nodes (translated, then scaled) and a camera without an
# aspect ratio, which Assimp 5.2 reads without its field of view.
COLLADA = """<?xml version="1.0" encoding="utf-8"?>
<COLLADA xmlns="http://www.collada.org/2005/11/COLLADASchema" version="1.4.1">
  <asset><unit name="meter" meter="1"/><up_axis>Y_UP</up_axis></asset>
  <library_cameras><camera id="cam"><optics><technique_common><perspective>
    <yfov>40</yfov><aspect_ratio>1.5</aspect_ratio><znear>0.1</znear><zfar>100</zfar>
  </perspective></technique_common></optics></camera></library_cameras>
  <library_geometries><geometry id="tri"><mesh>
    <source id="pos"><float_array id="pos-array" count="9">0 0 0 1 0 0 0 1 0</float_array>
      <technique_common><accessor source="#pos-array" count="3" stride="3">
        <param name="X" type="float"/><param name="Y" type="float"/><param name="Z" type="float"/>
      </accessor></technique_common></source>
    <vertices id="verts"><input semantic="POSITION" source="#pos"/></vertices>
    <triangles count="1"><input semantic="VERTEX" source="#verts" offset="0"/><p>0 1 2</p></triangles>
  </mesh></geometry></library_geometries>
  <library_visual_scenes><visual_scene id="scene">
    <node id="outer" name="outer"><translate>10 20 30</translate>
      <node id="inner" name="inner"><scale>2 2 2</scale><instance_geometry url="#tri"/></node>
    </node>
    <node id="eye" name="eye"><translate>0 1 5</translate><instance_camera url="#cam"/></node>
  </visual_scene></library_visual_scenes>
  <scene><instance_visual_scene url="#scene"/></scene>
</COLLADA>
"""
