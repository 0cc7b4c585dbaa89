import os
import pathlib

import numpy as np
import pytest

from mbao.devices import resolve

REPO = pathlib.Path(__file__).resolve().parents[1]
# Tests may read the shared test scenes next to the checkout (the package never does).
SHARED_SCENES = pathlib.Path(os.environ.get("MBAO_SHARED_SCENES", REPO.parent / "shared" / "scenes"))


def shared_scene(name):
    """Path of shared/scenes/<name>/, or skip when the shared scenes are not there."""
    folder = SHARED_SCENES / name
    if not (folder / "scene.glb").exists():
        pytest.skip(f"shared scene {name} not found under {SHARED_SCENES}")
    return folder


@pytest.fixture(scope="session")
def device():
    """The device every test renders on: $MBAO_DEVICE, else the first GPU, else the first device."""
    return resolve(None)


@pytest.fixture(scope="module")
def blender_home(tmp_path_factory):
    """A Blender user folder with the add-on installed and enabled (tests/blender_harness.py)."""
    from blender_harness import installed_home

    return installed_home(tmp_path_factory.mktemp("blender"))


@pytest.fixture
def rng():
    return np.random.default_rng(20261122)


@pytest.fixture(scope="session")
def dask_client():
    """A Dask client of two worker processes, one thread each, on this machine.
    Its scheduler's HTTP server (a dashboard_address of None is Dask's default,
    port 8787 on every interface) listens on loopback, on a port of its own for
    each pytest worker."""
    distributed = pytest.importorskip("distributed")
    with distributed.LocalCluster(
        n_workers=2, threads_per_worker=1, processes=True, dashboard_address="127.0.0.1:0"
    ) as cluster, distributed.Client(cluster) as client:
        yield client
