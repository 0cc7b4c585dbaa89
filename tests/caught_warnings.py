"""The warnings a block of code gives, as a test counts them."""

import contextlib
import warnings


@contextlib.contextmanager
def caught_warnings():
    """Records every warning the block gives, each time it is given. ResourceWarnings
    are left out: the garbage collector raises them for whatever it frees during the
    block, such as the sockets of a Dask cluster that another test on this pytest
    worker left running."""
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        warnings.simplefilter("ignore", ResourceWarning)
        yield caught
