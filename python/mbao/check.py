"""python -m mbao check FILE: whether a glTF file is valid, by the Khronos
glTF-Validator, and what ambient occlusion it stores (mbao.load_bake)."""

import json
import os
import pathlib
import shutil
import subprocess

import numpy as np

from . import _core
from .scene import is_gltf_path, load
from .stored_bake import OPEN, VERTICES, load_bake

# The validator's folder (validate.mjs and its node_modules), where it is not the checkout's tools/gltf_validator.
VALIDATOR_VARIABLE = "MBAO_GLTF_VALIDATOR"
_CHECKOUT_VALIDATOR = pathlib.Path(__file__).resolve().parents[2] / "tools" / "gltf_validator"
_VALIDATOR_SECONDS = 300
_SEVERITIES = ("error", "warning", "info", "hint")


def validator_folder():
    """The folder of the installed glTF-Validator: $MBAO_GLTF_VALIDATOR, else
    the checkout's tools/gltf_validator. Raises mbao.Error where it is not
    installed, saying how to install it."""
    folder = pathlib.Path(os.environ.get(VALIDATOR_VARIABLE) or _CHECKOUT_VALIDATOR)
    if not (folder / "node_modules" / "gltf-validator").is_dir() or shutil.which("node") is None:
        raise _core.Error(
            f"the Khronos glTF-Validator is not installed in {folder}: `make gltf-validator` installs "
            f"it there (Node.js and npm), or set {VALIDATOR_VARIABLE} to a folder holding "
            f"validate.mjs and its node_modules"
        )
    return folder


def validation_report(path):
    """The glTF-Validator's report on the glTF file at `path`, as its JSON (a dict)."""
    run = subprocess.run(
        ["node", str(validator_folder() / "validate.mjs"), os.fspath(path)],
        capture_output=True,
        text=True,
        timeout=_VALIDATOR_SECONDS,
    )
    if run.returncode != 0:
        raise _core.Error(f"{os.fspath(path)}: the glTF-Validator stopped: {run.stderr.strip()[-2000:]}")
    return json.loads(run.stdout)


def validation_lines(report, most=20):
    """The report as lines: the counts per severity, then up to `most` of its errors and warnings."""
    issues = report["issues"]
    counts = ", ".join(_counted(issues[f"num{name.capitalize()}s"], name) for name in _SEVERITIES)
    lines = [
        f"{'valid' if issues['numErrors'] == 0 else 'INVALID'}: {counts} "
        f"({report['validatorVersion']} of the Khronos glTF-Validator)"
    ]
    shown = [m for m in issues["messages"] if m["severity"] <= 1][:most]
    lines += [f"  {_SEVERITIES[m['severity']]} {m['code']} at {m.get('pointer', '/')}: {m['message']}" for m in shown]
    return lines


def _counted(count, noun):
    return f"{count} {noun}{'' if count == 1 else 's'}"


def occlusion_lines(path):
    """What occlusion the glTF file at `path` stores, a line per kind, as mbao.load_bake reads it."""
    scene = load(path, texcoords=True)
    stored = load_bake(path, scene)
    if stored is None:
        return ["none: no _OCCLUSION attribute and no occlusion texture on its triangles"]
    lines = []
    if stored.vertex_values is not None:
        values = stored.vertex_values[np.isfinite(stored.vertex_values)]
        lines.append(
            f"_OCCLUSION on {values.size} of {len(scene.vertices)} vertices: min {values.min():.3f}, mean "
            f"{values.mean():.3f}, max {values.max():.3f}"
        )
    materials = scene.uv_sets["materials"]
    for material, texture in stored.textures.items():
        height, width = texture.image.shape
        lines.append(
            f"material {material} ({materials[material]['name']!r}): occlusion texture {width}x{height} "
            f"through TEXCOORD_{texture.texcoord}, wrap {'/'.join(texture.wrap)}, mean "
            f"{texture.image.mean():.3f}"
        )
    read = stored.triangle_source != OPEN
    lines.append(
        f"{int(read.sum())} of {len(read)} triangles read it "
        f"({int((stored.triangle_source == VERTICES).sum())} from their vertices)"
    )
    return lines


def check(path):
    """Prints what `python -m mbao check` says of `path`; returns 1 where the validator finds errors, else 0."""
    if not is_gltf_path(path):
        raise ValueError(f"{os.fspath(path)}: check reads glTF files (.gltf, .glb)")
    if not os.path.isfile(path):
        raise _core.LoadError(f"{os.fspath(path)}: no such file")
    report = validation_report(path)
    print(f"file         {os.fspath(path)}")
    for k, line in enumerate(validation_lines(report)):
        print(f"{'glTF' if k == 0 else '':<12} {line}")
    if report["issues"]["numErrors"]:
        return 1
    for k, line in enumerate(occlusion_lines(path)):
        print(f"{'occlusion' if k == 0 else '':<12} {line}")
    return 0
