"""The progress bar of long work (reference, convergence): tqdm, imported only when shown."""


class progress_bar:
    """A context manager giving a tqdm bar, or None when `enabled` is False."""

    def __init__(self, enabled, total, description, unit):
        self._bar = None
        if enabled:
            self._bar = _tqdm(total=total, desc=description, unit=unit)

    def __enter__(self):
        return self._bar

    def __exit__(self, *exc):
        if self._bar is not None:
            self._bar.close()


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
