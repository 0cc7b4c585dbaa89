"""Batches: mbao.render_many renders what mbao.render renders, bit for bit,
here and on a Dask cluster of worker processes; a job that fails raises its
own error, or stands in its place with errors="return"."""

import pathlib

import numpy as np
import pytest

import mbao

CORNELL_GLB = pathlib.Path(__file__).parent / "data" / "cornell_box.glb"
SETTINGS = dict(width=24, height=16, bounces=2, samples=4)


def jobs_on(scene, count):
    return [dict(scene=scene, seed=k, **SETTINGS) for k in range(count)]


def one_by_one(jobs):
    return [mbao.render(**job).ao for job in jobs]


def assert_same_images(results, expected):
    assert len(results) == len(expected)
    for result, ao in zip(results, expected):
        np.testing.assert_array_equal(result.ao, ao)


@pytest.fixture
def client(dask_client):
    return dask_client


def test_a_batch_here_is_the_renders_one_by_one():
    jobs = jobs_on(mbao.cornell_box(), 3) + jobs_on(str(CORNELL_GLB), 2)
    assert_same_images(list(mbao.render_many(jobs)), one_by_one(jobs))


def test_a_batch_on_a_cluster_is_the_renders_one_by_one(client):
    scene = mbao.cornell_box()
    mesh = mbao.Mesh(scene.vertices, scene.indices)
    jobs = jobs_on(scene, 6) + jobs_on(str(CORNELL_GLB), 4) + jobs_on(mesh, 2)
    expected = one_by_one(jobs)
    results = list(mbao.render_many(jobs, client=client, in_flight=3))
    assert_same_images(results, expected)
    # The scene went to each worker once and kept its tree there: at most one build per worker.
    assert sum(not r.stats["tree_reused"] for r in results[:6]) <= 2


def test_workers_keep_a_scene_by_its_content(client):
    """Equal scenes, as separate objects and in separate batches, build one tree per worker."""
    jobs = [dict(scene=mbao.Mesh(np.eye(3), [[0, 1, 2]]), seed=k, width=8, height=8) for k in range(6)]
    results = list(mbao.render_many(jobs, client=client)) + list(mbao.render_many(jobs, client=client))
    assert sum(not r.stats["tree_reused"] for r in results) <= 2


def test_unordered_results_are_the_same_images(client):
    jobs = jobs_on(mbao.cornell_box(), 5)
    expected = {job["seed"]: ao for job, ao in zip(jobs, one_by_one(jobs))}
    results = list(mbao.render_many(jobs, client=client, ordered=False))
    assert len(results) == len(jobs)
    unmatched = dict(expected)
    for result in results:
        seed = next(s for s, ao in unmatched.items() if np.array_equal(ao, result.ao))
        del unmatched[seed]
    assert not unmatched


@pytest.mark.parametrize("on_cluster", [False, True])
def test_a_failed_job_raises_its_own_error(request, tmp_path, on_cluster):
    client = request.getfixturevalue("client") if on_cluster else None
    missing = tmp_path / "missing.glb"
    jobs = jobs_on(mbao.cornell_box(), 1) + jobs_on(str(missing), 1)
    with pytest.raises(mbao.LoadError, match="missing.glb"):
        list(mbao.render_many(jobs, client=client))
    results = list(mbao.render_many(jobs + jobs_on(mbao.cornell_box(), 1), client=client, errors="return"))
    assert isinstance(results[0], mbao.Result) and isinstance(results[2], mbao.Result)
    assert isinstance(results[1], mbao.LoadError) and "missing.glb" in str(results[1])
    bad_settings = [dict(scene=mbao.cornell_box(), width=0)]
    with pytest.raises(ValueError, match="width"):
        list(mbao.render_many(bad_settings, client=client))


def test_arguments_are_checked():
    with pytest.raises(ValueError, match="errors must be"):
        mbao.render_many([], errors="ignore")
    with pytest.raises(ValueError, match="in_flight must be in"):
        mbao.render_many([], client=object(), in_flight=0)
    with pytest.raises(TypeError, match="a job is a dict"):
        list(mbao.render_many([mbao.cornell_box()]))


def _sleep_then_return(scene, seconds, value):
    import time

    time.sleep(seconds)
    return value


def test_results_come_in_submission_order_whatever_finishes_first(client):
    """What keeps a cluster's sums in pass order: the first task is the slowest."""
    from mbao._cluster import results_in_order, scene_for_workers

    scene = scene_for_workers(client, mbao.cornell_box())
    tasks = [(_sleep_then_return, scene, 1.0 if k == 0 else 0.2, k) for k in range(3)]  # two workers
    assert [f.result() for f in results_in_order(client, iter(tasks))] == [0, 1, 2]
    # Unordered, the other worker's first short task comes before the long one.
    assert [f.result() for f in results_in_order(client, iter(tasks), ordered=False)][0] != 0


def test_a_progress_bar_counts_the_jobs(capsys):
    jobs = jobs_on(mbao.cornell_box(), 3)
    list(mbao.render_many(jobs, progress=True))
    assert "3/3" in capsys.readouterr().err
