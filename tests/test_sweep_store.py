"""Tests of the sweep's results on disk: journal, torn lines, lock, manifest, merged CSV."""

from __future__ import annotations

import csv
import json

import numpy as np
import pytest

from pil.experiments.sweep_store import (
    JOURNAL,
    MANIFEST,
    RESULTS,
    TIMINGS,
    RunStore,
    SweepStoreError,
    make_record,
    read_journal,
)

MANIFEST_DATA = {"kind": "learner", "function": "pil.experiments.systems:run_one", "seed": 0}
ID_COLUMNS = ["run_id", "system", "rate", "rep", "seed"]


def columns(run_id: str, rep: int = 0) -> dict[str, object]:
    system = run_id.split("|")[0]
    return {"run_id": run_id, "system": system, "rate": 0.6, "rep": rep, "seed": 11 + rep}


def ok(gestures: float) -> dict[str, object]:
    return {"status": "ok", "metrics": {"gestures": gestures, "actions": 2 * gestures}}


FAILED = {"status": "failed", "error": "RuntimeError: boom", "metrics": {}}


def test_records_survive_reopening_and_mark_runs_finished(tmp_path) -> None:
    with RunStore(tmp_path, MANIFEST_DATA) as store:
        store.append(make_record(columns("pil|a"), ok(3), 1))
        store.append(make_record(columns("c1|a"), FAILED, 1))
    with RunStore(tmp_path, MANIFEST_DATA) as store:
        assert store.finished_ids() == {"pil|a"}
        assert store.attempts("c1|a") == 1
        assert [r["status"] for r in store.records] == ["ok", "failed"]
    assert json.loads((tmp_path / MANIFEST).read_text())["seed"] == 0


def test_torn_last_line_is_ignored_and_cut_off(tmp_path) -> None:
    with RunStore(tmp_path, MANIFEST_DATA) as store:
        store.append(make_record(columns("pil|a"), ok(3), 1))
    journal = tmp_path / JOURNAL
    intact = journal.read_bytes()
    journal.write_bytes(intact + b'{"run_id": "pil|b", "status": "o')  # killed mid-write
    assert read_journal(journal) == (read_journal(journal)[0], len(intact))
    with RunStore(tmp_path, MANIFEST_DATA) as store:
        assert store.finished_ids() == {"pil|a"}
        store.append(make_record(columns("pil|b"), ok(4), 1))
    lines = journal.read_bytes().splitlines()
    assert len(lines) == 2 and all(json.loads(line)["status"] == "ok" for line in lines)


def test_a_corrupt_line_inside_the_journal_is_an_error(tmp_path) -> None:
    with RunStore(tmp_path, MANIFEST_DATA) as store:
        store.append(make_record(columns("pil|a"), ok(3), 1))
    journal = tmp_path / JOURNAL
    journal.write_bytes(b"garbage\n" + journal.read_bytes())
    with pytest.raises(SweepStoreError, match=r"runs.jsonl: line 1 is not a run record"):
        RunStore(tmp_path, MANIFEST_DATA).__enter__()


def test_a_directory_is_bound_to_its_settings(tmp_path) -> None:
    with RunStore(tmp_path, MANIFEST_DATA):
        pass
    with pytest.raises(SweepStoreError, match=r"other settings \(seed: 0 there, 5 now\)"):
        RunStore(tmp_path, {**MANIFEST_DATA, "seed": 5}).__enter__()


def test_two_sweeps_cannot_write_one_directory(tmp_path) -> None:
    with (
        RunStore(tmp_path, MANIFEST_DATA),
        pytest.raises(SweepStoreError, match="in use by another running robin-pil command"),
    ):
        RunStore(tmp_path, MANIFEST_DATA).__enter__()
    with RunStore(tmp_path, MANIFEST_DATA):  # the lock is released on close
        pass


def test_merged_csv_is_sorted_and_independent_of_write_order(tmp_path) -> None:
    records = [
        make_record(columns("pil|b", 1), ok(5), 1),
        make_record(columns("c1|a"), FAILED, 1),
        make_record(columns("c1|a"), ok(7.25), 2),  # the retry passed
        make_record(columns("pil|a"), FAILED, 1),
        make_record(columns("pil|a"), FAILED, 2),  # failed for good
        make_record(columns("pil|a"), ok(1), 3),  # a later invocation passed
        make_record(columns("c2|a"), FAILED, 1),
    ]
    outputs = []
    for order, directory in ((records, tmp_path / "one"), (records[::-1], tmp_path / "two")):
        with RunStore(directory, MANIFEST_DATA) as store:
            for record in order:
                store.append({**record, "wall_s": len(outputs), "host": directory.name})
            ids = ["pil|a", "pil|b", "c1|a", "c2|a", "c3|never-ran"]
            outputs.append(store.write_results(ids, ID_COLUMNS).read_bytes())
    assert outputs[0] == outputs[1]
    rows = list(csv.DictReader(outputs[0].decode().splitlines()))
    assert [r["run_id"] for r in rows] == ["c1|a", "c2|a", "pil|a", "pil|b"]
    assert [r["status"] for r in rows] == ["ok", "failed", "ok", "ok"]
    assert rows[0]["gestures"] == "7.25" and rows[1]["error"] == "RuntimeError: boom"
    assert list(rows[0]) == [*ID_COLUMNS, "status", "error", "gestures", "actions"]
    assert not list((tmp_path / "one").glob(".*.tmp"))
    assert (tmp_path / "one" / RESULTS).exists()


def test_numpy_metrics_are_written_as_plain_numbers(tmp_path) -> None:
    outcome = {
        "status": "ok",
        "metrics": {"n": np.int64(3), "x": np.float64(0.1), "b": np.bool_(True)},
    }
    with RunStore(tmp_path, MANIFEST_DATA) as store:
        store.append(make_record(columns("pil|a"), outcome, 1))
        text = store.write_results(["pil|a"], ID_COLUMNS).read_text()
    assert text.splitlines()[1].endswith(",ok,,3,0.1,True")


def test_out_must_be_a_directory(tmp_path) -> None:
    path = tmp_path / "file"
    path.write_text("x")
    with pytest.raises(SweepStoreError, match="exists and is not a directory"):
        RunStore(path, MANIFEST_DATA).__enter__()


def test_machine_timings_go_to_timings_csv_not_results(tmp_path) -> None:
    outcome = {"status": "ok", "metrics": {"legs": 4, "wall_time_s": 12.5, "real_time_factor": 3.1}}
    with RunStore(tmp_path, MANIFEST_DATA) as store:
        store.append({**make_record(columns("pil|a"), outcome, 1), "host": "n1:7", "wall_s": 13.0})
        results = store.write_results(["pil|a"], ID_COLUMNS).read_text()
    assert results.splitlines()[0].endswith(",status,error,legs")
    assert (tmp_path / TIMINGS).read_text().splitlines() == [
        "run_id,host,wall_s,wall_time_s,real_time_factor",
        "pil|a,n1:7,13.0,12.5,3.1",
    ]
