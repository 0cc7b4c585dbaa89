"""Writes the fuzzer's seed corpus, fuzz/corpus/: small glTF files that between
them reach every part of the loader (containers, node transforms, cameras,
index types, interleaved and sparse accessors, triangle strips and fans, alpha
masks from a bufferView, a data URI and an external file, KHR_texture_transform),
and copies of one of them that glTF-Transform quantized (KHR_mesh_quantization)
and compressed (KHR_draco_mesh_compression, EXT_meshopt_compression), as a user's
files come. The files are committed; rerun this only to change them, after
`make test` has installed glTF-Transform:

    .venv/bin/python fuzz/make_corpus.py
"""

import pathlib
import subprocess
import sys
import tempfile

import numpy as np

HERE = pathlib.Path(__file__).resolve().parent
GLTF_TRANSFORM = HERE.parent / "tests" / "gltf_transform" / "node_modules" / ".bin" / "gltf-transform"
sys.path.insert(0, str(HERE.parent / "tests"))

from gltf_writer import (  # noqa: E402
    CLAMP_TO_EDGE,
    FLOAT,
    LINES,
    MIRRORED_REPEAT,
    TRIANGLE_FAN,
    TRIANGLE_STRIP,
    UNSIGNED_BYTE,
    UNSIGNED_SHORT,
    GltfBuilder,
    png_bytes,
)

TRIANGLE = np.float32([[0, 0, 0], [1, 0, 0], [0, 1, 0]])
QUAD = np.float32([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]])
QUAD_INDICES = [0, 1, 2, 0, 2, 3]
QUAD_UV = np.float32([[0, 0], [1, 0], [1, 1], [0, 1]])


def triangle(b):
    b.add_scene([b.add_node(mesh=b.add_mesh([b.primitive(TRIANGLE, [0, 1, 2], index_type=UNSIGNED_BYTE)]))])


def hierarchy(b):
    """TRS and matrix nodes, normals, a camera, two scenes with a default, a skipped LINES primitive."""
    quad = b.primitive(QUAD, QUAD_INDICES, normals=np.tile(np.float32([0, 0, 1]), (4, 1)), index_type=UNSIGNED_SHORT)
    mesh = b.add_mesh([quad, b.primitive(QUAD, [0, 1, 1, 2], mode=LINES)])
    child = b.add_node(mesh=mesh, matrix=np.diag([1.0, 2.0, 1.0, 1.0]))
    eye = b.add_node(camera=b.add_perspective_camera(0.8), translation=(0, 0, 5))
    root = b.add_node(
        mesh=mesh, translation=(1, 2, 3), rotation=(0, 0.382683, 0, 0.92388), scale=(2, 2, 2), children=[child]
    )
    b.add_scene([b.add_node(mesh=mesh)])
    b.add_scene([root, eye, b.add_node(camera=b.add_orthographic_camera())], default=True)


def layouts(b):
    """Interleaved attributes with a byteStride, and sparse accessors with and without a base."""
    position, normal = b.add_interleaved([QUAD, np.tile(np.float32([0, 1, 0]), (4, 1))], byte_stride=32)
    sparse = b.add_sparse(3, indices=[1, 2], values=[[1, 0, 0], [0, 1, 0]], base=None, index_type=UNSIGNED_BYTE)
    moved = b.add_sparse(4, indices=[3], values=[[0, 2, 0]], base=QUAD)
    mesh = b.add_mesh(
        [
            b.primitive(position_accessor=position, normal_accessor=normal, indices=QUAD_INDICES),
            b.primitive(position_accessor=sparse),
            b.primitive(position_accessor=moved, indices=QUAD_INDICES),
        ]
    )
    b.add_scene([b.add_node(mesh=mesh)])


def strips_and_fans(b):
    """A strip and a fan, each indexed and not."""
    pentagon = np.float32([[0, 0, 0], [1, 0, 0], [1.3, 1, 0], [0.5, 1.6, 0], [-0.3, 1, 0]])
    b.add_scene(
        [
            b.add_node(
                mesh=b.add_mesh(
                    [
                        b.primitive(pentagon, [0, 1, 4, 2, 3], mode=TRIANGLE_STRIP, index_type=UNSIGNED_BYTE),
                        b.primitive(pentagon, mode=TRIANGLE_STRIP),
                        b.primitive(pentagon, [0, 1, 2, 3, 4], mode=TRIANGLE_FAN, index_type=UNSIGNED_SHORT),
                        b.primitive(pentagon, mode=TRIANGLE_FAN),
                    ]
                )
            )
        ]
    )


def transformed_mask(b, tmp):
    """A mask whose texture is offset, rotated and scaled by KHR_texture_transform."""
    masked(b, "bufferView", tmp)
    info = b.doc["materials"][0]["pbrMetallicRoughness"]["baseColorTexture"]
    info["extensions"] = {"KHR_texture_transform": {"offset": [0.25, 0.5], "rotation": 0.3, "scale": [2, 0.5]}}
    b.doc["extensionsUsed"] = b.doc["extensionsRequired"] = ["KHR_texture_transform"]


def encoded_copies(source, out):
    """glTF-Transform's quantized, Draco and meshopt copies of `source`."""
    if not GLTF_TRANSFORM.exists():
        sys.exit(f"{GLTF_TRANSFORM} is missing: `make test` installs it")
    for command in ("quantize", "draco", "meshopt"):
        subprocess.run(
            [str(GLTF_TRANSFORM), command, str(source), str(out / f"{command}.glb")], check=True, capture_output=True
        )


def masked(b, where, tmp):
    """A MASK material whose alpha comes from a 2 x 2 grey-alpha PNG stored `where`."""
    pixels = np.uint8([[[255, 255], [255, 0]], [[255, 0], [255, 255]]])
    image = b.add_image(png_bytes(pixels, tmp), where=where, file_name="mask.png")
    texture = b.add_texture(image, wrap_s=CLAMP_TO_EDGE, wrap_t=MIRRORED_REPEAT)
    material = b.add_material(alpha_mode="MASK", alpha_cutoff=0.5, base_color_factor=(1, 1, 1, 0.9), texture=texture)
    uv_type = UNSIGNED_BYTE if where == "bufferView" else FLOAT  # normalized bytes, or floats
    mesh = b.add_mesh(
        [
            b.primitive(QUAD, QUAD_INDICES, texcoords=QUAD_UV, texcoord_type=uv_type, material=material),
            b.primitive(TRIANGLE, material=b.add_material(alpha_mode="MASK", base_color_factor=(1, 1, 1, 0.2))),
        ]
    )
    b.add_scene([b.add_node(mesh=mesh)])


def main():
    out = HERE / "corpus"
    out.mkdir(exist_ok=True)
    with tempfile.TemporaryDirectory() as tmp:
        seeds = {
            "triangle.gltf": triangle,
            "hierarchy.glb": hierarchy,
            "layouts.glb": layouts,
            "mask_in_buffer.glb": lambda b: masked(b, "bufferView", tmp),
            "mask_data_uri.gltf": lambda b: masked(b, "data-uri", tmp),
            "strips_and_fans.glb": strips_and_fans,
            "texture_transform.glb": lambda b: transformed_mask(b, tmp),
        }
        for name, fill in seeds.items():
            b = GltfBuilder()
            fill(b)
            b.write(out / name)
        b = GltfBuilder()
        masked(b, "file", tmp)
        b.write_gltf_external(out / "external.gltf", bin_name="external.bin")
        for name in b.files:
            (out / name).write_bytes(b.files[name])
        encoded_copies(out / "mask_in_buffer.glb", out)


if __name__ == "__main__":
    main()
