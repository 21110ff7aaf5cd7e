"""Figures quoted in docs/ agree with the results files they come from.

A quoted figure is followed by a marker naming its source, e.g.

    1869/1877<!-- from bench/results/label_accuracy/labels.csv: seed=all; labelled; d -->

(``FILE: key=value, key=value; column; format``, keys apart by ", "): the CSV row whose
cells equal every key=value (exactly one), its column, formatted with the Python format
spec; the text right before the marker must end with it (a typographic minus counts as
"-"). A quoted table follows a marker naming its file, e.g.

    <!-- hand-hidden table: bench/results/hand_hidden/table.md -->

and its rows (the lines starting with "|" right after it) must be the file's table rows.
Every folder of bench/results is made by one recipe of ``bench/regenerate.py``.
"""

from __future__ import annotations

import csv
import functools
import importlib.util
import re
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent
MARKER = re.compile(
    r"<!-- from (?P<file>[^:]+): (?P<keys>[^;]*); (?P<column>[^;]+); (?P<fmt>[^ ]*) -->"
)


def _markers() -> list[tuple[str, int, re.Match[str], str]]:
    found = []
    for doc in [*sorted((ROOT / "docs").glob("*.md")), ROOT / "README.md"]:
        text = doc.read_text()
        for match in MARKER.finditer(text):
            line = text.count("\n", 0, match.start()) + 1
            found.append((doc.name, line, match, text[: match.start()]))
    return found


TABLE_MARKER = re.compile(r"<!-- [\w-]+ table: (?P<file>bench/results/\S+\.md) -->")


def _table_rows(lines: list[str]) -> list[str]:
    """The first run of table rows (lines starting with "|") in ``lines``."""
    start = next((k for k, line in enumerate(lines) if line.startswith("|")), len(lines))
    rows = []
    for line in lines[start:]:
        if not line.startswith("|"):
            break
        rows.append(line.rstrip())
    return rows


def _quoted_tables() -> list[tuple[str, int, str, list[str]]]:
    found = []
    for doc in [*sorted((ROOT / "docs").glob("*.md")), ROOT / "README.md"]:
        lines = doc.read_text().splitlines()
        for k, line in enumerate(lines):
            match = TABLE_MARKER.search(line)
            if match:
                found.append((doc.name, k + 1, match["file"], _table_rows(lines[k + 1 :])))
    return found


@functools.cache
def _table(path: Path) -> tuple[dict[str, str], ...]:
    with path.open(newline="") as handle:
        return tuple(csv.DictReader(handle))


def _row(path: Path, keys: str) -> dict[str, str]:
    wanted = dict(k.strip().split("=", 1) for k in keys.split(", ") if k.strip())
    rows = [r for r in _table(path) if all(r.get(k) == v for k, v in wanted.items())]
    assert len(rows) == 1, f"{path.name}: {len(rows)} rows match {wanted}"
    return rows[0]


def _format(value: str, fmt: str) -> str:
    if fmt in ("", "s"):
        return value
    number = float(value)
    return format(round(number) if fmt == "d" else number, fmt)


def test_there_are_quoted_figures() -> None:
    assert len(_markers()) >= 10


@pytest.mark.parametrize(
    ("doc", "line", "match", "before"),
    _markers(),
    ids=lambda v: str(v)[:30] if isinstance(v, str) else None,
)
def test_a_quoted_figure_equals_its_results_file(doc: str, line: int, match, before: str) -> None:
    path = ROOT / match["file"]
    assert path.is_file(), f"{doc}:{line}: {match['file']} does not exist"
    row = _row(path, match["keys"])
    assert match["column"] in row, f"{doc}:{line}: no column {match['column']!r}"
    want = _format(row[match["column"]], match["fmt"]).replace("−", "-")
    got = before.replace("−", "-")
    assert got.endswith(want), (
        f"{doc}:{line}: the text quotes {got[-20:]!r}, the file says {want!r}"
    )


def test_there_are_quoted_tables() -> None:
    assert len(_quoted_tables()) >= 3


@pytest.mark.parametrize(("doc", "line", "file", "rows"), _quoted_tables())
def test_a_quoted_table_equals_its_results_file(
    doc: str, line: int, file: str, rows: list[str]
) -> None:
    path = ROOT / file
    assert path.is_file(), f"{doc}:{line}: {file} does not exist"
    want = _table_rows(path.read_text().splitlines())
    assert rows and rows == want, f"{doc}:{line}: the table differs from {file}"


def test_every_results_folder_has_a_recipe() -> None:
    spec = importlib.util.spec_from_file_location("regenerate", ROOT / "bench" / "regenerate.py")
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    sys.modules[spec.name] = module  # a dataclass module must be importable by name
    spec.loader.exec_module(module)
    folders = {p.name for p in (ROOT / "bench" / "results").iterdir() if p.is_dir()}
    folders = {f for f in folders if not f.startswith(".")}
    assert folders <= set(module.BY_NAME), folders - set(module.BY_NAME)


def test_a_wrong_quote_is_caught(tmp_path: Path) -> None:
    table = tmp_path / "t.csv"
    table.write_text("seed,labelled\nall,1877\n")
    assert _format(_row(table, "seed=all")["labelled"], "d") == "1877"
    assert not "labelled 1876".endswith(_format("1877", "d"))
    assert _format("-2.61", ".1f") == "-2.6"
