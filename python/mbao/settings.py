"""The render settings, from the C++ core's one table of them (cpp/render/setting_specs.h).

mbao.render takes its signature and docstring from RENDER, mbao.Engine its
fields from ENGINE, and `python -m mbao render` its options from both; the
command line's --hbao-*, --denoise-* and --temporal-* options come from
HBAO_SETTINGS, DENOISE_SETTINGS and TEMPORAL_SETTINGS, the tables of
mbao.HBAO, mbao.Denoise and mbao.Temporal. mbao.bake and `python -m mbao bake`
take the bake's own settings from BAKE_SETTINGS. Each
spec is a dict: name, group, kind, doc, range, lo, hi, none_means, choices, default.
"""

import dataclasses
import textwrap

from . import _checks, _core

_SPECS = _core.setting_specs()
RENDER = {spec["name"]: spec for spec in _SPECS if spec["group"] == "render"}
ENGINE = {spec["name"]: spec for spec in _SPECS if spec["group"] == "engine"}
HBAO_SETTINGS = {spec["name"]: spec for spec in _core.setting_specs("hbao")}
DENOISE_SETTINGS = {spec["name"]: spec for spec in _core.setting_specs("denoise")}
TEMPORAL_SETTINGS = {spec["name"]: spec for spec in _core.setting_specs("temporal")}
BAKE_SETTINGS = {spec["name"]: spec for spec in _core.setting_specs("bake")}


def checked(spec, value):
    """`value` as the core takes it, or a TypeError / ValueError naming the setting.

    The core checks every range (RenderSettings::validate); here only what must
    hold before a value can reach it: its type, and the bounds of 64 bits."""
    name, kind = spec["name"], spec["kind"]
    if kind == "integer":
        return _checks.integer(name, value)
    if kind == "unsigned":
        return _checks.integer(name, value, spec["lo"], spec["hi"], spec["range"])
    if kind == "auto count":
        if value is None:
            return None
        value = _checks.integer(name, value)
        if value < 1:
            raise ValueError(f"{name} must be >= 1, or None for automatic; got {value}")
        return value
    if kind == "real":
        return None if value is None and spec["none_means"] else _checks.real(name, value)
    if kind == "choice":
        return _checks.choice(name, value, spec["choices"])
    return _checks.boolean(name, value)


def describe(spec):
    """One entry of a docstring: the setting, what it means, its default and range."""
    default = spec["default"]
    if default is None:
        default = f"None: {spec['none_means']}" if spec["none_means"] else "None (automatic)"
    else:
        default = repr(default)
    allowed = "" if spec["kind"] in ("choice", "flag", "auto count") else f", allowed {spec['range']}"
    return textwrap.fill(
        f"{spec['name']}: {spec['doc']} Default {default}{allowed}.", width=100, subsequent_indent="    "
    )


def _check_engine(engine):
    for spec in ENGINE.values():
        object.__setattr__(engine, spec["name"], checked(spec, getattr(engine, spec["name"])))


def _engine_class():
    fields = [(name, object, dataclasses.field(default=spec["default"])) for name, spec in ENGINE.items()]
    doc = (
        "How mbao does the work of a render; no engine setting changes the image.\n\n"
        '    mbao.render(scene, engine=mbao.Engine(traversal="stack", traversal_stats=True))\n\n'
        + "\n".join(describe(spec) for spec in ENGINE.values())
        + '\n\nstats["plan"] of a render says what "auto" chose and why (docs/kernel-variants.md).'
    )
    engine = dataclasses.make_dataclass(
        "Engine", fields, frozen=True, namespace={"__doc__": doc, "__post_init__": _check_engine}
    )
    engine.__module__ = "mbao"
    return engine


Engine = _engine_class()


def engine_values(engine):
    """{name: value} of an Engine, for the core."""
    return {name: getattr(engine, name) for name in ENGINE}


def markdown_table(table):
    """A settings table of the core (_core.setting_specs(table)) as docs/spec.md shows it."""
    rows = ["| setting | meaning | default | allowed |", "|---|---|---|---|"]
    rows += [
        f"| `{spec['name']}` | {spec['doc']} | {spec['default']!r} | {spec['range']} |"
        for spec in _core.setting_specs(table)
    ]
    return "\n".join(rows)
