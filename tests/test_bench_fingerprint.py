"""The suite's hash covers the files its conditions read: a retrained eye-camera confusion
(``measured.json``) changes it, a results folder made before is refused for new runs and
reported stale on its page, naming the file that changed."""

from __future__ import annotations

import json
import shutil
from pathlib import Path

import pytest

from pil.bench.journal import Journal
from pil.bench.leaderboard import render
from pil.bench.results import write_results
from pil.bench.run import Entrant, run_bench
from pil.bench.suite import SUITE_FILE, SuiteError, load_suite

MEASURED = "../../robin_sim/vision/data/measured.json"


def _suite_copy(folder: Path) -> tuple[Path, Path]:
    """The shipped suite and its measured confusion, copied so the copy can be changed."""
    (folder / "data").mkdir()
    measured = folder / "data" / "measured.json"
    shutil.copyfile((SUITE_FILE.parent / MEASURED).resolve(), measured)
    text = SUITE_FILE.read_text(encoding="utf-8").replace(MEASURED, "data/measured.json")
    suite = folder / "suite.yaml"
    suite.write_text(text, encoding="utf-8")
    return suite, measured


def _retrain(measured: Path) -> None:
    data = json.loads(measured.read_text(encoding="utf-8"))
    row = data["feedback_confusion"][0]
    row[0], row[2] = row[0] - 0.01, row[2] + 0.01  # one more thumb up discarded
    measured.write_text(json.dumps(data), encoding="utf-8")


def test_the_shipped_suite_hashes_the_eye_cameras_confusion():
    suite = load_suite()
    assert MEASURED in suite.inputs and len(suite.inputs[MEASURED]) == 64
    assert suite.stamp()["suite_inputs"] == dict(suite.inputs)


def test_a_changed_measured_json_changes_the_hash_and_a_folder_made_before_is_stale(tmp_path):
    path, measured = _suite_copy(tmp_path)
    before = load_suite(path)
    assert load_suite(path).sha256 == before.sha256  # the same files, the same hash
    out = tmp_path / "out"
    journal = Journal(out, before, "dev", True, commit="test")
    run_bench(
        before,
        [Entrant("random", "random")],
        ["assembly"],
        journal,
        before.seeds("dev", True)[:2],
        conditions=("eyes",),
    )
    write_results(before, out)
    assert before.stale(Journal.read_stamp(out) or {}) == ""
    assert "Stale" not in render(before, out)

    _retrain(measured)
    after = load_suite(path)
    assert after.sha256 != before.sha256 and after.inputs != before.inputs
    stale = after.stale(Journal.read_stamp(out) or {})
    assert "data/measured.json" in stale
    with pytest.raises(SuiteError, match=r"data/measured\.json.*new --out"):
        Journal(out, after, "dev", True, commit="test")  # refused as for another suite
    page = render(after, out)
    assert "**Stale**" in page and "data/measured.json" in page


def test_a_missing_condition_file_is_one_clear_error(tmp_path):
    path, measured = _suite_copy(tmp_path)
    measured.unlink()
    with pytest.raises(SuiteError, match=r"condition file .data/measured\.json."):
        load_suite(path)


def test_the_eyes_row_of_the_docs_quotes_the_shipped_confusion():
    """docs/bench.md's `eyes` row is computed from measured.json: the range of right and of
    discarded readings over the gestures, and each thumb's misread and discarded share."""
    data = json.loads((SUITE_FILE.parent / MEASURED).resolve().read_text(encoding="utf-8"))
    right = [row[i] for i, row in enumerate(data["confusion"])]
    gone = [row[-1] for row in data["confusion"]]
    ok, not_ok = (data["feedback_confusion"][data["feedback"].index(n)] for n in ("OK", "not OK"))

    def pct(x: float) -> str:
        return f"{100 * x:.1f}"

    row = next(
        line
        for line in (Path(__file__).parents[1] / "docs" / "bench.md").read_text().splitlines()
        if line.startswith("| `eyes` |")
    )
    assert f"{pct(min(right))}-{pct(max(right))} % right per gesture" in row
    assert f"{pct(min(gone))}-{pct(max(gone))} % discarded" in row
    assert f"not-OK read as OK {pct(not_ok[0])} %, discarded {pct(not_ok[2])} %" in row
    assert f"OK read as not-OK {pct(ok[1])} %, discarded {pct(ok[2])} %" in row
