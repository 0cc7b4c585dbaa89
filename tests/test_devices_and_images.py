"""The Python API's contract for mbao.devices (every way of naming one) and
mbao.save_image (PNG, EXR, masks, and what it refuses).
"""

import re

import numpy as np
import pytest

import mbao


@pytest.fixture(scope="module")
def cornell():
    return mbao.cornell_box()


# -- devices ----------------------------------------------------------------------------


def test_devices_are_listed(device):
    listed = mbao.devices()
    assert isinstance(listed, list) and listed
    for i, d in enumerate(listed):
        assert isinstance(d, mbao.Device)
        assert d.index == i
        assert isinstance(d.name, str) and d.name
        assert isinstance(d.platform, str) and d.platform
        assert d.type in ("GPU", "CPU", "accelerator", "other")
    assert device in listed


def pyopencl_device(device):
    import pyopencl

    matches = [
        d
        for platform in pyopencl.get_platforms()
        if platform.name.strip() == device.platform
        for d in platform.get_devices()
        if d.name.strip() == device.name
    ]
    assert matches, f"pyopencl does not list {device!r}"
    return matches[0]


def test_every_way_of_naming_a_device_gives_the_same_image(cornell, device):
    ways = {
        "None": None,
        "index": device.index,
        "numpy index": np.int64(device.index),
        "name, upper case": device.name.upper(),
        "name, lower case": device.name.lower(),
        "platform: name": f"{device.platform}: {device.name}",
        "mbao.Device": device,
        "pyopencl.Device": pyopencl_device(device),
    }
    reference = None
    for way, value in ways.items():
        result = mbao.render(cornell, width=16, height=16, seed=11, device=value)
        assert device.name in result.stats["device"], way
        if reference is None:
            reference = result
        else:
            np.testing.assert_array_equal(result.ao, reference.ao, err_msg=way)
            np.testing.assert_array_equal(result.mask, reference.mask, err_msg=way)


def test_device_negative_index(cornell):
    with pytest.raises(ValueError, match="device"):
        mbao.render(cornell, width=1, height=1, device=-1)


# -- mbao.save_image -------------------------------------------------------------------


def read_image(path):
    import OpenImageIO as oiio

    image = oiio.ImageBuf(str(path))
    assert not image.has_error, image.geterror()
    return image.spec(), image.get_pixels(oiio.FLOAT)


def test_save_png_is_8_bit_and_clipped(tmp_path):
    values = np.linspace(-0.5, 1.5, 12, dtype=np.float32).reshape(3, 4)
    mbao.save_image(tmp_path / "ao.png", values)
    spec, pixels = read_image(tmp_path / "ao.png")
    assert (spec.width, spec.height, spec.nchannels) == (4, 3, 1)
    assert spec.format == "uint8"
    expected = np.round(np.clip(values, 0.0, 1.0) * 255.0) / 255.0
    np.testing.assert_allclose(pixels[..., 0], expected, atol=0.5 / 255.0)
    assert pixels.min() == 0.0 and pixels.max() == 1.0


def test_save_exr_round_trips_float32(tmp_path, rng):
    values = (rng.random((5, 7)) * 3.0 - 1.0).astype(np.float32)
    mbao.save_image(str(tmp_path / "ao.exr"), values)
    spec, pixels = read_image(tmp_path / "ao.exr")
    assert (spec.width, spec.height, spec.nchannels) == (7, 5, 1)
    np.testing.assert_array_equal(pixels[..., 0], values)


def test_save_rgb_image(tmp_path, rng):
    values = rng.random((4, 6, 3)).astype(np.float32)
    mbao.save_image(tmp_path / "rgb.exr", values)
    spec, pixels = read_image(tmp_path / "rgb.exr")
    assert spec.nchannels == 3
    np.testing.assert_array_equal(pixels, values)


def test_save_mask(tmp_path, cornell):
    result = mbao.render(cornell, width=8, height=8)
    mask = np.zeros((4, 5), bool)
    mask[1:3, 2:] = True
    mbao.save_image(tmp_path / "mask.png", mask)
    _, pixels = read_image(tmp_path / "mask.png")
    np.testing.assert_array_equal(pixels[..., 0], mask.astype(np.float32))
    mbao.save_image(tmp_path / "render_mask.png", result.mask)  # a Result's mask as it is
    assert read_image(tmp_path / "render_mask.png")[1].shape == (8, 8, 1)


@pytest.mark.parametrize("shape", [(5,), (2, 2, 2, 2), (0, 3), ()])
def test_save_image_refuses_bad_shapes(tmp_path, shape):
    with pytest.raises(ValueError, match="shape"):
        mbao.save_image(tmp_path / "x.png", np.zeros(shape, np.float32))


@pytest.mark.parametrize("array", [np.full((2, 2), "a"), np.full((2, 2), None), np.zeros((2, 2), complex)])
def test_save_image_refuses_non_numbers(tmp_path, array):
    with pytest.raises(TypeError, match="dtype"):
        mbao.save_image(tmp_path / "x.png", array)
    assert not (tmp_path / "x.png").exists()


def test_save_image_unknown_extension_says_why(tmp_path):
    path = tmp_path / "ao.xyz"
    with pytest.raises((ValueError, OSError)) as info:
        mbao.save_image(path, np.zeros((2, 2), np.float32))
    # Beyond the file name, the message says what is wrong: the format or extension.
    reason = str(info.value).replace(str(path), "")
    assert re.search(r"(?i)format|extension|\.xyz", reason), f"unhelpful message: {info.value}"


def test_save_image_into_missing_folder(tmp_path):
    with pytest.raises(OSError, match="no_such_folder"):
        mbao.save_image(tmp_path / "no_such_folder" / "ao.png", np.zeros((2, 2), np.float32))
