"""Batches of renders, here or on a Dask cluster."""

import os
from typing import Any, Iterable, Iterator, Optional, Union

from . import _checks
from ._progress import checked_progress, progress_count, progress_reporter
from ._types import Job, Progress
from .render import Result, render
from .scene import as_scene

_ERRORS = ("raise", "return")


def render_many(
    jobs: Iterable[Job],
    *,
    client: Any = None,
    ordered: bool = True,
    errors: str = "raise",
    in_flight: Optional[int] = None,
    progress: Progress = None,
) -> Iterator[Union[Result, Exception]]:
    """Renders a batch, yielding each job's mbao.Result.

    jobs: an iterable (a generator too) of dicts of mbao.render's arguments;
        each one's "scene" is an mbao.Scene, an mbao.Mesh or a scene file's path.
    client: None renders here, one job after the other. A
        dask.distributed.Client renders on its workers, an OpenCL device each
        (the one MBAO_DEVICE or the default names in the worker's process). A
        path is loaded by each worker that needs it, once; a Scene or Mesh is
        pickled (its arrays, masks and UV sets) and sent once to each worker
        that needs it, which keeps it, with its kd-tree and device copy, by
        its content: from job to job and batch to batch.
    ordered: yield in job order; False: as the jobs finish (with a client).
    errors: "raise" re-raises a job's error (the same mbao.Error subclass, with
        its message) when its turn comes; "return" yields the exception in its
        place and goes on.
    in_flight: with a client, the most jobs submitted and not yet yielded
        (default: twice the cluster's threads), so that the batch's results
        never all sit in memory.
    progress: as for render, over the jobs, here on the client: None, a bar on
        a terminal for a batch longer than a few seconds; False, none; True, a
        bar; or a callable progress(jobs_done, jobs_total), the total None
        where jobs has no length. A job's own render shows no bar unless
        its "progress" asks for one.

    Each job renders what mbao.render(**job) renders, bit for bit.
    """
    _checks.choice("errors", errors, _ERRORS)
    ordered = _checks.boolean("ordered", ordered)
    if in_flight is not None:
        in_flight = _checks.integer("in_flight", in_flight, 1, 2**31 - 1, "[1, 2^31 - 1], or None")
    checked_progress(progress)
    rendered = (
        _rendered_here(jobs, errors) if client is None else _rendered_on(client, jobs, ordered, errors, in_flight)
    )
    return _counted(rendered, progress, len(jobs) if hasattr(jobs, "__len__") else None)


def _counted(rendered, progress, total):
    """The results as they come, with a bar over them where asked."""
    with progress_reporter(progress, "render_many", "job", total) as report:
        count = progress_count(report, total)
        try:
            for outcome in rendered:
                yield outcome
                count.advance()
        finally:
            rendered.close()


def _checked_job(job):
    if not isinstance(job, dict) or "scene" not in job:
        raise TypeError(f'a job is a dict of mbao.render\'s arguments with a "scene", got {job!r:.200}')
    return dict(job, progress=job.get("progress", False))


def _rendered_here(jobs, errors):
    loaded = {}  # path: its scene, loaded once for the batch
    for job in jobs:
        job = _checked_job(job)
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
    from ._cluster import results_in_order, scene_for_workers  # only batches on a cluster need Dask

    sent = {}  # id of a Scene or Mesh: (the object, kept alive; what the tasks take for it)

    def tasks():
        for job in map(_checked_job, jobs):
            scene = job["scene"]
            if id(scene) not in sent:
                sent[id(scene)] = (scene, scene_for_workers(client, scene))
            yield _render_job, sent[id(scene)][1], {name: value for name, value in job.items() if name != "scene"}

    futures = results_in_order(client, tasks(), ordered=ordered, in_flight=in_flight)
    try:
        for future in futures:
            yield _outcome(future, errors)
    finally:
        futures.close()


def _outcome(future, errors):
    try:
        return future.result()
    except Exception as error:
        if errors == "raise":
            raise
        return error
    finally:
        future.release()


def _render_job(scene, arguments):
    return render(scene, **arguments)
