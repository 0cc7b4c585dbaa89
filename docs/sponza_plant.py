"""Renders docs/sponza_plant_masks.png and docs/sponza_plant_solid.png: one of
Sponza's potted plants with its alpha masks, and the same triangles as solid
quads. Run from the repository root: .venv/bin/python docs/sponza_plant.py"""

import pathlib

import mbao

here = pathlib.Path(__file__).resolve().parent
scene = mbao.load(here.parent.parent / "shared" / "scenes" / "sponza" / "scene.glb")
solid = mbao.Mesh(scene.vertices, scene.indices, scene.normals)
camera = mbao.Camera((-830.0, 170.0, -110.0), (-960.0, 50.0, -230.0), vfov_deg=40.0)
for name, target in (("masks", scene), ("solid", solid)):
    result = mbao.render(target, camera=camera, width=256, height=256, samples=64, max_distance=300.0)
    mbao.save_image(here / f"sponza_plant_{name}.png", result.ao)
    print(name, f"{result.stats['frame_ms']:.0f} ms")
