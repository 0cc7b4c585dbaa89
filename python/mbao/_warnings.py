"""Warnings that point at the user's code: at the first caller outside this
package, however deep inside mbao they are raised (a bake through bake_file,
a render through the command line), so that Python's filters and messages
name the user's line."""

import os
import sys
import warnings

_PACKAGE = os.path.dirname(os.path.abspath(__file__)) + os.sep


def warn(message, category=UserWarning):
    """warnings.warn(message, category), attributed to the first frame outside mbao."""
    level, frame = 2, sys._getframe(1)
    while frame is not None and frame.f_code.co_filename.startswith(_PACKAGE):
        frame = frame.f_back
        level += 1
    warnings.warn(message, category, stacklevel=level)
