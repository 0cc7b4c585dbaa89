"""What batches and references share on a Dask cluster: scenes sent to the
workers once, and work submitted a window ahead of the results taken."""

import collections
import os

from distributed import as_completed, wait

from .scene import as_scene


def scene_for_workers(client, scene, *, broadcast=False):
    """What a task takes for `scene`: a path, which workers load themselves, or
    the future of the Scene (an mbao.Mesh too) sent to the cluster once.
    broadcast: to every worker now, so that a worker lost midway leaves copies."""
    if isinstance(scene, (str, os.PathLike)):
        return os.path.abspath(os.fspath(scene))
    return client.scatter(as_scene(scene), broadcast=broadcast, hash=False)


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


def _next_finished(pending, completed):
    if completed is None:
        future = pending.popleft()
        wait(future)
        return future
    future = next(completed)
    pending.remove(future)
    return future


def on_worker(function, scene, *arguments):
    """function(the scene, *arguments) on a worker, `scene` loaded there if it is a path."""
    return function(_loaded(scene) if isinstance(scene, str) else scene, *arguments)


# On a worker: the scenes it loaded from paths, by path and file state, the
# most recently used last. A few, so that jobs that alternate between files do
# not load them again, and not all: scenes can be large.
_loaded_on_worker = collections.OrderedDict()
_SCENES_KEPT_ON_WORKER = 4


def _loaded(path):
    try:
        state = os.stat(path)
    except OSError:
        return as_scene(path)  # the loader's error, as on the client
    key = (path, state.st_mtime_ns, state.st_size)
    if key not in _loaded_on_worker:
        _loaded_on_worker[key] = as_scene(path)
        if len(_loaded_on_worker) > _SCENES_KEPT_ON_WORKER:
            _loaded_on_worker.popitem(last=False)
    _loaded_on_worker.move_to_end(key)
    return _loaded_on_worker[key]
