"""The public API as a typed script uses it: tests/test_typing.py checks it
with mypy --strict, which refuses a call to anything unannotated."""

from typing import Any

import numpy as np

import mbao

scene: mbao.Scene = mbao.cornell_box()
camera: mbao.Camera = mbao.Camera((278.0, 273.0, -800.0), (278.0, 273.0, 0.0), vfov_deg=39.3)
result: mbao.Result = mbao.render(scene, camera=camera, width=32, height=32, bounces=2, samples=4)
ao: "np.ndarray[Any, Any]" = result.ao
mbao.save_image("ao.png", ao, alpha=result.coverage)
frames: list[mbao.Result] = list(mbao.render_sequence(scene, [camera, "frame"], width=16, height=16))
mesh = mbao.Mesh(np.zeros((3, 3)), [[0, 1, 2]])
baked: mbao.Bake = mbao.bake(mesh, bounces=2, samples=16, progress=False)
values: "np.ndarray[Any, Any] | None" = baked.values
loaded: mbao.Scene = mbao.load("scene.glb", texcoords=True)
stored: mbao.StoredBake | None = mbao.load_bake("baked.glb")
devices: list[mbao.Device] = mbao.devices()
for done in mbao.render_many([{"scene": scene, "width": 8, "height": 8}], progress=True):
    print(done)
