"""Camera rays walked sixteen to a packet (traversal "lanes", kernels/kd_packet.h)
find what each finds walked alone (the full stack, one ray per work item): the
same image and the same traversal counts, bit for bit, whatever the image's
size, tiles and camera samples cut the packets into, from an eye inside the
scene, from one outside it, and from one on a split plane, where the rays of a
packet part at the first node."""

import numpy as np
import pytest

import mbao
from meshes import random_soup


@pytest.fixture(scope="module")
def soup():
    scene = mbao.Mesh(*random_soup(np.random.default_rng(7), 3000))
    assert scene.kd_tree()["stats"]["max_depth"] >= 16  # long walks, where packets part often
    return scene


def assert_packets_find_the_single_rays_hits(scene, camera, **settings):
    tile_pixels = settings.pop("tile_pixels", None)
    settings = dict(camera=camera, bounces=1, samples=2, seed=11, **settings)
    engine = dict(traversal_stats=True, tile_pixels=tile_pixels)
    packets = mbao.render(scene, engine=mbao.Engine(traversal="lanes", **engine), **settings)
    alone = mbao.render(scene, engine=mbao.Engine(traversal="stack", organisation="wavefront", **engine), **settings)
    assert packets.stats["traversal_mode"] == "lanes" and alone.stats["traversal_mode"] == "stack"
    np.testing.assert_array_equal(packets.ao, alone.ao)
    np.testing.assert_array_equal(packets.mask, alone.mask)
    assert packets.stats["traversal"] == alone.stats["traversal"]
    # Not vacuous: some camera rays hit, some miss, and the hits are shaded.
    assert 0 < packets.mask.sum() < packets.mask.size
    assert packets.ao[packets.mask].min() < 1.0
    return packets


@pytest.mark.parametrize(
    "size, spp, tile_pixels",
    [((37, 23), 1, None), ((37, 23), 3, 100), ((16, 16), 1, 7), ((5, 3), 2, None)],
)
def test_from_an_eye_outside_the_scene(soup, size, spp, tile_pixels):
    """Image sizes, camera samples and tiles that are not multiples of sixteen
    leave the last packet of a tile part empty."""
    camera = mbao.Camera(eye=(1.6, 1.3, 2.2), target=(0.5, 0.5, 0.5), vfov_deg=50.0)
    assert_packets_find_the_single_rays_hits(
        soup, camera, width=size[0], height=size[1], spp=spp, tile_pixels=tile_pixels
    )


def test_from_an_eye_inside_the_scene(soup):
    camera = mbao.Camera(eye=(0.5, 0.45, 0.55), target=(0.9, 0.6, 0.1), vfov_deg=100.0)
    assert_packets_find_the_single_rays_hits(soup, camera, width=40, height=24)


@pytest.mark.parametrize("height", [30, 31])
def test_from_an_eye_on_the_roots_split_plane(soup, height):
    """Looking along the plane, the image's halves lie on its two sides: a ray
    there takes one child alone, decided by its direction, not by the eye.
    The 4 x 4 squares of rows 12-15 hold rays on both sides (30 rows) or, with
    31, the middle row's rays, which lie in the plane."""
    tree = soup.kd_tree()
    assert tree["origin"] == (0.0, 0.0, 0.0)  # the tree's frame is the scene's
    axis = int(tree["nodes"][0, 0] & 3)
    split = float(tree["nodes"][0:1, 1].view(np.float32)[0])
    eye, target = np.array([0.5, 0.5, -0.8]), np.array([0.5, 0.5, 0.5])
    if axis == 2:
        eye, target = np.array([-0.8, 0.5, 0.5]), np.array([0.5, 0.5, 0.5])
    eye[axis] = target[axis] = split
    up = np.eye(3)[axis]  # the plane splits the image into its top and bottom halves
    camera = mbao.Camera(eye=tuple(eye), target=tuple(target), up=tuple(up), vfov_deg=60.0)
    image = assert_packets_find_the_single_rays_hits(soup, camera, width=32, height=height)
    assert image.mask[:12].any() and image.mask[16:].any()  # triangles on both sides
