"""Renders docs/helmet_bake.png: the Damaged Helmet shaded by its artist's
occlusion texture, and by mbao's b = 1 and b = 2 bakes into generated UVs (its
own UVs are mirrored, which a per-texel bake refuses). Each panel looks its
texture up at the camera rays' hits. Run from the repository root:
.venv/bin/python docs/helmet_bake.py"""

import math
import pathlib
import tempfile

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import OpenImageIO as oiio  # noqa: E402

import mbao  # noqa: E402
from mbao._gltf import GltfDocument  # noqa: E402

here = pathlib.Path(__file__).resolve().parent
folder = here.parent.parent / "shared" / "scenes" / "damaged_helmet"
SIZE, RESOLUTION, SAMPLES = 384, 1024, 64


def camera_hits(scene, camera):
    """Triangle and barycentrics of the ray through each pixel centre (SPEC 3.1)."""
    eye, target, up = (np.asarray(v, float) for v in (camera.eye, camera.target, camera.up))
    forward = (target - eye) / np.linalg.norm(target - eye)
    right = np.cross(forward, up) / np.linalg.norm(np.cross(forward, up))
    true_up = np.cross(right, forward)
    tan_half = math.tan(math.radians(camera.vfov_deg) / 2)
    y, x = np.mgrid[0:SIZE, 0:SIZE]
    u, v = ((x + 0.5) / SIZE) * 2 - 1, 1 - ((y + 0.5) / SIZE) * 2
    directions = forward + (u * tan_half)[..., None] * right + (v * tan_half)[..., None] * true_up
    _, triangle, barycentrics = mbao.trace(scene, np.tile(eye, (SIZE * SIZE, 1)), directions.reshape(-1, 3))
    return triangle, barycentrics


def bilinear_repeat(image, uv):
    """The image looked up bilinearly at uv (N, 2) with REPEAT, row 0 at v = 0."""
    height, width = image.shape
    x, y = uv[:, 0] * width - 0.5, uv[:, 1] * height - 0.5
    x0, y0 = np.floor(x).astype(int), np.floor(y).astype(int)
    fx, fy = x - x0, y - y0

    def at(i, j):
        return image[np.mod(j, height), np.mod(i, width)]

    return (
        (1 - fx) * (1 - fy) * at(x0, y0)
        + fx * (1 - fy) * at(x0 + 1, y0)
        + (1 - fx) * fy * at(x0, y0 + 1)
        + fx * fy * at(x0 + 1, y0 + 1)
    )


def shaded(triangle, barycentrics, corner_uvs, image):
    """Each pixel's texture value at its hit, white where the ray missed."""
    hit = triangle >= 0
    corners = corner_uvs[triangle[hit]]
    b1, b2 = barycentrics[hit, 0:1], barycentrics[hit, 1:2]
    uv = (1 - b1 - b2) * corners[:, 0] + b1 * corners[:, 1] + b2 * corners[:, 2]
    pixels = np.ones(SIZE * SIZE)
    pixels[hit] = bilinear_repeat(image, uv)
    return pixels.reshape(SIZE, SIZE)


def shipped_occlusion(path, scene):
    """The artist's occlusion texture (its R channel) and the corners' UVs in the set it reads."""
    document = GltfDocument(path)
    material = document.doc["materials"][0]["occlusionTexture"]
    image = document.doc["images"][document.doc["textures"][material["index"]]["source"]]
    view = document.doc["bufferViews"][image["bufferView"]]
    start = view.get("byteOffset", 0)
    with tempfile.TemporaryDirectory() as temporary:
        encoded = pathlib.Path(temporary) / "occlusion"
        encoded.write_bytes(document.bin[start : start + view["byteLength"]])
        pixels = oiio.ImageBuf(str(encoded)).get_pixels(oiio.FLOAT)[..., 0]
    return pixels, scene.uv_sets["sets"][material.get("texCoord", 0)][scene.indices]


def main():
    path = folder / "scene.glb"
    scene = mbao.load(path, texcoords=True)
    camera = mbao.Camera.load(folder / "camera.json")
    radius = camera.max_distance  # the bakes' radius, as a render from this camera would take it
    triangle, barycentrics = camera_hits(scene, camera)
    shipped, shipped_uvs = shipped_occlusion(path, scene)
    panels = [("the artist's occlusion texture", shaded(triangle, barycentrics, shipped_uvs, shipped))]
    for bounces in (1, 2):
        bake = mbao.bake(
            scene,
            target="texture",
            texcoord="generate",
            resolution=RESOLUTION,
            samples=SAMPLES,
            bounces=bounces,
            camera=camera,
            progress=False,
        )
        texture = bake.textures[0]
        corner_uvs = np.zeros((scene.triangle_count, 3, 2), np.float32)
        corner_uvs[texture.triangles] = texture.texcoords
        panels.append((f"mbao, b = {bounces}", shaded(triangle, barycentrics, corner_uvs, texture.image)))
        print(f"b = {bounces}: {bake.stats['frame_ms'] / 1e3:.1f} s, {texture.stats['charts']} charts")
    figure, axes = plt.subplots(1, 3, figsize=(12, 4.3))
    for axis, (title, image) in zip(axes, panels):
        axis.imshow(image, cmap="gray", vmin=0, vmax=1)
        axis.set_title(title)
        axis.axis("off")
    figure.suptitle(
        f"Damaged Helmet: max_distance {radius}, rho 1, {RESOLUTION}x{RESOLUTION} generated UVs, "
        f"{SAMPLES} estimates per texel of {bake.settings['directions']} {bake.settings['estimator']}s each",
        fontsize=10,
    )
    figure.tight_layout()
    figure.savefig(here / "helmet_bake.png", dpi=80)


if __name__ == "__main__":
    main()
