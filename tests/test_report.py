"""The performance tables in README.md and docs/performance.md are bench/report.py's output.

Every figure in them comes from a committed benchmark run (bench/results/*.json);
nobody types one in. A run committed without its tables regenerated, or a table
edited by hand, fails here.
"""

import copy
import importlib.util
import subprocess
import sys

from conftest import REPO

SCRIPT = REPO / "bench" / "report.py"


def load_report():
    spec = importlib.util.spec_from_file_location("report", SCRIPT)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_the_committed_tables_are_the_scripts_output():
    check = subprocess.run([sys.executable, str(SCRIPT), "--check"], capture_output=True, text=True)
    assert check.returncode == 0, check.stderr


def test_every_result_file_has_a_table_and_every_table_a_result_file():
    report = load_report()
    runs = report.load_results()
    named = set()
    for path in report.DOCUMENTS:
        for match in report.BLOCK.finditer(path.read_text()):
            kind, file = match.group(2), match.group(3)
            report.render(kind, file, runs)  # exits naming the table or file where either is unknown
            named.add(file)
    assert set(runs) <= named, f"results without a table: {set(runs) - named}"


def test_a_changed_figure_makes_the_tables_stale():
    report = load_report()
    runs = report.load_results()
    text = report.DOCUMENTS[0].read_text()
    assert report.regenerate(text, runs)[1] == []
    slower = copy.deepcopy(runs)
    name = next(iter(slower))
    slower[name]["results"][0]["frames"][0]["frame_ms"] *= 2
    assert ("summary", "all") in report.regenerate(text, slower)[1]
