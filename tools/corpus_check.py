"""Loads and renders every model file under a folder, beside what Assimp's own
command-line tool (`assimp info`, Debian's assimp-utils) and the Khronos glTF
validator (`make gltf-validator`) say of it: the check of issue 59, that every
file Assimp imports with triangles and every glTF file the validator accepts
loads and renders in mbao.

    make corpus CORPUS=FOLDER        (or: .venv/bin/python tools/corpus_check.py FOLDER --report docs/corpus.md)

Each file runs in a process of its own, so that one that crashes or hangs a
reader is reported rather than ending the run. The report has the counts and
a table of the files mbao refuses although Assimp or the validator accepts
them, with mbao's message.
"""

import argparse
import json
import os
import pathlib
import re
import subprocess
import sys

# What a file is, by its extension: Assimp's formats (its importers' list), and glTF.
GLTF = {".gltf", ".glb"}
SKIPPED = {
    ".png",
    ".jpg",
    ".jpeg",
    ".bmp",
    ".tga",
    ".gif",
    ".dds",
    ".txt",
    ".md",
    ".bin",
    ".mtl",
    ".xml",
    ".glsl",
    ".json",
    ".ktx2",
    ".hdr",
    ".tif",
    ".tiff",
    ".psd",
    ".pcx",
    ".raw",
    ".exr",
    ".webp",
}
SECONDS = 120

CHILD = r"""
import json, math, sys, warnings
warnings.simplefilter("ignore")
import numpy as np
import mbao
try:
    scene = mbao.load(sys.argv[1])
    frame = mbao.render(scene, width=32, height=32, samples=1, camera="frame", progress=False)
    print(json.dumps({"triangles": scene.triangle_count, "warnings": len(scene.warnings),
                      "renders": bool(np.isfinite(frame.ao).all() and frame.mask.any())}))
except (mbao.LoadError, ValueError) as e:
    print(json.dumps({"error": str(e).splitlines()[0][:300]}))
"""


def assimp_verdict(path):
    """'triangles' where `assimp info` imports the file with triangles or polygons, 'other' where it imports
    only points or lines, None where it does not import it (or runs past SECONDS)."""
    try:
        done = subprocess.run(
            ["assimp", "info", str(path)], capture_output=True, text=True, timeout=SECONDS, errors="replace"
        )
    except subprocess.TimeoutExpired:
        return None
    types = re.search(r"^Primitive Types:\s*(.*)$", done.stdout, re.M)
    if done.returncode != 0 or types is None:
        return None
    return "triangles" if re.search(r"triangles|polygons", types.group(1)) else "other"


def validator_verdict(path):
    """Whether the Khronos validator finds no error in a glTF file; None where it stops."""
    import mbao
    from mbao.check import validation_report

    try:
        return validation_report(path)["issues"]["numErrors"] == 0
    except mbao.Error:
        return None


def mbao_verdict(path):
    try:
        done = subprocess.run(
            [sys.executable, "-c", CHILD, str(path)], capture_output=True, text=True, timeout=SECONDS, errors="replace"
        )
    except subprocess.TimeoutExpired:
        return {"error": f"ran past {SECONDS} s"}
    lines = done.stdout.strip().splitlines()
    if done.returncode != 0 or not lines:
        return {"error": f"the process ended with {done.returncode}: {done.stderr.strip().splitlines()[-1:]}"}
    return json.loads(lines[-1])


def model_files(folder):
    for path in sorted(pathlib.Path(folder).rglob("*")):
        if path.is_file() and path.suffix.lower() not in SKIPPED:
            yield path


def check(path):
    row = {"file": os.fspath(path), "mbao": mbao_verdict(path)}
    if path.suffix.lower() in GLTF:
        row["valid"] = validator_verdict(path)
    row["assimp"] = assimp_verdict(path)
    return row


def expected(row):
    """Whether mbao should load and render the file: Assimp imports it with triangles, or it is valid glTF."""
    return row["assimp"] == "triangles" or row.get("valid") is True


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("folder")
    parser.add_argument("--json", help="write every file's row here")
    parser.add_argument("--report", help="write the report here (Markdown) as well as to the standard output")
    args = parser.parse_args()
    rows = []
    for path in model_files(args.folder):
        rows.append(check(path))
        print(f"{len(rows)}: {path}", file=sys.stderr, flush=True)
    if args.json:
        pathlib.Path(args.json).write_text(json.dumps(rows, indent=1) + "\n")
    report = "\n".join(report_lines(rows, args.folder)) + "\n"
    print(report, end="")
    if args.report:
        pathlib.Path(args.report).write_text(report)
    return 0


def report_lines(rows, folder):
    should = [r for r in rows if expected(r)]
    failing = [r for r in should if "error" in r["mbao"] or not r["mbao"].get("renders")]
    lines = [
        "<!-- written by tools/corpus_check.py (make corpus); docs/limits.md explains what is left -->",
        "# Model files mbao refuses",
        "",
        f"{len(rows)} files; {len(should)} that Assimp's `assimp info` imports with triangles or the Khronos "
        f"validator accepts; {len(should) - len(failing)} of those load and render in mbao. The others:",
        "",
        "| file | Assimp | validator | mbao |",
        "|---|---|---|---|",
    ]
    for r in failing:
        message = r["mbao"].get("error", "no image").replace(os.fspath(r["file"]), "FILE").replace("|", "\\|")
        lines.append(f"| {os.path.relpath(r['file'], folder)} | {r['assimp']} | {r.get('valid', '')} | {message} |")
    return lines


if __name__ == "__main__":
    sys.exit(main())
