"""Simulated people fitted to recorded live sessions: the sources, the consent, the fit.

The recorded sessions are ``tests/data/fitted_people`` (made by ``tests/people_record.py``:
two scripted stand-ins through a real study with consent, real live sessions; not people).
Pure Python and scipy: no physics here (``tests/test_people_sim.py`` runs the simulation).
"""

from __future__ import annotations

import dataclasses
import hashlib
import json
import os
import shutil
from pathlib import Path

import numpy as np
import pytest
from scipy import stats

from pil.experiments.people_fit import (
    FittedPerson,
    FittedPersonError,
    Latency,
    Rate,
    fit_person,
    read_person,
    write_person,
)
from pil.experiments.people_observed import observe
from pil.experiments.people_sources import find_sources
from pil.types import Feedback
from robin_sim.cli.main import main

DATA = Path(__file__).parent / "data" / "fitted_people"
STAND_INS = DATA / "stand_ins"


def copy(tmp_path: Path, name: str = "stand_ins") -> Path:
    folder = tmp_path / name
    shutil.copytree(DATA / name, folder)
    return folder


def test_the_sources_are_the_consented_sessions_with_their_checksums() -> None:
    sources = find_sources(STAND_INS)
    assert sorted(sources.sessions) == ["P01", "P02"] and sources.left_out == {}
    for who, sessions in sources.sessions.items():
        assert [s.name for s in sessions] == [
            f"sessions/{who}/block1-pil",
            f"sessions/{who}/block2-pil",
        ]
        for session in sessions:
            for name, sha in session.sha256.items():
                data = (STAND_INS / session.name / name).read_bytes()
                assert hashlib.sha256(data).hexdigest() == sha


def test_each_thumb_read_from_the_inputs_is_the_verdict_the_log_holds() -> None:
    """The observations come from inputs.jsonl and events.jsonl; the log's feedback is the
    session's own record of the same verdicts: a thumb down is "not ok", a thumb up "ok",
    silence "none", action by action."""
    for sessions in find_sources(STAND_INS).sessions.values():
        for session in sessions:
            seen = observe(session.inputs, session.events, session.log)
            verdicts = [e["feedback"] for e in session.log if e["action"] is not None]
            expected = {"down": "not ok", "up": "ok", None: "none"}
            read = [expected[None if j.late else j.thumb] for j in seen.judgements]
            assert read == verdicts, session.name
            gestures = [
                e
                for e in session.inputs
                if e["accepted"] and e["raw"].get("type") in ("point", "gesture")
            ]
            assert len(seen.gesture_latencies) == len(gestures) > 0
            assert min(seen.gesture_latencies) > 0.0
            assert all(j.latency > 0 for j in seen.judgements if j.latency is not None)


def test_the_fit_is_scipys_lognormal_and_exact_binomial_intervals() -> None:
    sessions = find_sources(STAND_INS).sessions["P02"]
    observed = [observe(s.inputs, s.events, s.log) for s in sessions]
    person = fit_person("P02", observed, [], [])
    latencies = [v for o in observed for v in o.gesture_latencies]
    sigma, _, scale = stats.lognorm.fit(latencies, floc=0)
    assert person.gesture_latency.median == pytest.approx(scale, abs=1e-4)
    assert person.gesture_latency.sigma == pytest.approx(sigma, abs=1e-4)
    assert person.gesture_latency.n == len(latencies)
    low, high = person.gesture_latency.median_low, person.gesture_latency.median_high
    assert low < person.gesture_latency.median < high
    rate = person.up_on_right  # Clopper-Pearson, as scipy's binomial test gives it
    k, n = rate.k, rate.n
    assert 0 < k < n
    ci = stats.binomtest(k, n).proportion_ci(0.95, method="exact")
    assert (rate.low, rate.high) == (
        pytest.approx(ci.low, abs=1e-4),
        pytest.approx(ci.high, abs=1e-4),
    )
    for k in (0, 3, 10):  # the ends too
        ci = stats.binomtest(k, 10).proportion_ci(0.95, method="exact")
        assert Rate.of(k, 10).low == pytest.approx(ci.low, abs=1e-4)
        assert Rate.of(k, 10).high == pytest.approx(ci.high, abs=1e-4)
    # the stand-ins differ as scripted: P02 approves far more often by silence than P01
    p01 = fit_person(
        "P01",
        [observe(s.inputs, s.events, s.log) for s in find_sources(STAND_INS).sessions["P01"]],
        [],
        [],
    )
    assert p01.up_on_right.high < person.up_on_right.low or p01.up_on_right.p > 0.6
    assert person.gesture_latency.median > p01.gesture_latency.median


def test_a_lognormal_is_recovered_from_its_draws() -> None:
    rng = np.random.default_rng(3)
    fitted = Latency.fit(list(1.7 * np.exp(rng.normal(0, 0.4, 4000))))
    assert fitted is not None
    assert fitted.median == pytest.approx(1.7, rel=0.03)
    assert fitted.sigma == pytest.approx(0.4, rel=0.05)
    assert fitted.median_low < 1.7 < fitted.median_high
    draws = [fitted.draw(rng) for _ in range(4000)]
    assert float(np.median(draws)) == pytest.approx(1.7, rel=0.05)
    assert Latency.fit([]) is None
    one = Latency.fit([2.5])
    assert one is not None and (one.median, one.sigma) == (2.5, 0.0)
    assert Rate.of(0, 0).p is None and Rate.of(0, 0).value(0.3) == 0.3


def test_the_fitted_file_reads_back_and_a_wrong_one_is_refused(tmp_path: Path) -> None:
    sessions = find_sources(STAND_INS).sessions["P01"]
    observed = [observe(s.inputs, s.events, s.log) for s in sessions]
    names = [{"session": s.name, "sha256": s.sha256} for s in sessions]
    person = fit_person("P01", observed, names, [{"system": "pil"}])
    write_person(person, tmp_path / "P01.json")
    data = json.loads((tmp_path / "P01.json").read_text())
    assert data["format"] == 1 and data["sources"][0]["sha256"]["summary.json"]
    assert read_person(data, "P01.json") == person
    with pytest.raises(FittedPersonError, match="not a fitted person of format 1"):
        read_person({**data, "format": 9}, "P01.json")
    with pytest.raises(FittedPersonError, match="a field is missing"):
        read_person({k: v for k, v in data.items() if k != "up_on_right"}, "P01.json")


def test_a_withdrawn_participant_is_left_out(tmp_path: Path) -> None:
    folder = copy(tmp_path)
    registry = json.loads((folder / "registry.json").read_text())
    registry["participants"][1]["status"] = "withdrawn"
    (folder / "registry.json").write_text(json.dumps(registry))
    sources = find_sources(folder)
    assert list(sources.sessions) == ["P01"] and sources.left_out == {"P02": "withdrawn (registry)"}


def refused(capsys: pytest.CaptureFixture[str], *argv: str) -> str:
    assert main(["people", *argv]) == 2
    return capsys.readouterr().err


def test_sessions_without_consent_are_refused(tmp_path: Path, capsys) -> None:
    folder = copy(tmp_path)
    log = [
        line
        for line in (folder / "log.jsonl").read_text().splitlines()
        if not ('"P02"' in line and '"consent"' in line)
    ]
    (folder / "log.jsonl").write_text("\n".join(log) + "\n")
    out = tmp_path / "out"
    err = refused(capsys, "--from-sessions", str(folder), "--out", str(out))
    assert "2 session(s) without a recorded consent" in err and "P02" in err and "P01" not in err
    plain = tmp_path / "plain" / "P09"  # a plain robin-pil live folder: no study, no consent
    shutil.copytree(STAND_INS / "sessions" / "P01" / "block1-pil", plain / "s1")
    err = refused(capsys, "--from-sessions", str(tmp_path / "plain"), "--out", str(out))
    assert "P09/s1 (in no study folder)" in err
    assert not out.exists()  # refused before anything is written


def test_bad_input_is_one_message_and_exit_2(tmp_path: Path, capsys) -> None:
    out = str(tmp_path / "out")
    (tmp_path / "empty").mkdir()
    assert "no live session" in refused(capsys, "--from-sessions", str(tmp_path / "empty"))
    assert "not a folder" in refused(capsys, "--from-sessions", str(tmp_path / "none"))
    folder = copy(tmp_path)
    err = refused(capsys, "--from-sessions", str(folder), "--sessions-per-person", "0")
    assert "--sessions-per-person must be 1 to 1000, got 0" in err
    err = refused(capsys, "--from-sessions", str(folder), "--appearance", "--out", out)
    assert "--appearance with --from-sessions" in err
    summary = folder / "sessions" / "P02" / "block2-pil" / "summary.json"
    changed = {**json.loads(summary.read_text()), "scenario": "nowhere"}
    summary.write_text(json.dumps(changed))
    err = refused(capsys, "--from-sessions", str(folder), "--out", out)
    assert "block2-pil: its setting cannot be simulated: nowhere: cannot read the scenario" in err
    summary.write_text('{"live": {"participant": "P02"')
    assert "summary.json: not JSON (" in refused(capsys, "--from-sessions", str(folder))
    summary.write_text(json.dumps({"live": {"participant": "P02"}}))
    inputs = summary.parent / "inputs.jsonl"
    inputs.unlink()
    os.mkfifo(inputs)  # would hang a plain open(); refused at once
    assert "inputs.jsonl: cannot read a session file: not a regular file" in refused(
        capsys, "--from-sessions", str(folder), "--out", out
    )
    assert not Path(out).exists()


def test_the_webcams_hand_examples_go_into_the_fitted_file() -> None:
    """Real landmarks (the tracker's readings of tests/data/hands' footage), read by the live
    session's hand reader as a webcam session logs them: the confident ones are kept per
    label, as sent, and the fitted person carries them."""
    from hand_data import footage, message

    from robin_sim.live.hands.landmarks import check_hand
    from robin_sim.live.hands.reader import HandReader

    data, reader, rows = footage(), HandReader(640, 480), []
    for i in range(len(data["label"])):
        points = data["landmarks"][i]
        raw = message(None if np.isnan(points).any() else points, str(data["handedness"][i]))
        raw["aspect"] = float(data["aspect"][i])
        reading = reader.read(check_hand(raw), 0.1 * i).as_dict()
        rows.append({"raw": raw, "reading": reading, "accepted": True, "truth": data["label"][i]})
    seen = observe(rows, [], [])
    assert seen.hand_examples, "no confident reading in the footage"
    truth = {
        json.dumps(r["raw"]["landmarks"]): str(r["truth"]) for r in rows if r["raw"]["landmarks"]
    }
    agree = total = 0
    for label, examples in seen.hand_examples.items():
        assert 0 < len(examples) <= 12
        for marks in examples:
            assert np.array(marks).shape == (21, 3)
            sent = next(k for k in truth if np.allclose(json.loads(k), marks, atol=1e-4))
            agree += truth[sent] == label
            total += 1
    assert agree / total > 0.7  # the reader's labels are mostly the footage's
    person = fit_person("W", [seen, *observe_sessions("P01")], [], [])
    assert person.hand_examples == seen.hand_examples


def observe_sessions(who: str) -> list:
    return [observe(s.inputs, s.events, s.log) for s in find_sources(STAND_INS).sessions[who]]


def test_the_docs_tables_are_the_results_files() -> None:
    """docs/people.md's tables are what docs/people_tables.py makes of the committed results."""
    import importlib.util

    root = Path(__file__).resolve().parents[1]
    spec = importlib.util.spec_from_file_location("people_tables", root / "docs/people_tables.py")
    assert spec is not None and spec.loader is not None
    tables = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(tables)
    page = (root / "docs" / "people.md").read_text()
    for name, table in tables.tables(root / "bench" / "results" / "people_fitted").items():
        assert tables.section(page, name) == table, name


def test_a_session_not_in_the_registry_is_refused_and_a_sessions_folder_is_enough(
    tmp_path: Path, capsys
) -> None:
    folder = copy(tmp_path)
    sources = find_sources(folder / "sessions")  # DIR inside the study: its records still count
    assert sorted(sources.sessions) == ["P01", "P02"]
    shutil.copytree(folder / "sessions/P01/block1-pil", folder / "sessions/P01/stray")
    err = refused(capsys, "--from-sessions", str(folder), "--out", str(tmp_path / "out"))
    assert "sessions/P01/stray (not among P01's sessions in the study's registry)" in err


def test_the_players_thumbs_follow_the_fitted_shares() -> None:
    """The simulated person's verdicts on 1000 actions of each kind against its shares
    (binomial tests), and its latencies against the fitted lognormal's median."""
    down, up = Latency(1.0, 0.3, 10, 0.9, 1.1), Latency(2.0, 0.3, 10, 1.8, 2.2)
    person = FittedPerson(
        participant="X",
        gesture_latency=down,
        down_latency=down,
        up_latency=up,
        down_on_wrong_move=Rate(9, 10, 0.9, 0.5, 1.0),
        down_on_wrong_fingers=Rate(6, 10, 0.6, 0.3, 0.9),
        down_on_right=Rate(1, 10, 0.1, 0.0, 0.4),
        up_on_right=Rate(5, 10, 0.5, 0.2, 0.8),
        late_thumbs=0,
    )
    rng, n = np.random.default_rng(1), 1000
    cases = {  # (action, meant) -> (P(thumb down), P(thumb up)), shares of all such actions
        ("location", "object"): (0.9, 0.0),
        ("close", "object"): (0.6, 0.0),
        ("object", "object"): (0.1, 0.5),
    }
    for (action, meant), (p_down, p_up) in cases.items():
        verdicts = [person.verdict(action, meant, rng) for _ in range(n)]
        downs = [v[1] for v in verdicts if v is not None and v[0] is Feedback.NOT_OK]
        ups = [v[1] for v in verdicts if v is not None and v[0] is Feedback.OK]
        assert stats.binomtest(len(downs), n, p_down).pvalue > 0.001, (action, len(downs))
        if p_up:
            assert stats.binomtest(len(ups), n, p_up).pvalue > 0.001, (action, len(ups))
            assert float(np.median(ups)) == pytest.approx(2.0, rel=0.1)
        else:
            assert not ups
        assert float(np.median(downs)) == pytest.approx(1.0, rel=0.1)
    # a share fitted from nothing: the wrong actions' pooled share stands in for it
    unseen = dataclasses.replace(person, down_on_wrong_fingers=Rate.of(0, 0))
    downs = sum(
        (v := unseen.verdict("open", "human", rng)) is not None and v[0] is Feedback.NOT_OK
        for _ in range(n)
    )
    assert stats.binomtest(downs, n, 0.9).pvalue > 0.001
