"""What work on a Dask cluster shares (render_many, reference, convergence):
scenes sent to the workers once and kept there, and tasks submitted a window
ahead of the results taken."""

import collections
import hashlib
import os
import pickle

from distributed import as_completed, wait

from .scene import as_scene


def scene_for_workers(client, scene, *, broadcast=False):
    """What a task takes for `scene`: a path, which workers load themselves, or
    the Scene (an mbao.Mesh too) sent to the cluster once, with a hash of its
    content by which workers keep it, and its tree, from task to task and
    call to call. broadcast: to every worker now, so that a worker lost midway
    leaves copies."""
    if isinstance(scene, (str, os.PathLike)):
        return os.path.abspath(os.fspath(scene))
    scene = as_scene(scene)
    content = hashlib.blake2b(pickle.dumps(scene, protocol=pickle.HIGHEST_PROTOCOL), digest_size=16).hexdigest()
    return content, client.scatter(scene, broadcast=broadcast, hash=False)


def default_in_flight(client):
    """Tasks submitted ahead of the results taken: two per worker thread."""
    return 2 * max(1, sum(client.nthreads().values()))


def results_in_order(client, tasks, *, ordered=True, in_flight=None):
    """Submits (function, *arguments) tuples from `tasks`, at most `in_flight`
    unfinished at once, and yields their futures, finished, in the order
    submitted (ordered=False: as they finish). Closing the generator cancels
    those not yielded."""
    in_flight = in_flight or default_in_flight(client)
    pending = collections.deque()
    completed = None if ordered else as_completed()
    try:
        for function, *arguments in tasks:
            future = client.submit(on_worker, function, *arguments, pure=False)
            pending.append(future)
            if completed is not None:
                completed.add(future)
            if len(pending) >= in_flight:
                yield _next_finished(pending, completed)
        while pending:
            yield _next_finished(pending, completed)
    finally:
        client.cancel(list(pending))


def results_of(client, tasks):
    """The results of results_in_order's futures, in order: a task's error is
    raised here; leaving early cancels the tasks not yet taken."""
    futures = results_in_order(client, tasks)
    try:
        for future in futures:
            yield future.result()
    finally:
        futures.close()


def _next_finished(pending, completed):
    if completed is None:
        future = pending.popleft()
        wait(future)
        return future
    future = next(completed)
    pending.remove(future)
    return future


def on_worker(function, scene, *arguments):
    """function(the scene, *arguments) on a worker, with the worker's own copy
    of the scene where it keeps one (see scene_for_workers)."""
    if isinstance(scene, str):
        try:
            state = os.stat(scene)
        except OSError:
            return function(as_scene(scene), *arguments)  # the loader's error, as on the client
        scene = _kept(("file", scene, state.st_mtime_ns, state.st_size), lambda: as_scene(scene))
    else:
        content, sent = scene
        scene = _kept(("content", content), lambda: sent)
    return function(scene, *arguments)


# On a worker: the scenes it keeps, with their trees and device copies, by
# path and file state or by content, the most recently used last. A few, so
# that jobs that alternate between scenes do not load or build them again, and
# not all: scenes can be large.
_kept_on_worker = collections.OrderedDict()
_SCENES_KEPT_ON_WORKER = 4


def _kept(key, make):
    if key not in _kept_on_worker:
        _kept_on_worker[key] = make()
        if len(_kept_on_worker) > _SCENES_KEPT_ON_WORKER:
            _kept_on_worker.popitem(last=False)
    _kept_on_worker.move_to_end(key)
    return _kept_on_worker[key]
