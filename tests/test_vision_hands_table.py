"""The capsule-against-articulated table in docs/vision.md is what its results files give."""

from __future__ import annotations

import importlib.util
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
RESULTS = ROOT / "bench" / "results" / "vision_hands"


def _table_module():
    spec = importlib.util.spec_from_file_location(
        "vision_hands_table", ROOT / "bench" / "vision_hands_table.py"
    )
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    sys.modules[spec.name] = module
    spec.loader.exec_module(module)
    return module


def test_the_docs_table_and_table_md_are_the_results_files_table() -> None:
    module = _table_module()
    text = "\n".join(module.table(RESULTS / "capsule.csv", RESULTS / "articulated.csv")) + "\n"
    assert (RESULTS / "table.md").read_text() == text
    docs = (ROOT / "docs" / "vision.md").read_text()
    shown = docs.split(module.BEGIN, 1)[1].split(module.END, 1)[0]
    assert shown == "\n" + text
    assert "| all | all | 1008 |" in text  # 3 seeds x 336 paired samples


def test_a_changed_result_changes_the_table(tmp_path: Path) -> None:
    module = _table_module()
    lines = (RESULTS / "articulated.csv").read_text().splitlines()
    header, first = lines[0], lines[1].split(",")
    first[-1] = "0" if first[-1] == "1" else "1"  # one sample read the other way
    changed = tmp_path / "articulated.csv"
    changed.write_text("\n".join([header, ",".join(first), *lines[2:]]) + "\n")
    before = module.table(RESULTS / "capsule.csv", RESULTS / "articulated.csv")
    assert module.table(RESULTS / "capsule.csv", changed) != before


def test_the_docs_models_table_is_the_previous_and_this_models_table() -> None:
    """The previous model against this one, on the same articulated-hand samples."""
    module = _table_module()
    lines = module.table(RESULTS / "previous.csv", RESULTS / "articulated.csv", module.MODELS)
    text = "\n".join(lines) + "\n"
    assert (RESULTS / "models.md").read_text() == text
    docs = (ROOT / "docs" / "vision.md").read_text()
    shown = docs.split(module.MODELS_BEGIN, 1)[1].split(module.MODELS_END, 1)[0]
    assert shown == "\n" + text
    assert "| all | all | 1008 |" in text and "| shown | grasp |" in text
