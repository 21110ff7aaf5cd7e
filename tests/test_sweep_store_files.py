"""A sweep directory whose files are of the wrong kind, and journal records without metrics."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from pil.experiments.sweep_store import (
    JOURNAL,
    MANIFEST,
    RESULTS,
    RunStore,
    SweepStoreError,
    make_record,
)
from robin_sim.cli.main import main

MANIFEST_DATA = {"kind": "learner", "function": "pil.experiments.systems:run_one", "seed": 0}


@pytest.mark.parametrize("name", [MANIFEST, JOURNAL, RESULTS])
def test_a_folder_in_place_of_a_store_file_is_refused(tmp_path: Path, name: str) -> None:
    (tmp_path / name).mkdir()
    with pytest.raises(SweepStoreError, match=f"{name} is not a regular file"):
        RunStore(tmp_path, MANIFEST_DATA).__enter__()


@pytest.mark.parametrize("text", ["[]", "3", '"x"', "null"])
def test_a_manifest_that_is_not_an_object_is_refused(tmp_path: Path, text: str) -> None:
    (tmp_path / MANIFEST).write_text(text)
    with pytest.raises(SweepStoreError, match="not the sweep's settings"):
        RunStore(tmp_path, MANIFEST_DATA).__enter__()


def test_an_ok_record_without_metrics_is_not_done(tmp_path: Path) -> None:
    columns = {"run_id": "pil|a", "system": "pil", "rate": 1.0, "rep": 0, "seed": 1}
    with RunStore(tmp_path, MANIFEST_DATA) as store:
        record = make_record(columns, {"status": "ok", "metrics": {"gestures": 3}}, 1)
        store.append({**record, "metrics": None})
    with RunStore(tmp_path, MANIFEST_DATA) as store:
        assert store.finished_ids() == set()
        path = store.write_results(["pil|a"], list(columns))
        assert "failed,journal record without metrics" in path.read_text()
        store.append(make_record(columns, {"status": "ok", "metrics": {"gestures": 3}}, 2))
        assert store.finished_ids() == {"pil|a"}
        assert ",ok,,3" in store.write_results(["pil|a"], list(columns)).read_text()


@pytest.mark.parametrize("how", ["folder", "list"])
def test_sweep_cli_refuses_a_wrong_kind_of_manifest_with_exit_2(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], how: str
) -> None:
    out = tmp_path / "sweep"
    out.mkdir()
    if how == "folder":
        (out / MANIFEST).mkdir()
    else:
        (out / MANIFEST).write_text(json.dumps([]))
    argv = ["sweep", "--reps", "1", "--systems", "pil", "--rates", "1.0", "--quiet"]
    code = main([*argv, "--workers", "1", "--no-report", "--out", str(out)])
    err = capsys.readouterr().err.strip()
    assert code == 2, err
    assert err.count("\n") == 0 and err.startswith("robin-pil sweep: error: ")
    assert MANIFEST in err
    assert sorted(p.name for p in out.iterdir()) == [MANIFEST]
