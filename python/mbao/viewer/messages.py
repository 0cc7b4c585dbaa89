"""The page's messages to the server, checked (docs/viewer.md): each is a JSON
object with a "type"; anything else is refused with a message that names it."""

import json
import math

from .. import _checks, _core
from .view_settings import updated

# The largest message the server reads: a camera and every setting fit in far less.
MAX_MESSAGE_BYTES = 64 * 1024

_FIELDS = {
    "set": {"camera", "settings", "interactive"},
    "pick": {"x", "y"},
    "save": {"what"},
}
SAVE_KINDS = ("png", "exr", "camera")


def parse(text, settings, methods, suggested_radius=None):
    """The message in `text`, checked: {"type": ..., ...} with a camera as an
    mbao.Camera carrying `suggested_radius` (the home camera's, SPEC 1) and
    settings as the view's whole settings after the change. Raises ValueError
    or TypeError naming what is wrong."""
    if not isinstance(text, str):
        raise TypeError("messages are JSON text, got binary data")
    try:
        message = json.loads(text)
    except json.JSONDecodeError as error:
        raise ValueError(f"a message is not JSON: {error}") from None
    if not isinstance(message, dict):
        raise TypeError(f"a message must be a JSON object, got {type(message).__name__}")
    kind = message.get("type")
    if kind not in _FIELDS:
        raise ValueError(f"message type must be one of {', '.join(map(repr, _FIELDS))}; got {kind!r}")
    unknown = set(message) - _FIELDS[kind] - {"type"}
    if unknown:
        raise ValueError(
            f"a {kind!r} message has no field {', '.join(map(repr, sorted(unknown)))}; "
            f"its fields are {', '.join(sorted(_FIELDS[kind]))}"
        )
    if kind == "set":
        return _set(message, settings, methods, suggested_radius)
    return {"pick": _pick, "save": _save}[kind](message)


def _set(message, settings, methods, suggested_radius):
    parsed = {"type": "set"}
    if "camera" in message:
        parsed["camera"] = camera_from_json(message["camera"], suggested_radius)
    if "settings" in message:
        parsed["settings"] = updated(settings, settings_from_json(message["settings"]), methods)
    if "interactive" in message:
        parsed["interactive"] = _checks.boolean("interactive", message["interactive"])
    return parsed


def _pick(message):
    point = {}
    for axis in ("x", "y"):
        value = _checks.real(axis, message.get(axis))
        if not 0.0 <= value <= 1.0:
            raise ValueError(f"pick {axis} must be in [0, 1] (a fraction of the image), got {value}")
        point[axis] = value
    return dict(type="pick", **point)


def _save(message):
    return dict(type="save", what=_checks.choice("what", message.get("what"), SAVE_KINDS))


def camera_from_json(value, suggested_radius=None):
    """An mbao.Camera from {eye, target, up, vfov_deg} (SPEC 3.1.1), each
    checked, with `suggested_radius` as its max_distance."""
    if not isinstance(value, dict):
        raise TypeError(f"camera must be an object {{eye, target, up, vfov_deg}}, got {type(value).__name__}")
    unknown = set(value) - {"eye", "target", "up", "vfov_deg"}
    if unknown:
        raise ValueError(
            f"camera has no field {', '.join(map(repr, sorted(unknown)))}; " "its fields are eye, target, up, vfov_deg"
        )
    missing = {"eye", "target", "up", "vfov_deg"} - set(value)
    if missing:
        raise ValueError(f"camera lacks {', '.join(sorted(missing))}")
    vectors = [_vector(f"camera {name}", value[name]) for name in ("eye", "target", "up")]
    vfov = _checks.real("camera vfov_deg", value["vfov_deg"])
    return _core.Camera(*vectors, vfov_deg=vfov, max_distance=suggested_radius)


def _vector(name, value):
    if not isinstance(value, list) or len(value) != 3:
        raise TypeError(f"{name} must be a list of 3 numbers, got {value!r}")
    numbers = [_checks.real(name, v) for v in value]
    if not all(math.isfinite(v) for v in numbers):
        raise ValueError(f"{name} must be finite, got {value!r}")
    return tuple(numbers)


def camera_json(camera, max_distance=None):
    """The camera as camera.json holds it (SPEC 3.1.1), with `max_distance`
    as its suggested radius where that is given and finite."""
    data = dict(eye=list(camera.eye), target=list(camera.target), up=list(camera.up), vfov_deg=camera.vfov_deg)
    if max_distance is not None and math.isfinite(max_distance):
        data["max_distance"] = max_distance
    return data


# JSON has no infinity: an unlimited radius travels as this string.
UNLIMITED = "inf"


def settings_json(settings):
    """The settings as JSON carries them: max_distance inf as "inf"."""
    radius = settings.get("max_distance")
    return dict(settings, max_distance=UNLIMITED) if radius is not None and math.isinf(radius) else dict(settings)


def settings_from_json(settings):
    if isinstance(settings, dict) and settings.get("max_distance") == UNLIMITED:
        return dict(settings, max_distance=math.inf)
    return settings
