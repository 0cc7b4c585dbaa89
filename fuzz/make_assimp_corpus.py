"""Writes the Assimp loader fuzzer's seed corpus, fuzz/assimp_corpus/: a small
file of each text format the fuzzer picks, after the byte that picks it
(assimp_loader_fuzzer.cpp's order: obj, ply, stl, dae, ...). The files are
committed; rerun this only to change them:

    .venv/bin/python fuzz/make_assimp_corpus.py
"""

import pathlib
import sys

HERE = pathlib.Path(__file__).resolve().parent
OUT = HERE / "assimp_corpus"
sys.path.insert(0, str(HERE.parent / "tests"))

from scene_files import COLLADA  # noqa: E402

SEEDS = {
    "triangle.obj": (
        0,
        "o t\nv 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 0 1\nvn 0 0 1\n" "f 1/1/1 2/2/1 3/3/1\nl 1 2\n",
    ),
    "triangle.ply": (
        1,
        "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
        "property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n"
        "0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n",
    ),
    "triangle.stl": (
        2,
        "solid t\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 1 0\n"
        "endloop\nendfacet\nendsolid t\n",
    ),
    "placed.dae": (3, COLLADA),
}


def main():
    OUT.mkdir(exist_ok=True)
    for name, (format_byte, text) in SEEDS.items():
        (OUT / name).write_bytes(bytes([format_byte]) + text.encode())


if __name__ == "__main__":
    main()
