"""The one bake the Blender add-on asks of mbao: some triangles of a scene given
as arrays, baked by mbao.bake, its result as arrays (SPEC 9).

The add-on calls bake() in Blender's own process where Blender's Python imports
mbao. Where it cannot, it runs this module in mbao's Python as a child process:

    python -m mbao.blender.request REQUEST.npz RESULT.npz

which prints `progress DONE TOTAL` and `warning MESSAGE` lines as it goes, and
on failure mbao's message as the last line of its standard error, with exit
status 1.
"""

import json
import sys
import traceback
import warnings

import numpy as np


def bake(arrays, settings, progress=None):
    """mbao.bake of the triangles arrays["triangles"] of the mesh the arrays
    describe (vertices, indices, optional normals and texcoords), with
    `settings` its keyword arguments (target "vertices" or "texture"; a texture
    is baked into the mesh's one UV set). Returns {"values", "standard_error"}:
    per vertex (N,), or per texel (H, W), row 0 at v = 0."""
    from .. import Mesh, bake as mbao_bake

    mesh = Mesh(arrays["vertices"], arrays["indices"], arrays.get("normals"), arrays.get("texcoords"))
    into_texture = settings["target"] == "texture"
    uv_set = {"texcoord": 0} if into_texture else {}
    result = mbao_bake(mesh, triangles=arrays["triangles"], progress=progress or False, **uv_set, **settings)
    if not into_texture:
        return {"values": result.values, "standard_error": result.standard_error}
    texture = result.textures[0]
    return {"values": texture.image, "standard_error": texture.standard_error}


def message_of(error):
    """An error as the one line Blender shows: mbao's message, else the exception's type too."""
    text = " ".join(str(error).split())
    return text if _is_users(error) else f"{type(error).__name__}: {text}"


def _is_users(error):
    """Whether an error is mbao's refusal of what it was given (its own errors,
    mbao.Error and those of its kind, or bad values), not a fault in mbao."""
    return isinstance(error, (ValueError, TypeError, OSError)) or type(error).__module__.startswith("mbao")


def write_request(path, arrays, settings):
    """The request a child process reads: the arrays, and the settings as JSON."""
    np.savez(path, settings=np.array(json.dumps(settings)), **{k: v for k, v in arrays.items() if v is not None})


def _read_request(path):
    with np.load(path) as request:
        arrays = {name: request[name] for name in request.files if name != "settings"}
        return arrays, json.loads(str(request["settings"]))


def main(argv):
    if len(argv) != 2:
        print("usage: python -m mbao.blender.request REQUEST.npz RESULT.npz", file=sys.stderr)
        return 2

    def progress(done, total):
        print(f"progress {done} {total}", flush=True)

    def show_warning(message, category, filename, lineno, file=None, line=None):
        print(f"warning {' '.join(str(message).split())}", flush=True)

    try:
        arrays, settings = _read_request(argv[0])
        with warnings.catch_warnings():
            warnings.showwarning = show_warning
            result = bake(arrays, settings, progress)
        np.savez(argv[1], **result)
    except Exception as error:  # any failure is the user's to read, as one line, in Blender
        if not _is_users(error):
            traceback.print_exc()
        print(message_of(error), file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    raise SystemExit(main(sys.argv[1:]))
