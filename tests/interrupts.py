"""A real Ctrl-C in the middle of a render or a bake."""

import os
import signal
import threading
import time

import pytest


def interrupt_after_the_first_tile(run):
    """Calls run(progress) while another thread sends this process a SIGINT as
    soon as the first tile is done, expects it to raise KeyboardInterrupt, and
    returns {tiles_done: tiles_total} of the tiles that finished. Progress is a
    dict's C-implemented __setitem__, which runs no Python bytecode and so no
    signal handler: only the core's own check between tiles can stop early."""
    tiles_done = {}

    def interrupt_once():
        while not tiles_done:
            time.sleep(0.001)
        os.kill(os.getpid(), signal.SIGINT)

    previous = signal.signal(signal.SIGINT, signal.default_int_handler)
    try:
        sender = threading.Thread(target=interrupt_once)
        sender.start()
        with pytest.raises(KeyboardInterrupt):
            run(tiles_done.__setitem__)
        sender.join()
    finally:
        signal.signal(signal.SIGINT, previous)
    return tiles_done
