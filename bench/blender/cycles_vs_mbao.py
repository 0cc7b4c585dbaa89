"""Cycles' AO bake beside mbao's add-on, in one Blender, on one CPU (issue 62).

The Damaged Helmet (or another glTF) gets a new UV map without overlaps, mbao's
generated one (the helmet's own mirrors halves, which mbao refuses and Cycles
overwrites). Both bake b = 1 into it at one size, margin and AO
distance; each at a sample count that reaches one RMS standard error over the
texels whose centres a triangle holds (Cycles' error from two seeds' difference,
mbao's its own). Then mbao
bakes b = 2 at its count. Run by bench/blender/run.py, which installs the
add-on; writes JSON to the path after `--`.
"""

import json
import math
import os
import platform
import sys
import time

import bpy
import numpy as np

ARGUMENTS = dict(
    zip(("scene", "size", "padding", "distance", "mbao_samples", "output"), sys.argv[sys.argv.index("--") + 1 :])
)
SIZE, PADDING = int(ARGUMENTS["size"]), int(ARGUMENTS["padding"])
DISTANCE, MBAO_SAMPLES = float(ARGUMENTS["distance"]), int(ARGUMENTS["mbao_samples"])
PILOT_SAMPLES = (16, 64)  # Cycles' sample counts whose errors fix its error's power law


def scene_with_lightmap_uvs(path):
    """The file's triangles as one smooth-shaded Blender mesh, read by mbao (Debian's Blender 3.4.1
    cannot import glTF beside Debian's numpy 1.24: its importer uses np.bool), in a UV map of
    mbao's generated charts (SPEC 6.3) at the bake's size and padding, welded where positions meet."""
    import mbao

    loaded = mbao.load(path)
    charts = mbao.bake(
        loaded,
        target="texture",
        texcoord="generate",
        resolution=SIZE,
        padding=PADDING,
        samples=2,
        max_distance=DISTANCE,
        progress=False,
    ).textures
    corner_uvs = np.zeros((loaded.triangle_count, 3, 2), np.float32)
    for texture in charts.values():
        corner_uvs[texture.triangles] = texture.texcoords
    bpy.ops.wm.read_homefile(use_empty=True)
    mesh = bpy.data.meshes.new("scene")
    mesh.from_pydata(loaded.vertices.tolist(), [], loaded.indices.tolist())
    mesh.polygons.foreach_set("use_smooth", np.ones(len(mesh.polygons), bool))
    mesh.uv_layers.new(name="lightmap").data.foreach_set("uv", corner_uvs.ravel())  # loop 3 t + k: corner k of t
    mesh.update()
    obj = bpy.data.objects.new("scene", mesh)
    bpy.context.scene.collection.objects.link(obj)
    obj.data.materials.append(bpy.data.materials.new("baked"))
    bpy.context.view_layer.objects.active = obj
    obj.select_set(True)
    bpy.ops.object.mode_set(mode="EDIT")
    bpy.ops.mesh.select_all(action="SELECT")
    bpy.ops.mesh.remove_doubles(threshold=1e-6)  # smooth normals across the file's seams
    bpy.ops.object.mode_set(mode="OBJECT")
    return obj


def image_in_every_material(obj, name):
    """A float image, the active Image Texture node of each of obj's materials (where Cycles bakes)."""
    image = bpy.data.images.new(name, SIZE, SIZE, float_buffer=True)
    image.colorspace_settings.name = "Non-Color"
    for material in obj.data.materials:
        material.use_nodes = True
        node = material.node_tree.nodes.new("ShaderNodeTexImage")
        node.image = image
        material.node_tree.nodes.active = node
    return image


def pixels(image):
    values = np.empty(SIZE * SIZE * 4, np.float32)
    image.pixels.foreach_get(values)
    return values.reshape(SIZE, SIZE, 4)[..., 0].astype(np.float64)


def baked_by_cycles(image, samples, seed):
    scene = bpy.context.scene
    scene.cycles.samples, scene.cycles.seed = samples, seed
    started = time.perf_counter()
    bpy.ops.object.bake(type="AO", margin=PADDING, margin_type="EXTEND", use_clear=True)
    return time.perf_counter() - started, pixels(image)


def texels_cycles_bakes(image):
    """The texels whose centres a triangle holds: those Cycles bakes before its margin (the rest it
    extends into), where both bakers estimate the surface's AO."""
    image.pixels.foreach_set(np.full(SIZE * SIZE * 4, -1.0, np.float32))
    bpy.context.scene.cycles.samples = 1
    bpy.ops.object.bake(type="AO", margin=0, use_clear=False)
    return pixels(image) >= 0.0


def baked_by_mbao(image, bounces, samples):
    started = time.perf_counter()
    result = bpy.ops.mbao.bake(
        target="IMAGE",
        image=image.name,
        bounces=bounces,
        samples=samples,
        max_distance=DISTANCE,
        padding=PADDING,
        standard_error=True,
    )
    seconds = time.perf_counter() - started
    assert result == {"FINISHED"}, result
    return seconds, pixels(image), pixels(bpy.data.images[image.name + "_standard_error"])


def cycles_error(image, samples, compared):
    """Cycles' RMS standard error over the compared texels at `samples`, from two seeds' bakes."""
    _, first = baked_by_cycles(image, samples, 0)
    _, second = baked_by_cycles(image, samples, 1)
    return rms((first - second)[compared]) / math.sqrt(2.0)


def cycles_samples_for(image, target, compared):
    """The samples at which Cycles' error is `target`, by its power law through the pilots' errors:
    its Sobol sequences converge faster than 1/sqrt(samples)."""
    (n1, n2) = PILOT_SAMPLES
    e1, e2 = cycles_error(image, n1, compared), cycles_error(image, n2, compared)
    order = math.log(e1 / e2) / math.log(n2 / n1)
    return max(1, round(n2 * (e2 / target) ** (1.0 / order))), order


def where_mbaos_time_goes(samples):
    """The add-on's b = 1 bake in parts: Blender's scene as arrays, then mbao.bake of them, its
    tracing (the renderer's frame_ms) apart from the rest (the texel layout, dilation)."""
    import mbao
    from mbao_bake.scene_arrays import bake_input

    started = time.perf_counter()
    given = bake_input(bpy.context, {"target": "IMAGE", "image": "mbao"})
    arrays = given.arrays
    converted = time.perf_counter()
    mesh = mbao.Mesh(arrays["vertices"], arrays["indices"], arrays["normals"], arrays["texcoords"])
    result = mbao.bake(
        mesh,
        target="texture",
        triangles=arrays["triangles"],
        texcoord=0,
        resolution=SIZE,
        padding=PADDING,
        samples=samples,
        max_distance=DISTANCE,
        progress=False,
    )
    baked = time.perf_counter()
    tracing = result.stats["frame_ms"] / 1e3
    return {
        "scene_to_arrays_seconds": converted - started,
        "bake_seconds": baked - converted,
        "tracing_seconds": tracing,
        "mrays_per_s": result.stats["rays_secondary"] / tracing / 1e6,
    }


def rms(values):
    return float(math.sqrt(np.mean(np.square(values))))


def _cpu_name():
    with open("/proc/cpuinfo") as info:
        return next(
            (line.split(":", 1)[1].strip() for line in info if line.startswith("model name")), platform.machine()
        )


def main():
    import mbao_bake.jobs

    sys.path.insert(0, mbao_bake.jobs.location()["package"])  # mbao, as the add-on finds it
    obj = scene_with_lightmap_uvs(ARGUMENTS["scene"])
    scene = bpy.context.scene
    scene.render.engine = "CYCLES"
    scene.cycles.device = "CPU"
    scene.cycles.use_denoising = False  # raw estimates (and Debian's Cycles has no denoiser: it bakes zeros)
    scene.world = bpy.data.worlds.new("world")
    scene.world.light_settings.distance = DISTANCE
    cycles_image = image_in_every_material(obj, "cycles")
    mbao_image = bpy.data.images.new("mbao", SIZE, SIZE, float_buffer=True)

    bpy.ops.mbao.bake(target="IMAGE", image="mbao", samples=2, max_distance=DISTANCE)  # kernels built
    mbao_seconds, mbao_values, mbao_error = baked_by_mbao(mbao_image, 1, MBAO_SAMPLES)
    compared = texels_cycles_bakes(cycles_image)
    target = rms(mbao_error[compared])
    cycles_samples, cycles_order = cycles_samples_for(cycles_image, target, compared)
    cycles_seconds, cycles_values = baked_by_cycles(cycles_image, cycles_samples, 2)
    _, cycles_again = baked_by_cycles(cycles_image, cycles_samples, 3)
    achieved_error = rms((cycles_values - cycles_again)[compared]) / math.sqrt(2.0)
    b2_seconds, b2_values, b2_error = baked_by_mbao(mbao_image, 2, MBAO_SAMPLES)
    parts = where_mbaos_time_goes(MBAO_SAMPLES)

    difference = (mbao_values - cycles_values)[compared]
    z = difference / np.sqrt(mbao_error[compared] ** 2 + achieved_error**2)
    obj.data.calc_loop_triangles()
    import mbao

    result = {
        "scene": os.path.basename(os.path.dirname(ARGUMENTS["scene"])),
        "triangles": len(obj.data.loop_triangles),
        "size": SIZE,
        "padding": PADDING,
        "distance": DISTANCE,
        "blender": bpy.app.version_string,
        "cpu": _cpu_name(),
        "cores": os.cpu_count(),
        "device": f"{mbao.devices()[0].platform}: {mbao.devices()[0].name}",
        "device_version": mbao.devices()[0].version,
        "compared_texels": int(compared.sum()),
        "cycles": {
            "samples": cycles_samples,
            "seconds": cycles_seconds,
            "rms_standard_error": achieved_error,
            "error_order": cycles_order,
            "mean": float(cycles_values[compared].mean()),
        },
        "mbao_b1": {
            "samples": MBAO_SAMPLES,
            "seconds": mbao_seconds,
            "rms_standard_error": target,
            **parts,
            "mean": float(mbao_values[compared].mean()),
        },
        "mbao_b2": {
            "samples": MBAO_SAMPLES,
            "seconds": b2_seconds,
            "rms_standard_error": rms(b2_error[compared]),
            "mean": float(b2_values[compared].mean()),
        },
        "b1_difference": {
            "mean": float(difference.mean()),
            "rms": rms(difference),
            "mean_z": float(z.mean()),
            "rms_z": rms(z),
            "beyond_4_sigma": float(np.mean(np.abs(z) > 4.0)),
        },
    }
    with open(ARGUMENTS["output"], "w") as out:
        json.dump(result, out, indent=2)
    print(json.dumps(result, indent=2))


main()
