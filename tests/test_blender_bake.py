"""The Blender add-on's bake (SPEC 9), in Debian's Blender, headless: its
values are mbao.bake's, it writes where it is told, refuses what it cannot do
in words, and a cancelled bake writes nothing."""

import pytest

from blender_harness import blender


def test_the_operators_settings_are_mbao_bakes(blender_home, tmp_path):
    """Named as mbao.bake's arguments, with its defaults: the estimator's in
    Blender's capitals, and no radius as a distance of 0."""
    blender(
        blender_home,
        tmp_path,
        """
        import inspect
        parameters = inspect.signature(mbao.bake).parameters
        properties = bpy.ops.mbao.bake.get_rna_type().properties
        for name in ("bounces", "samples", "rho", "seed", "padding"):
            assert properties[name].default == parameters[name].default, name
        assert properties["estimator"].default == parameters["estimator"].default.upper()
        assert parameters["max_distance"].default is None and properties["max_distance"].default == 0.0
        scene_settings = bpy.context.scene.mbao_bake.bl_rna.properties
        assert {p.identifier for p in scene_settings} - {"rna_type", "name"} == \
            {p.identifier for p in properties} - {"rna_type"}
    """,
    )


@pytest.mark.parametrize("run_in", ["BLENDER", "CHILD"])
def test_a_vertex_bake_is_mbao_bakes_values(blender_home, tmp_path, run_in):
    """The cube baked among the plane: its color attribute holds mbao.bake's
    values of the cube's triangles, the plane occluding, bit for bit, in
    Blender's process and in a child process alike; the standard error beside."""
    blender(
        blender_home,
        tmp_path,
        f"""
        bpy.context.preferences.addons["mbao_bake"].preferences.run_in = {run_in!r}
        cube, plane = cube_on_a_plane()
        result = bpy.ops.mbao.bake(bounces=2, samples=32, seed=5, max_distance=3.0, standard_error=True)
        assert result == {{"FINISHED"}}, result
        vertices = np.concatenate([world_vertices(cube), world_vertices(plane)])
        indices = np.concatenate([triangles(cube), triangles(plane) + len(cube.data.vertices)])
        expected = mbao.bake(mbao.Mesh(vertices, indices), bounces=2, samples=32, seed=5, max_distance=3.0,
                             triangles=np.arange(len(triangles(cube))), progress=False)
        n = len(cube.data.vertices)
        baked = colors(cube, "mbao_ao")
        assert np.array_equal(baked[:, 0], expected.values[:n]), abs(baked[:, 0] - expected.values[:n]).max()
        assert np.array_equal(baked[:, 1], baked[:, 0]) and np.all(baked[:, 3] == 1.0)
        assert np.array_equal(colors(cube, "mbao_ao_standard_error")[:, 0], expected.standard_error[:n])
        assert baked[:, 0].min() < 0.9 and baked[:, 0].max() == 1.0  # the foot is occluded, the top open
        assert "mbao_ao" not in plane.data.color_attributes

        assert bpy.ops.mbao.bake(bounces=2, samples=32, seed=5, max_distance=3.0, attribute="corners",
                                 domain="CORNER", preview=True) == {{"FINISHED"}}
        loop_vertices = np.empty(len(cube.data.loops), np.int32)
        cube.data.loops.foreach_get("vertex_index", loop_vertices)
        assert np.array_equal(colors(cube, "corners")[:, 0], baked[loop_vertices, 0])
        nodes = cube.active_material.node_tree.nodes  # the preview: the attribute as the base colour
        assert [n.attribute_name for n in nodes if n.type == "ATTRIBUTE"] == ["corners"]
    """,
    )


def test_a_mirrored_object_is_baked_on_its_front(blender_home, tmp_path):
    """The plane scaled by -1 along x still faces up in Blender; baked under the
    cube, it is occluded (its winding is flipped back in world space, else it
    would face down, onto nothing)."""
    blender(
        blender_home,
        tmp_path,
        """
        cube, plane = cube_on_a_plane(cuts=1)
        plane.scale = (-1.0, 1.0, 1.0)
        select(plane)
        assert bpy.ops.mbao.bake(samples=16) == {"FINISHED"}
        assert colors(plane, "mbao_ao")[:, 0].min() < 1.0
    """,
    )


def test_what_is_visible_occludes_instances_included(blender_home, tmp_path):
    """A hidden cube over the plane occludes nothing; a collection's instance
    there does, as Blender shows it, though its source lies far away."""
    blender(
        blender_home,
        tmp_path,
        """
        cube, plane = cube_on_a_plane(cuts=1)
        cube.hide_set(True)
        select(plane)
        assert bpy.ops.mbao.bake(samples=16, max_distance=2.0) == {"FINISHED"}
        assert colors(plane, "mbao_ao")[:, 0].min() == 1.0
        shelf = bpy.data.collections.new("shelf")
        bpy.context.scene.collection.children.link(shelf)
        bpy.ops.mesh.primitive_cube_add(location=(100.0, 0.0, 1.0))
        source = bpy.context.active_object
        for collection in source.users_collection:
            collection.objects.unlink(source)
        shelf.objects.link(source)
        shelf.instance_offset = (100.0, 0.0, 0.0)
        bpy.context.view_layer.layer_collection.children["shelf"].exclude = True  # only its instance is shown
        bpy.ops.object.collection_instance_add(collection="shelf", location=(0.0, 0.0, 0.0))
        select(plane)
        assert bpy.ops.mbao.bake(samples=16, max_distance=2.0) == {"FINISHED"}
        assert colors(plane, "mbao_ao")[:, 0].min() < 1.0
    """,
    )


def test_an_image_bake_fills_the_covered_texels_and_pads_the_rest(blender_home, tmp_path):
    """The floor, its UVs shrunk to the middle of a 32 x 32 float image, baked
    with padding 2: the image is mbao.bake's texture of the floor's UVs, bit for
    bit (covered texels, their dilation, and 1 beyond); saved as an 8-bit PNG
    beside the .blend, it reads back within the PNG's rounding."""
    blender(
        blender_home,
        tmp_path,
        """
        cube, plane = cube_on_a_plane(cuts=1)
        uvs = np.empty(len(plane.data.loops) * 2, np.float32)
        plane.data.uv_layers.active.data.foreach_get("uv", uvs)
        uvs = 0.25 + 0.5 * uvs
        plane.data.uv_layers.active.data.foreach_set("uv", uvs)
        plane.data.update()  # tells the depsgraph, which the add-on reads
        image = bpy.data.images.new("ao", 32, 32, float_buffer=True)
        select(plane)
        assert bpy.ops.mbao.bake(target="IMAGE", image="ao", samples=16, padding=2, preview=True) == {"FINISHED"}
        assert [n.image for n in plane.active_material.node_tree.nodes if n.type == "TEX_IMAGE"] == [image]
        pixels = np.empty(32 * 32 * 4, np.float32)
        image.pixels.foreach_get(pixels)
        pixels = pixels.reshape(32, 32, 4)

        loop_vertices = np.empty(len(plane.data.loops), np.int32)
        plane.data.loops.foreach_get("vertex_index", loop_vertices)
        corners = np.empty(len(plane.data.loop_triangles) * 3, np.int32)
        plane.data.loop_triangles.foreach_get("loops", corners)
        cube_vertices = world_vertices(cube)
        vertices = np.concatenate([world_vertices(plane)[loop_vertices], cube_vertices])
        indices = np.concatenate([corners.reshape(-1, 3), triangles(cube) + len(loop_vertices)])
        texcoords = np.concatenate([uvs.reshape(-1, 2), np.zeros((len(cube_vertices), 2))])
        expected = mbao.bake(mbao.Mesh(vertices, indices, texcoords=texcoords), target="texture", samples=16,
                             padding=2, resolution=32, triangles=np.arange(len(corners) // 3), progress=False)
        texture = expected.textures[0]
        assert np.array_equal(pixels[..., 0], texture.image)
        assert texture.coverage[8:24, 8:24].all() and texture.coverage.sum() == 16 * 16
        assert pixels[6, 16, 0] == texture.image[8, 16] and pixels[0, 0, 0] == 1.0  # padded; beyond the padding
        assert texture.image[8:24, 8:24].min() < 0.9  # the cube's foot

        bpy.ops.wm.save_as_mainfile(filepath=os.path.abspath("scene.blend"))
        select(plane)
        assert bpy.ops.mbao.bake(target="IMAGE", image="ao", samples=16, padding=2, save=True) == {"FINISHED"}
        assert image.filepath_raw == "//ao.png"
        saved = bpy.data.images.load(os.path.abspath("ao.png"))
        saved.colorspace_settings.name = "Non-Color"
        back = np.empty(32 * 32 * 4, np.float32)
        saved.pixels.foreach_get(back)
        assert np.abs(back.reshape(32, 32, 4)[..., 0] - texture.image).max() <= 0.5 / 255 + 1e-6
    """,
    )


def test_bad_settings_are_reported_not_raised(blender_home, tmp_path):
    """Each refusal is an error report naming the problem (a RuntimeError
    "Error: ..." to a script), never a traceback from inside the add-on."""
    blender(
        blender_home,
        tmp_path,
        """
        cube, plane = cube_on_a_plane(cuts=1)
        refused("samples must be in [2, 65536], got 0", samples=0)
        refused("bounces", bounces=0)
        bpy.ops.object.select_all(action="DESELECT")
        refused("select a mesh object to bake")
        select(cube)
        refused("has no image to bake into", target="IMAGE")
        refused("there is no image named 'nothing'", target="IMAGE", image="nothing")
        bpy.data.images.new("ao", 8, 8)
        refused("Save Beside .blend needs the .blend saved first", target="IMAGE", image="ao", save=True)
        twin = cube.copy()  # a linked duplicate: the same mesh
        bpy.context.collection.objects.link(twin)
        select(cube, twin)
        refused("share one mesh")
        select(cube)
        cube.data.uv_layers.remove(cube.data.uv_layers[0])
        refused(f"object {cube.name} has no UV map", target="IMAGE", image="ao")
        bpy.ops.object.modifier_add(type="SUBSURF")
        refused("modifiers make", target="COLOR_ATTRIBUTE")
        assert "mbao_ao" not in cube.data.color_attributes
    """,
    )


@pytest.mark.parametrize("run_in", ["BLENDER", "CHILD"])
def test_cancelling_leaves_the_attribute_as_it_was(blender_home, tmp_path, run_in):
    """Esc cancels the bake's job: here as the bake starts, in either place it
    runs. Nothing is written: the attribute keeps its values."""
    blender(
        blender_home,
        tmp_path,
        f"""
        import mbao_bake.jobs
        bpy.context.preferences.addons["mbao_bake"].preferences.run_in = {run_in!r}
        cube, plane = cube_on_a_plane()
        before = bpy.ops.mbao.bake(samples=4)
        kept = colors(cube, "mbao_ao").copy()
        started = mbao_bake.jobs.BakeJob.__init__

        def start_then_cancel(self, *arguments):
            started(self, *arguments)
            self.cancel()

        mbao_bake.jobs.BakeJob.__init__ = start_then_cancel
        assert bpy.ops.mbao.bake(samples=65536, seed=1) == {{"CANCELLED"}}
        assert np.array_equal(colors(cube, "mbao_ao"), kept)
    """,
    )
