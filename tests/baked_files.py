"""What the baked-file tests share: an input in another format, and the glTF-Validator's verdict on what mbao writes."""

import numpy as np

from mbao.check import validation_report
from meshes import plane
from scene_files import write_obj


def validation_errors(path):
    """The glTF-Validator's errors on `path`, as (code, pointer) pairs, from the
    report `python -m mbao check` reads (which fails naming how to install the
    validator where it is missing)."""
    report = validation_report(path)
    return [(m["code"], m.get("pointer")) for m in report["issues"]["messages"] if m["severity"] == 0]


def floor_and_wall_obj(tmp_path):
    """The floor and the wall standing on it as an OBJ with vertex normals."""
    floor, floor_indices = plane(1.0, divisions=4)
    wall = np.array([[-0.5, 0.0, 0.0], [0.5, 0.0, 0.0], [0.5, 1.0, 0.0], [-0.5, 1.0, 0.0]])
    vertices = np.concatenate([floor, wall])
    triangles = np.concatenate([floor_indices, np.array([[0, 1, 2], [0, 2, 3]]) + len(floor)])
    normals = np.concatenate([np.tile([0.0, 1.0, 0.0], (len(floor), 1)), np.tile([0.0, 0.0, 1.0], (4, 1))])
    write_obj(tmp_path / "floor_and_wall.obj", vertices, triangles, normals)
    return tmp_path / "floor_and_wall.obj"
