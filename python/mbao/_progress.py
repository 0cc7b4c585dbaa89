"""progress= as every long call takes it (render, render_sequence, bake,
render_many, reference, convergence), with one meaning everywhere:

- None (the default): a bar where someone is watching (a terminal, or a
  Jupyter kernel's output), once the work has run SHOWN_AFTER_S seconds;
- False: no bar;
- True: a bar, from the start;
- a callable progress(done, total), called as the work advances; total is
  None while it is unknown.

The bar is tqdm's, imported only when one is made."""

import sys

# Work shorter than this shows no bar by default: a bar that flashes past says nothing.
SHOWN_AFTER_S = 2.0

MEANING = "None (a bar on a terminal for long work), False, True or a callable progress(done, total)"


def checked_progress(progress):
    """progress, refused with a TypeError unless it is one of its meanings."""
    if not (progress is None or isinstance(progress, bool) or callable(progress)):
        raise TypeError(f"progress must be {MEANING}, got {type(progress).__name__}")
    return progress


class progress_reporter:
    """A context manager giving report(done, total, note=None), or None when
    nothing is to be reported (so that a render need not stop between tiles)."""

    def __init__(self, progress, description, unit, total=None):
        checked_progress(progress)
        self._callback = progress if callable(progress) else None
        shown = progress is True or (progress is None and _watched())
        self._bar = (
            _tqdm(total=total, desc=description, unit=unit, delay=0 if progress is True else SHOWN_AFTER_S)
            if shown
            else None
        )

    def __enter__(self):
        if self._callback is not None:
            return lambda done, total, note=None: self._callback(done, total)
        return None if self._bar is None else self._advance

    def _advance(self, done, total, note=None):
        self._bar.total = total
        if note is not None:
            self._bar.set_postfix_str(note, refresh=False)
        self._bar.update(done - self._bar.n)

    def __exit__(self, *exc):
        if self._bar is not None:
            self._bar.close()


class progress_count:
    """Units of work done, reported as they grow (report: a progress_reporter's, or None)."""

    def __init__(self, report, total=None):
        self._report, self.total, self.done = report, total, 0

    def advance(self, count=1):
        self.done += count
        if self._report is not None:
            self._report(self.done, self.total)


def _watched():
    """Whether a bar would be seen: stderr is a terminal, or a Jupyter kernel's output."""
    stderr = sys.stderr
    if stderr is None:
        return False
    if type(stderr).__module__.startswith("ipykernel"):
        return True
    try:
        return stderr.isatty()
    except (AttributeError, ValueError):  # a replaced or closed stream
        return False


def _tqdm(**arguments):
    """tqdm.auto's bar: a widget in Jupyter, else text. Debian's ipywidgets 6
    (which its Jupyter brings) lacks what tqdm's widget sets (a progress bar's
    style), so there the bar is text. It is text from the start: the widget
    tqdm would half make opens a comm in the old protocol, which stops a
    headless run (nbclient 0.7, `nbconvert --execute`) with KeyError 'state'."""
    if _ipywidgets_major() < 7:
        from tqdm.std import tqdm
    else:
        from tqdm.auto import tqdm

    try:
        return tqdm(**arguments)
    except AttributeError:
        from tqdm.std import tqdm as text_tqdm

        return text_tqdm(**arguments)


def _ipywidgets_major():
    """The installed ipywidgets' major version, 0 without it (read without importing it)."""
    from importlib.metadata import PackageNotFoundError, version

    try:
        return int(version("ipywidgets").split(".")[0])
    except (PackageNotFoundError, ValueError):
        return 0
