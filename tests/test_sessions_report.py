"""The sessions report (pil/experiments/sessions_report.py, `robin-pil report DIR`)."""

from __future__ import annotations

import csv
import json
import math
import subprocess
import sys
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from scipy import stats

from pil.experiments.sessions_report import (
    MEASURES,
    SESSION_COLUMNS,
    SessionsError,
    is_within,
    load_sessions,
    session_tests,
    summarize_sessions,
)
from robin_sim.cli.main import main


def summary(
    participant: str,
    session: str,
    condition: str,
    values: dict[str, Any],
    status: str = "finished",
    block: int | None = 1,
) -> dict[str, Any]:
    """A summary.json in the live contract's shape (episode fields plus the "live" block)."""
    fields = {
        "gestures": 14,
        "actions": 20,
        "rejected": 4,
        "interrupted_actions": 1,
        "sim_time_s": 120.0,
        "mean_handover_s": 30.0,
        "legs_delivered": 3,
    }
    fields.update(values)
    return {
        "status": status,
        "error": "",
        "system": condition,
        "rate": 1.0,
        "seed": 0,
        "scenario": "table_one",
        "tables": 1,
        "legs_total": 3,
        **fields,
        "live": {
            "participant": participant,
            "session": session,
            "condition": condition,
            "block": block,
            "protocol": "reactive_vs_proactive",
            "handover_types": ["A", "B", "C"],
            "inputs": 40,
            "inputs_rejected": 2,
            "frames_streamed": 1800,
            "stream_fps": 15.0,
            "started_utc": "2026-12-01T12:00:00Z",
        },
    }


def write(root: Path, data: dict[str, Any]) -> Path:
    live = data["live"]
    path = root / live["participant"] / live["session"] / "summary.json"
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(json.dumps(data), encoding="utf-8")
    return path


# within-subject: (participant, condition, block, gestures, actions, mean handover s)
WITHIN = [
    ("P01", "pil", 1, 20, 30, 41.0),
    ("P01", "pil", 2, 16, 24, 35.0),
    ("P01", "proactive", 3, 14, 26, 30.5),
    ("P02", "proactive", 1, 15, 27, 31.0),
    ("P02", "pil", 2, 19, 25, 38.0),
    ("P03", "pil", 1, 22, 33, 44.0),
    ("P03", "proactive", 2, 13, 29, 29.0),
    ("P04", "proactive", 1, 17, 22, None),
    ("P04", "pil", 2, 18, 21, 36.5),
]


@pytest.fixture
def within_folder(tmp_path: Path) -> Path:
    root = tmp_path / "live"
    for participant, condition, block, gestures, actions, handover in WITHIN:
        values = {
            "gestures": gestures,
            "actions": actions,
            "mean_handover_s": handover,
            "sim_time_s": 100.0 + gestures * 3.5,
            "rejected": actions - gestures,
        }
        write(
            root, summary(participant, f"block{block}-{condition}", condition, values, block=block)
        )
    # an unfinished session: listed, not counted
    write(root, summary("P02", "block3-proactive", "proactive", {"gestures": 99}, "ended", 3))
    episode = root / "P01" / "episode-test" / "summary.json"  # no "live" block: not a session
    episode.parent.mkdir(parents=True)
    episode.write_text(json.dumps({"status": "finished", "gestures": 5}), encoding="utf-8")
    return root


def counted(rows: list[dict[str, Any]], condition: str, measure: str) -> list[float]:
    return [
        r[measure]
        for r in rows
        if r["counted"] and r["condition"] == condition and r[measure] is not None
    ]


def test_means_and_sds_match_numpy(within_folder: Path) -> None:
    rows = load_sessions(within_folder)
    assert len(rows) == 10 and sum(r["counted"] for r in rows) == 9
    summary_rows = {s["condition"]: s for s in summarize_sessions(rows)}
    assert list(summary_rows) == ["pil", "proactive"]
    assert summary_rows["pil"]["n"] == 5 and summary_rows["proactive"]["n"] == 4
    for condition, entry in summary_rows.items():
        for measure in MEASURES:
            values = np.array(counted(rows, condition, measure), dtype=float)
            assert entry[f"{measure}_mean"] == pytest.approx(values.mean(), rel=1e-12)
            assert entry[f"{measure}_sd"] == pytest.approx(values.std(ddof=1), rel=1e-12)
    assert summary_rows["proactive"]["gestures_mean"] == pytest.approx((14 + 15 + 13 + 17) / 4)
    assert summary_rows["proactive"]["mean_handover_s_n"] == 3  # P04's null left out


def test_paired_t_tests_match_scipy(within_folder: Path) -> None:
    rows = load_sessions(within_folder)
    assert is_within(rows)
    tests = {t["measure"]: t for t in session_tests(rows)}
    assert set(tests) == set(MEASURES)
    # participants' means per condition (P01's two pil blocks averaged), same order
    pil_g, pro_g = [(20 + 16) / 2, 19, 22, 18], [14, 15, 13, 17]
    expected = stats.ttest_rel(pil_g, pro_g)
    gestures = tests["gestures"]
    assert (gestures["test"], gestures["a"], gestures["b"], gestures["n"]) == (
        "paired",
        "pil",
        "proactive",
        4,
    )
    assert gestures["t"] == pytest.approx(expected.statistic, rel=1e-12)
    assert gestures["p"] == pytest.approx(expected.pvalue, rel=1e-12)
    assert gestures["mean_a"] == pytest.approx(np.mean(pil_g))
    # P04 has no proactive handover time: 3 pairs
    pil_h, pro_h = [(41.0 + 35.0) / 2, 38.0, 44.0], [30.5, 31.0, 29.0]
    handover = tests["mean_handover_s"]
    assert handover["n"] == 3
    assert handover["p"] == pytest.approx(stats.ttest_rel(pil_h, pro_h).pvalue, rel=1e-12)
    # legs delivered: all 3 everywhere, differences constant -> no p-value
    assert math.isnan(tests["legs_delivered"]["p"]) and math.isnan(tests["legs_delivered"]["t"])


def test_paired_tests_carry_interval_effect_size_and_holm(within_folder: Path) -> None:
    """The difference's CI and d_z match scipy; Holm runs over the declared family (every
    measure of the one pair), untestable comparisons left out of it, as statsmodels does."""
    from statsmodels.stats.multitest import multipletests

    tests = {t["measure"]: t for t in session_tests(load_sessions(within_folder))}
    pil_g, pro_g = [(20 + 16) / 2, 19, 22, 18], [14, 15, 13, 17]
    diffs = np.subtract(pil_g, pro_g)
    ci = stats.ttest_rel(pil_g, pro_g).confidence_interval(0.95)
    gestures = tests["gestures"]
    assert gestures["mean_diff"] == pytest.approx(diffs.mean(), rel=1e-12)
    assert (gestures["ci_low"], gestures["ci_high"]) == pytest.approx((ci.low, ci.high))
    assert gestures["effect_size"] == pytest.approx(diffs.mean() / diffs.std(ddof=1))
    testable = [m for m in MEASURES if not math.isnan(tests[m]["p"])]
    assert 1 < len(testable) < len(MEASURES)  # legs delivered has no spread: out of the family
    expected = multipletests([tests[m]["p"] for m in testable], method="holm")[1]
    assert [tests[m]["p_holm"] for m in testable] == pytest.approx(list(expected), rel=1e-12)
    legs = tests["legs_delivered"]
    assert all(math.isnan(legs[k]) for k in ("p_holm", "ci_low", "ci_high", "effect_size"))


def test_between_subject_gets_welch(tmp_path: Path) -> None:
    root = tmp_path / "between"
    data = {
        "pil": {"P01": 20, "P03": 23, "P05": 19},
        "proactive": {"P02": 14, "P04": 17, "P06": 12},
    }
    for condition, by in data.items():
        for participant, gestures in by.items():
            write(root, summary(participant, "s1", condition, {"gestures": gestures}))
    write(root, summary("P05", "s2", "pil", {"gestures": 25}))  # a repeated block: averaged
    rows = load_sessions(root)
    assert not is_within(rows)
    test = next(t for t in session_tests(rows) if t["measure"] == "gestures")
    expected = stats.ttest_ind([20, 23, 22], [14, 17, 12], equal_var=False)
    assert (test["test"], test["n"]) == ("welch", "3/3")
    assert test["p"] == pytest.approx(expected.pvalue, rel=1e-12)
    assert test["t"] == pytest.approx(expected.statistic, rel=1e-12)
    ci = expected.confidence_interval(0.95)
    assert (test["ci_low"], test["ci_high"]) == pytest.approx((ci.low, ci.high))
    pooled = math.sqrt((np.var([20, 23, 22], ddof=1) + np.var([14, 17, 12], ddof=1)) / 2)
    assert test["effect_size"] == pytest.approx((np.mean([20, 23, 22]) - 43 / 3) / pooled)


def test_sessions_sort_participants_by_number(tmp_path: Path) -> None:
    for participant in ("P10", "P2", "P1"):
        write(tmp_path, summary(participant, "s", "pil", {}))
    assert [r["participant"] for r in load_sessions(tmp_path)] == ["P1", "P2", "P10"]


def test_unfinished_sessions_do_not_make_a_design_within(tmp_path: Path) -> None:
    root = tmp_path / "live"
    write(root, summary("P01", "a", "pil", {}))
    write(root, summary("P01", "b", "proactive", {}, status="interrupted"))
    assert not is_within(load_sessions(root))


def test_cli_writes_csv_report_and_figure(within_folder: Path, capsys: Any) -> None:
    out = within_folder.parent / "rep"
    assert main(["report", str(within_folder), "--out", str(out)]) == 0
    listed = capsys.readouterr().out.split()
    names = ("sessions.csv", "session_tests.csv", "report.md", "sessions.png")
    assert listed == [str(out / n) for n in names]
    with (out / "sessions.csv").open(newline="") as handle:
        reader = csv.DictReader(handle)
        assert tuple(reader.fieldnames or ()) == SESSION_COLUMNS
        table = list(reader)
    assert len(table) == 10
    ended = [r for r in table if r["counted"] == "False"]
    assert [(r["participant"], r["session"], r["status"], r["gestures"]) for r in ended] == [
        ("P02", "block3-proactive", "ended", "99")
    ]
    first = table[0]
    assert (first["participant"], first["block"], first["condition"], first["gestures"]) == (
        "P01",
        "1",
        "pil",
        "20",
    )
    assert first["summary"] == "P01/block1-pil/summary.json"
    assert first["handover_types"] == "A B C" and first["stream_fps"] == "15.0"
    assert (
        next(r for r in table if r["participant"] == "P04" and r["condition"] == "proactive")[
            "mean_handover_s"
        ]
        == ""
    )
    report = (out / "report.md").read_text()
    assert "status `finished`" in report and "## Paired t-tests (within-subject)" in report
    assert "| P02 | block3-proactive | proactive | table_one | ended | 3 / 3 |" in report
    p = stats.ttest_rel([18, 19, 22, 18], [14, 15, 13, 17]).pvalue
    assert "| instruction gestures | pil | proactive | 4 | 19.25 | 14.75 |" in report
    assert f"{p:.3g}" in report and "| p (Holm) |" in report and "a - b [95 % CI]" in report
    with (out / "session_tests.csv").open(newline="") as handle:
        tested = {r["measure"]: r for r in csv.DictReader(handle)}
    assert set(tested) == set(MEASURES)
    assert float(tested["gestures"]["p"]) == pytest.approx(p, rel=1e-9)
    assert float(tested["gestures"]["p_holm"]) >= float(tested["gestures"]["p"])
    import matplotlib.image

    image = matplotlib.image.imread(out / "sessions.png")
    assert image.shape[0] > 300 and image.shape[1] > 600 and image[..., :3].std() > 0.05


def test_default_out_is_inside_the_folder_and_end_to_end(within_folder: Path) -> None:
    done = subprocess.run(
        [sys.executable, "-m", "robin_sim.cli.main", "report", str(within_folder)],
        capture_output=True,
        text=True,
    )
    assert done.returncode == 0, done.stderr
    assert (within_folder / "report" / "sessions.csv").is_file()
    assert len(load_sessions(within_folder)) == 10  # the report folder adds no sessions


def refused(args: list[str], capsys: Any) -> str:
    assert main(["report", *args]) == 2
    err = capsys.readouterr().err
    assert err.startswith("robin-pil report: error: ") and len(err.splitlines()) == 1
    return err


def test_a_folder_that_is_neither_is_refused(tmp_path: Path, capsys: Any) -> None:
    (tmp_path / "notes.txt").write_text("hello")
    err = refused([str(tmp_path)], capsys)
    assert f"{tmp_path}: nothing to report; expected a folder of live sessions" in err
    assert '"live" block' in err and "results.csv or runs.csv" in err
    assert sorted(p.name for p in tmp_path.iterdir()) == ["notes.txt"]
    err = refused([str(tmp_path / "no_such_folder")], capsys)
    assert "no_such_folder: no such file or folder; expected a results CSV, a study" in err


def test_an_out_path_that_is_a_file_is_refused(within_folder: Path, capsys: Any) -> None:
    (within_folder.parent / "taken").write_text("x")
    err = refused([str(within_folder), "--out", str(within_folder.parent / "taken")], capsys)
    assert "taken: cannot make the folder" in err


@pytest.mark.parametrize(
    ("text", "message"),
    [
        ('{"status": "finished", "live": {', "not a JSON summary at line 1; the file is corrupt"),
        ("[1, 2]", "expected a JSON object"),
        (
            json.dumps({**summary("P09", "x", "pil", {}), "gestures": "many"}),
            "gestures: expected a number, got 'many'",
        ),
        (
            json.dumps({k: v for k, v in summary("P09", "x", "pil", {}).items() if k != "actions"}),
            "missing field 'actions'; a live summary has gestures, actions",
        ),
        (
            json.dumps({**summary("P09", "x", "pil", {}), "live": {"participant": "P09"}}),
            "live.session: expected a non-empty text, got None",
        ),
    ],
)
def test_a_corrupt_summary_is_named_and_nothing_written(
    within_folder: Path, capsys: Any, text: str, message: str
) -> None:
    bad = within_folder / "P09" / "x" / "summary.json"
    bad.parent.mkdir(parents=True)
    bad.write_text(text, encoding="utf-8")
    out = within_folder.parent / "rep"
    err = refused([str(within_folder), "--out", str(out)], capsys)
    assert f"{bad}: " in err and message in err
    assert not out.exists()
    with pytest.raises(SessionsError):
        load_sessions(within_folder)


def test_sessions_refuse_csv_options(tmp_path: Path, capsys: Any) -> None:
    write(tmp_path, summary("P01", "b", "pil", {}))
    err = refused([str(tmp_path), "--baseline", "pil"], capsys)
    assert "--metrics and --baseline are for a results CSV" in err
    assert not (tmp_path / "report").exists()


def test_study_folders_and_csvs_still_report(tmp_path: Path, capsys: Any) -> None:
    lines = ["rep,system,rate,total_gestures,total_actions,gestures,actions"]
    lines += [
        f"{r},{s},1.0,{10 + r + k},{20 + r},{10 + r + k},{20 + r * k}"
        for r in range(3)
        for k, s in enumerate(("pil", "c1"))
    ]
    (tmp_path / "runs.csv").write_text("\n".join(lines) + "\n")
    assert main(["report", str(tmp_path)]) == 0
    assert (tmp_path / "report" / "summary.md").is_file()
    assert main(["report", str(tmp_path / "runs.csv"), "--out", str(tmp_path / "r2")]) == 0
    assert (tmp_path / "r2" / "tests.csv").is_file()  # paired by rep (no seed column)
    assert ",rep," in (tmp_path / "r2" / "tests.csv").read_text()
    capsys.readouterr()
    err = refused([str(tmp_path / "runs.csv"), "--baseline", "nope"], capsys)
    assert "unknown baseline system 'nope'; valid choices: 'c1', 'pil'" in err


def test_one_condition_is_summarised_without_tests(tmp_path: Path, capsys: Any) -> None:
    write(tmp_path, summary("P01", "a", "pil", {"gestures": 12}))
    write(tmp_path, summary("P02", "a", "pil", {"gestures": 16}))
    assert main(["report", str(tmp_path)]) == 0
    report = (tmp_path / "report" / "report.md").read_text()
    assert "| pil | 2 | 2 | 14.00 ± 2.83 |" in report
    assert "No t-tests: the counted sessions hold fewer than two conditions." in report
    assert (tmp_path / "report" / "sessions.png").read_bytes().startswith(b"\x89PNG")


def test_only_unfinished_sessions_are_listed_and_the_report_goes_on(
    tmp_path: Path, capsys: Any
) -> None:
    write(tmp_path, summary("P01", "a", "pil", {"legs_delivered": 1}, status="ended"))
    assert main(["report", str(tmp_path)]) == 0
    report = (tmp_path / "report" / "report.md").read_text()
    assert "1 sessions of 1 participants; 0 counted, 1 left out." in report
    assert "No session is `finished` yet" in report
    assert "| P01 | a | pil | table_one | ended | 1 / 3 | `P01/a/summary.json` |" in report
    rows = list(csv.DictReader((tmp_path / "report" / "sessions.csv").open()))
    assert [(r["status"], r["counted"]) for r in rows] == [("ended", "False")]
    assert not (tmp_path / "report" / "sessions.png").exists()  # no figure without a count


def test_scenarios_are_split_and_one_value_shows_n_without_sd(tmp_path: Path) -> None:
    four = summary("P01", "a", "pil", {"gestures": 16})
    four.update(scenario="assembly", legs_total=4)
    write(tmp_path, four)
    one = summary("P02", "a", "pil", {"gestures": 4})
    one.update(scenario="one_handover", legs_total=1)
    write(tmp_path, one)
    rows = load_sessions(tmp_path)
    entries = summarize_sessions(rows)
    assert [(e["scenario"], e["condition"], e["n"]) for e in entries] == [
        ("assembly", "pil", 1),
        ("one_handover", "pil", 1),
    ]
    assert [e["gestures_mean"] for e in entries] == [16.0, 4.0]  # never pooled to 10
    assert all(math.isnan(e["gestures_sd"]) for e in entries)
    assert main(["report", str(tmp_path)]) == 0
    report = (tmp_path / "report" / "report.md").read_text()
    assert "## scenario `assembly`, protocol `reactive_vs_proactive`" in report
    assert "## scenario `one_handover`, protocol `reactive_vs_proactive`" in report
    assert "| pil | 1 | 1 | 16.00 (n = 1) |" in report and "± 0.00" not in report
    assert "10.00" not in report


def test_a_summary_with_nan_anywhere_is_refused_by_name(tmp_path: Path) -> None:
    """Issue 39: ``"rate": NaN`` in a session's summary passed (the field is not a measure)."""
    from pil.experiments.sessions_load import SessionsError, _read_summary

    path = tmp_path / "summary.json"
    path.write_text('{"status": "finished", "rate": NaN}', encoding="utf-8")
    with pytest.raises(SessionsError, match=r"summary\.json: not a JSON summary"):
        _read_summary(path)
