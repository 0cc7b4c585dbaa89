"""Puts the add-on where Blender finds it (`python -m mbao blender --install`),
or into a zip that Preferences > Add-ons > Install takes (`--zip FILE`). Either
way the add-on learns where this mbao is and which Python runs it."""

import json
import shutil
import subprocess
import sys
import zipfile
from pathlib import Path

ADDON = "mbao_bake"  # not "mbao": Blender puts add-ons on sys.path, where it would hide the package
SOURCE = Path(__file__).with_name(ADDON)
SUPPORTED = "Blender 3.4 and later 3.x (Debian 12's is 3.4.1)"


def location():
    """The add-on's location.json: the folder holding the mbao package, and the Python that imports it."""
    return {"package": str(Path(__file__).resolve().parents[2]), "python": sys.executable}


def _addon_files():
    return sorted(p for p in SOURCE.iterdir() if p.suffix == ".py")


def write_zip(path):
    """A zip of the add-on, its location.json included."""
    with zipfile.ZipFile(path, "w", zipfile.ZIP_DEFLATED) as archive:
        for file in _addon_files():
            archive.write(file, f"{ADDON}/{file.name}")
        archive.writestr(f"{ADDON}/location.json", json.dumps(location(), indent=2))
    return Path(path)


def install(blender="blender"):
    """Copies the add-on into the user's add-on folder of `blender` (its
    executable) and enables it in the user's preferences; returns the folder."""
    said = _ask_blender(
        blender, "import bpy; print('addons:', bpy.utils.user_resource('SCRIPTS', path='addons', " "create=True))"
    )
    folder = Path(next(line for line in said.splitlines() if line.startswith("addons: "))[len("addons: ") :]) / ADDON
    if folder.exists():
        shutil.rmtree(folder)
    folder.mkdir(parents=True)
    for file in _addon_files():
        shutil.copy2(file, folder / file.name)
    (folder / "location.json").write_text(json.dumps(location(), indent=2))
    _ask_blender(
        blender, f"import bpy; bpy.ops.preferences.addon_enable(module={ADDON!r}); " f"bpy.ops.wm.save_userpref()"
    )
    return folder


def _ask_blender(blender, expression):
    """Runs a Python expression in `blender`, in the background; returns what it printed."""
    if shutil.which(blender) is None:
        raise OSError(
            f"no Blender at {blender!r}: install it (Debian: apt-get install blender), or name its "
            f"executable with --blender"
        )
    run = subprocess.run(
        [blender, "-b", "--python-exit-code", "1", "--python-expr", expression],
        capture_output=True,
        text=True,
        timeout=120,
    )
    if run.returncode != 0:
        raise OSError(f"{blender} failed ({run.returncode}): {run.stderr.strip() or run.stdout.strip()}")
    return run.stdout
