"""The progress bar of long work (reference, convergence): tqdm, imported only when shown."""


class progress_bar:
    """A context manager giving a tqdm bar, or None when `enabled` is False."""

    def __init__(self, enabled, total, description, unit):
        self._bar = None
        if enabled:
            from tqdm.auto import tqdm

            self._bar = tqdm(total=total, desc=description, unit=unit)

    def __enter__(self):
        return self._bar

    def __exit__(self, *exc):
        if self._bar is not None:
            self._bar.close()
