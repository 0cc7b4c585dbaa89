"""Batches of renders, here or on a Dask cluster."""

import collections
import os

from . import _checks
from .render import render
from .scene import as_scene

_ERRORS = ("raise", "return")


def render_many(jobs, *, client=None, ordered=True, errors="raise", in_flight=None):
    """Renders a batch, yielding each job's mbao.Result.

    jobs: an iterable (a generator too) of dicts of mbao.render's arguments;
        each one's "scene" is an mbao.Scene, an mbao.Mesh or a scene file's path.
    client: None renders here, one job after the other. A
        dask.distributed.Client renders on its workers, an OpenCL device each
        (the one MBAO_DEVICE or the default names in the worker's process). A
        path is loaded by each worker that needs it, once; a Scene or Mesh is
        pickled (its arrays, masks and UV sets) and sent once to each worker
        that needs it, where it keeps its kd-tree and device copy from job to
        job.
    ordered: yield in job order; False: as the jobs finish (with a client).
    errors: "raise" re-raises a job's error (the same mbao.Error subclass, with
        its message) when its turn comes; "return" yields the exception in its
        place and goes on.
    in_flight: with a client, the most jobs submitted and not yet yielded
        (default: twice the cluster's threads), so that the batch's results
        never all sit in memory.

    Each job renders what mbao.render(**job) renders, bit for bit.
    """
    if errors not in _ERRORS:
        raise ValueError(f"errors must be \"raise\" or \"return\", got {errors!r}")
    ordered = _checks.boolean("ordered", ordered)
    if in_flight is not None:
        in_flight = _checks.integer("in_flight", in_flight, 1, 2**31 - 1, "[1, 2^31 - 1], or None")
    if client is None:
        return _rendered_here(jobs, errors)
    return _rendered_on(client, jobs, ordered, errors, in_flight)


def _checked_job(job):
    if not isinstance(job, dict) or "scene" not in job:
        raise TypeError(f"a job is a dict of mbao.render's arguments with a \"scene\", got {job!r:.200}")
    return job


def _rendered_here(jobs, errors):
    loaded = {}  # path: its scene, loaded once for the batch
    for job in jobs:
        job = dict(_checked_job(job))
        try:
            if isinstance(job["scene"], (str, os.PathLike)):
                path = os.fspath(job["scene"])
                if path not in loaded:
                    loaded[path] = as_scene(path)
                job["scene"] = loaded[path]
            yield render(**job)
        except Exception as error:
            if errors == "raise":
                raise
            yield error


def _rendered_on(client, jobs, ordered, errors, in_flight):
    from distributed import as_completed  # only batches on a cluster need Dask

    if in_flight is None:
        in_flight = 2 * max(1, sum(client.nthreads().values()))
    scenes = {}  # id of a Scene or Mesh: (the object, kept alive; its future on the cluster)
    pending = collections.deque()
    completed = None if ordered else as_completed()
    for job in map(_checked_job, jobs):
        scene = job["scene"]
        if not isinstance(scene, (str, os.PathLike)):
            if id(scene) not in scenes:
                scenes[id(scene)] = (scene, client.scatter(as_scene(scene), hash=False))
            scene = scenes[id(scene)][1]
        else:
            scene = os.path.abspath(os.fspath(scene))
        arguments = {name: value for name, value in job.items() if name != "scene"}
        future = client.submit(_render_on_worker, scene, arguments, pure=False)
        pending.append(future)
        if completed is not None:
            completed.add(future)
        if len(pending) >= in_flight:
            yield _outcome(_next_done(pending, completed), errors)
    while pending:
        yield _outcome(_next_done(pending, completed), errors)


def _next_done(pending, completed):
    """The next future to yield: the oldest, or with `completed` the first to finish."""
    if completed is None:
        return pending.popleft()
    future = next(completed)
    pending.remove(future)
    return future


def _outcome(future, errors):
    try:
        return future.result()
    except Exception as error:
        if errors == "raise":
            raise
        return error
    finally:
        future.release()


# On a worker: the scenes it loaded from paths, by path and file state, the
# most recently used last. A few, so that jobs that alternate between files do
# not load them again, and not all: scenes can be large.
_loaded_on_worker = collections.OrderedDict()
_SCENES_KEPT_ON_WORKER = 4


def _render_on_worker(scene, arguments):
    if isinstance(scene, str):
        try:
            state = os.stat(scene)
        except OSError:
            return render(scene, **arguments)  # the loader's error, as here
        key = (scene, state.st_mtime_ns, state.st_size)
        if key not in _loaded_on_worker:
            _loaded_on_worker[key] = as_scene(scene)
            if len(_loaded_on_worker) > _SCENES_KEPT_ON_WORKER:
                _loaded_on_worker.popitem(last=False)
        _loaded_on_worker.move_to_end(key)
        scene = _loaded_on_worker[key]
    return render(scene, **arguments)
