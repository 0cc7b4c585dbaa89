"""Every warning mbao gives names the user's line: the first caller outside the
package, however deep inside mbao it was raised, so that Python's filters and
its message point at the code that asked (python/mbao/_warnings.py)."""


import numpy as np

import mbao
from caught_warnings import caught_warnings
from gltf_writer import LINES, GltfBuilder
from meshes import box, merge


def closed_boxes():
    """16 closed boxes in a row: with an unlimited radius every AO ray hits one."""
    vertices, indices = box((-1.0, -1.5, -2.0), (1.0, 1.5, 2.0))
    return merge(*[(vertices + (4.0 * k, 0.0, 0.0), indices) for k in range(16)])


def only_warning(call):
    """The one warning `call` gives."""
    with caught_warnings() as caught:
        call()
    assert len(caught) == 1, [str(w.message) for w in caught]
    return caught[0]


def test_a_render_of_a_closed_scene():
    inside = mbao.Camera(eye=(0.0, 0.0, 0.0), target=(0.5, 0.1, -0.3), vfov_deg=90.0)
    mesh = mbao.Mesh(*closed_boxes())
    warning = only_warning(lambda: mbao.render(mesh, camera=inside, width=16, height=16))
    assert "looks closed" in str(warning.message)
    assert warning.filename == __file__


def test_a_bake_of_a_closed_scene():
    mesh = mbao.Mesh(*closed_boxes())
    warning = only_warning(lambda: mbao.bake(mesh, samples=2, progress=False))
    assert "looks closed" in str(warning.message)
    assert warning.filename == __file__


def test_a_bake_of_a_closed_scene_through_bake_file(tmp_path):
    """bake_file calls bake, which warns: the warning still names this file, not bake_file's."""
    b = GltfBuilder()
    vertices, indices = closed_boxes()
    b.add_scene([b.add_node(mesh=b.add_mesh([b.primitive(np.float32(vertices), np.ravel(indices))]))])
    path = b.write(tmp_path / "boxes.glb")
    warning = only_warning(lambda: mbao.bake_file(path, tmp_path / "baked.glb", samples=2, progress=False))
    assert "looks closed" in str(warning.message)
    assert warning.filename == __file__


def test_a_load_that_skips_a_primitive(tmp_path):
    b = GltfBuilder()
    triangle = np.float32([[0, 0, 0], [1, 0, 0], [0, 1, 0]])
    lines = b.primitive(triangle + np.float32([0, 0, 5]), [0, 1, 1, 2], mode=LINES)
    b.add_scene([b.add_node(mesh=b.add_mesh([b.primitive(triangle, [0, 1, 2]), lines]))])
    path = b.write(tmp_path / "lines.gltf")
    warning = only_warning(lambda: mbao.load(path))
    assert "primitive 1" in str(warning.message)
    assert warning.filename == __file__
