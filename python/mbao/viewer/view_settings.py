"""The settings a view has: render's own, from its table, and the viewer's (docs/viewer.md).

A view's settings are a flat dict. Every name of mbao.render's settings means
what it means there, except `method`, which the viewer extends; `denoise`,
`temporal` and `frames` are render_sequence's and the viewer's own.
"""

import math

from .. import _checks
from ..settings import RENDER, checked

# What the image shows (SPEC 8): render's two methods, HBAO with the GTAO fit,
# and a bake the file holds, looked up at the camera hits.
METHODS = ("raytraced", "hbao", "hbao+gtao", "baked")

# The viewer's own settings, described as the render table describes its.
VIEWER = {
    "denoise": dict(
        name="denoise",
        kind="flag",
        default=False,
        doc="Filter each frame with the edge-aware a-trous filter (SPEC 7.3).",
    ),
    "temporal": dict(
        name="temporal",
        kind="flag",
        default=True,
        doc="A still camera accumulates its frames as render_sequence does (SPEC 7.4).",
    ),
    "frames": dict(
        name="frames",
        kind="count",
        default=0,
        doc="Stop a still view's accumulation after this many frames; 0: once the history is full "
        "(mbao.Temporal's max_length).",
    ),
}


def defaults():
    """A new view's settings: render's defaults and the viewer's."""
    values = {name: spec["default"] for name, spec in RENDER.items()}
    values.update({name: spec["default"] for name, spec in VIEWER.items()})
    return values


def updated(settings, changes, methods):
    """`settings` with `changes` applied, each checked: a new dict, or a
    TypeError / ValueError naming the setting. `methods`: the methods this view
    offers (METHODS, less "baked" for a scene without a bake)."""
    if not isinstance(changes, dict):
        raise TypeError(f"settings must be an object of setting names to values, got {type(changes).__name__}")
    values = dict(settings)
    for name, value in changes.items():
        values[name] = checked_setting(name, value, methods)
    return values


def checked_setting(name, value, methods):
    if name == "method":
        return _checks.choice("method", value, methods)
    if name in RENDER:
        return checked(RENDER[name], value)
    if name in ("denoise", "temporal"):
        return _checks.boolean(name, value)
    if name == "frames":
        return _checks.integer("frames", value, 0, 2**31 - 1, "[0, 2^31)")
    raise ValueError(
        f"unknown setting {name!r}; a view's settings are {', '.join(sorted(list(RENDER) + list(VIEWER)))}"
    )


def described(methods):
    """Every setting's spec, as the page builds its controls from them (JSON: an infinite bound as "inf")."""
    specs = [dict(spec, choices=list(methods)) if name == "method" else spec for name, spec in RENDER.items()]
    return [{key: _finite_or_text(value) for key, value in spec.items()} for spec in specs + list(VIEWER.values())]


def _finite_or_text(value):
    return str(value) if isinstance(value, float) and not math.isfinite(value) else value
