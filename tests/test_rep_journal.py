"""The journal of a study's finished repetitions (:mod:`pil.experiments.rep_journal`): what a
rerun reads back, and what it does not trust."""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np
import pytest

from pil.experiments.rep_journal import JOURNAL_NAME, RepJournal
from pil.regular_files import UnreadableFileError

SETTINGS = {"study": "study", "rates": [0.4, 1.0], "seed": 0}
ROWS = [{"rep": 0, "rate": np.float64(0.4), "gestures": np.int64(12), "ok": np.True_}]


def test_a_finished_repetition_is_read_back_with_the_same_values(tmp_path: Path) -> None:
    kept = RepJournal(tmp_path, SETTINGS).add(0, 77, ROWS)
    assert kept == [{"rep": 0, "rate": 0.4, "gestures": 12, "ok": True}]
    assert [type(v) for v in kept[0].values()] == [int, float, int, bool]
    again = RepJournal(tmp_path, SETTINGS)
    assert again.count() == 1
    assert again.finished(0, 77) == kept
    assert again.finished(0, 78) is None  # another seed: run again
    assert again.finished(1, 77) is None


def test_a_torn_last_line_is_ignored_and_the_next_starts_on_its_own_line(tmp_path: Path) -> None:
    RepJournal(tmp_path, SETTINGS).add(0, 7, ROWS)
    path = tmp_path / JOURNAL_NAME
    with path.open("a") as handle:
        handle.write('{"format": 1, "key": "x", "rep": 1, "se')  # killed mid-write
    journal = RepJournal(tmp_path, SETTINGS)
    assert journal.count() == 1
    journal.add(1, 8, ROWS)
    assert RepJournal(tmp_path, SETTINGS).finished(1, 8) is not None
    assert RepJournal(tmp_path, SETTINGS).count() == 2


def test_a_journal_of_other_settings_is_started_anew(tmp_path: Path) -> None:
    RepJournal(tmp_path, SETTINGS).add(0, 7, ROWS)
    other = RepJournal(tmp_path, {**SETTINGS, "seed": 1})
    assert other.count() == 0 and not (tmp_path / JOURNAL_NAME).exists()
    other.add(0, 9, ROWS)
    assert RepJournal(tmp_path, SETTINGS).count() == 0  # the first study's reps are gone


def test_a_torn_utf8_character_at_the_end_keeps_every_finished_repetition(
    tmp_path: Path,
) -> None:
    """Issue 39: a torn character made the whole journal unreadable; it was deleted and every
    finished repetition ran again without a word."""
    RepJournal(tmp_path, SETTINGS).add(0, 7, ROWS)
    RepJournal(tmp_path, SETTINGS).add(1, 8, ROWS)
    path = tmp_path / JOURNAL_NAME
    with path.open("ab") as handle:
        handle.write("é".encode()[:1])  # the first byte of a two-byte character
    journal = RepJournal(tmp_path, SETTINGS)
    assert journal.count() == 2 and journal.dropped == 1
    assert path.exists()
    journal.add(2, 9, ROWS)
    again = RepJournal(tmp_path, SETTINGS)
    assert again.count() == 3 and again.dropped == 1


def test_damaged_lines_in_the_middle_are_dropped_and_counted(tmp_path: Path) -> None:
    RepJournal(tmp_path, SETTINGS).add(0, 7, ROWS)
    path = tmp_path / JOURNAL_NAME
    key = RepJournal(tmp_path, SETTINGS).key
    with path.open("ab") as handle:
        handle.write(b'{"format": 1, "key": "' + key.encode() + b'", "rep": 1, "seed": NaN}\n')
        handle.write(b'{"format": 1, "key": "' + key.encode() + b'", "rep": "1", "seed": 3,')
        handle.write(b' "rows": []}\n\xff\xfe\n')
    RepJournal(tmp_path, SETTINGS).add(3, 9, ROWS)
    journal = RepJournal(tmp_path, SETTINGS)
    assert journal.count() == 2 and journal.dropped == 3


@pytest.mark.parametrize("kind", ["dev-zero", "fifo", "folder"])
def test_a_journal_that_is_not_a_regular_file_is_refused_by_name(tmp_path: Path, kind: str) -> None:
    path = tmp_path / JOURNAL_NAME
    if kind == "dev-zero":
        path.symlink_to("/dev/zero")
    elif kind == "fifo":
        os.mkfifo(path)
    else:
        path.mkdir()
    with pytest.raises(UnreadableFileError, match=f"{JOURNAL_NAME}: cannot read the study"):
        RepJournal(tmp_path, SETTINGS)
