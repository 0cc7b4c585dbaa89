"""OpenCL failures become mbao errors that say what to do (issue 6). The
kernel build log and the memory estimate are checked in tests/cpp/test_device_limits.cpp."""

import os
import subprocess
import sys

import pytest

PROGRAM = """
import mbao
try:
    mbao.render(mbao.cornell_box(), width=4, height=4)
except Exception as error:
    print(type(error).__name__, error, sep=": ")
"""


def run_in_a_process(**environment):
    """The device list is read once per process: a fresh one sees the environment."""
    result = subprocess.run(
        [sys.executable, "-c", PROGRAM], env={**os.environ, **environment}, capture_output=True, text=True, timeout=120
    )
    assert result.returncode == 0, result.stderr
    return result.stdout.strip()


def test_no_opencl_platform_is_a_device_error_that_says_what_to_install(tmp_path):
    # ocl-icd reads the drivers from OCL_ICD_VENDORS: an empty directory is a machine without any.
    output = run_in_a_process(OCL_ICD_VENDORS=str(tmp_path))
    assert output.startswith("DeviceError: no OpenCL device found")
    assert "pocl-opencl-icd" in output


@pytest.mark.parametrize("value", ["no-such-gpu", "99", "99999999999999999999999"])
def test_mbao_device_naming_no_device_lists_the_devices_there_are(device, value):
    output = run_in_a_process(MBAO_DEVICE=value)
    assert output.startswith(f'ValueError: MBAO_DEVICE="{value}" names no device')
    assert device.name in output
