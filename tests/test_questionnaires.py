"""Questionnaires after protocol blocks: definitions, checks, saving and the report's summary."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest
from scipy.stats import ttest_rel, wilcoxon

from pil.experiments.questionnaire_report import (
    answers_markdown,
    load_answers,
    paired_tests,
    summarize_answers,
    write_answers_report,
)
from pil.experiments.sessions_load import SessionsError
from robin_sim.live.config import LiveConfig
from robin_sim.live.inputs import LiveInputError
from robin_sim.live.protocol import load_protocol
from robin_sim.live.questioning import QUESTIONNAIRES_NAME, Questioning
from robin_sim.live.questionnaires import QuestionnaireError, load_questionnaires

PROTOCOL = """\
name: q
scenario: one_handover
conditions: [pil, proactive]
blocks:
  - types: [A]
questionnaires:
"""


def test_presets_nasa_tlx_raw_and_godspeed_scales() -> None:
    tlx, godspeed = load_questionnaires(["nasa-tlx", "godspeed"], "here")
    assert [i.id for i in tlx.items] == [
        "mental",
        "physical",
        "temporal",
        "performance",
        "effort",
        "frustration",
    ]
    assert {(i.minimum, i.maximum, i.step) for i in tlx.items} == {(0, 100, 5)}
    answers = tlx.check_answers(
        dict(zip([i.id for i in tlx.items], [50, 60, 70, 80, 40, 75], strict=True))
    )
    assert tlx.scores(answers) == {"raw_tlx": pytest.approx(62.5)}
    scales = [i.scale for i in godspeed.items]
    assert {s: scales.count(s) for s in dict.fromkeys(scales)} == {
        "anthropomorphism": 5,
        "animacy": 6,
        "likeability": 5,
        "perceived_intelligence": 5,
        "perceived_safety": 3,
    }
    assert {(i.minimum, i.maximum) for i in godspeed.items} == {(1, 5)}
    ratings = {
        i.id: (5 if i.scale == "likeability" else 1 + k % 2) for k, i in enumerate(godspeed.items)
    }
    scores = godspeed.scores(godspeed.check_answers(ratings))
    assert scores["likeability"] == 5.0
    assert scores["perceived_safety"] == pytest.approx(5 / 3)  # its items rated 2, 1, 2


@pytest.mark.parametrize(
    ("answers", "expected"),
    [
        ({"mental": 50}, "please answer every question"),
        (
            {
                **dict.fromkeys(
                    ["mental", "physical", "temporal", "performance", "effort", "frustration"], 50
                ),
                "mental": 57,
            },
            "in steps of 5",
        ),
        (
            {
                **dict.fromkeys(
                    ["mental", "physical", "temporal", "performance", "effort", "frustration"], 50
                ),
                "effort": 105,
            },
            "from 0 to 100",
        ),
        (
            {
                **dict.fromkeys(
                    ["mental", "physical", "temporal", "performance", "effort", "frustration"], 50
                ),
                "effort": True,
            },
            "whole number",
        ),
        ({"mood": 3}, "unknown item 'mood'"),
        ([1, 2], "must be an object"),
    ],
)
def test_bad_answers_are_refused_with_the_reason(answers, expected: str) -> None:
    (tlx,) = load_questionnaires(["nasa-tlx"], "here")
    with pytest.raises(QuestionnaireError, match=expected):
        tlx.check_answers(answers)


@pytest.mark.parametrize(
    ("yaml", "expected"),
    [
        ("  - nasa_tlx\n", "unknown preset 'nasa_tlx'; valid choices: nasa-tlx, godspeed"),
        ("  - {name: t, items: [{id: a, text: A}], points: 1}\n", "points: expected a whole"),
        ("  - {name: t, items: [{id: a, text: A}, {id: a, text: B}]}\n", "id 'a' is given twice"),
        ("  - {name: t, items: [{id: a, txt: A}]}\n", "unknown key 'txt'; valid keys: id, text"),
        ("  - {name: godspeed, items: [{id: a, text: A}]}\n", "not a preset's"),
        ("  - nasa-tlx\n  - nasa-tlx\n", "'nasa-tlx' is listed twice"),
        ("  {}\n", "expected a non-empty list"),
    ],
)
def test_protocol_questionnaires_are_checked_at_load(tmp_path: Path, yaml: str, expected) -> None:
    path = tmp_path / "p.yaml"
    path.write_text(PROTOCOL + yaml)
    with pytest.raises(QuestionnaireError, match=expected) as error:
        load_protocol(path)
    assert str(error.value).startswith(f"{path}: questionnaires")


def test_cli_refuses_a_bad_questionnaire_before_serving(tmp_path: Path, capsys) -> None:
    from robin_sim.cli.main import main

    path = tmp_path / "p.yaml"
    path.write_text(PROTOCOL + "  - {name: t, items: [{id: a, text: A}], points: 12}\n")
    out = tmp_path / "out"
    assert (
        main(
            [
                "live",
                "--protocol",
                str(path),
                "--participant",
                "P01",
                "--out",
                str(out),
                "--no-browser",
                "--port",
                "0",
            ]
        )
        == 2
    )
    err = capsys.readouterr().err
    assert "points: expected a whole number from 2 to 11, got 12" in err and not out.exists()


def test_answers_are_saved_one_line_each_and_wrong_messages_refused(tmp_path: Path) -> None:
    path = tmp_path / "p.yaml"
    path.write_text(
        PROTOCOL + "  - nasa-tlx\n  - {name: ease, points: 5, items: "
        "[{id: clear, text: Robin understood me.}]}\n"
    )
    protocol = load_protocol(path)
    config = LiveConfig(participant="P03", system="proactive", block=1, protocol=str(path))
    asking = Questioning(protocol.questionnaires, tmp_path, config)
    assert asking.status()["questionnaire"]["name"] == "nasa-tlx"
    for message, expected in (
        ("[" * 3000, "not a JSON message"),
        ('{"type": "end"}', "answer it"),
        ('{"type": "answers", "questionnaire": "ease"}', "is 'nasa-tlx'"),
        (
            '{"type": "answers", "questionnaire": "nasa-tlx", "answers": {}, "note": "hi"}',
            r"unknown field\(s\) 'note'; an answer takes 'type', 'questionnaire', 'answers'",
        ),
    ):
        with pytest.raises(LiveInputError, match=expected):
            asking.receive(message)
    tlx = dict.fromkeys([i.id for i in protocol.questionnaires[0].items], 30)
    assert not asking.receive(
        json.dumps({"type": "answers", "questionnaire": "nasa-tlx", "answers": tlx})
    )
    assert asking.receive(b'{"type": "answers", "questionnaire": "ease", "answers": {"clear": 4}}')
    lines = [json.loads(x) for x in (tmp_path / QUESTIONNAIRES_NAME).read_text().splitlines()]
    assert [(x["questionnaire"], x["scores"]) for x in lines] == [
        ("nasa-tlx", {"raw_tlx": 30.0}),
        ("ease", {"clear": 4.0, "mean": 4.0}),
    ]
    # each score's scale is saved with it: the report refuses a score off it
    assert [x["ranges"] for x in lines] == [
        {"raw_tlx": [0.0, 100.0]},
        {"clear": [1.0, 5.0], "mean": [1.0, 5.0]},
    ]
    assert {(x["participant"], x["condition"], x["block"]) for x in lines} == {
        ("P03", "proactive", 1)
    }


def _write(folder: Path, participant: str, condition: str, block: int, tlx: float) -> None:
    session = folder / participant / f"block{block + 1}-{condition}"
    session.mkdir(parents=True, exist_ok=True)
    entry = {
        "participant": participant,
        "condition": condition,
        "block": block,
        "questionnaire": "nasa-tlx",
        "scores": {"raw_tlx": tlx},
    }
    with (session / QUESTIONNAIRES_NAME).open("a") as file:
        file.write(json.dumps(entry) + "\n")


def test_report_pairs_participants_who_rated_both_conditions(tmp_path: Path) -> None:
    pil = {"P01": 40.0, "P02": 55.0, "P03": 35.0, "P04": 60.0}
    proactive = {"P01": 30.0, "P02": 50.0, "P03": 20.0, "P05": 90.0}  # P04, P05: one condition
    for p, v in pil.items():
        _write(tmp_path, p, "pil", 0, v)
    for p, v in proactive.items():
        _write(tmp_path, p, "proactive", 1, v)
    _write(tmp_path, "P01", "pil", 2, 50.0)  # a second pil block: P01's pil value is 45
    rows = load_answers(tmp_path)
    assert len(rows) == 9
    (test,) = paired_tests(rows)
    xs, ys = [45.0, 55.0, 35.0], [30.0, 50.0, 20.0]
    assert test["n"] == 3
    assert test["p_t"] == pytest.approx(ttest_rel(xs, ys).pvalue)
    assert test["p_w"] == pytest.approx(wilcoxon(xs, ys).pvalue)
    assert test["mean_diff"] == pytest.approx(35 / 3)  # differences 15, 5, 15
    ci = ttest_rel(xs, ys).confidence_interval(0.95)
    assert (test["ci_low"], test["ci_high"]) == pytest.approx((ci.low, ci.high))
    assert test["p_t_holm"] == pytest.approx(test["p_t"])  # a family of one test
    by = {s["condition"]: s for s in summarize_answers(rows)}
    assert by["pil"]["participants"] == 4 and by["pil"]["mean"] == pytest.approx(48.75)
    text = answers_markdown(rows)
    assert "| nasa-tlx | raw_tlx | pil | 4 | 48.75 ± " in text
    written = write_answers_report(tmp_path, tmp_path / "report")
    assert [p.name for p in written] == ["questionnaires.md", "questionnaires.csv"]
    _write(tmp_path, "P09", "pil", 0, 10.0)
    only = [r for r in load_answers(tmp_path) if r["participant"] == "P09"]
    assert "| nasa-tlx | raw_tlx | pil | 1 | 10.00 |" in answers_markdown(only)  # n = 1: no sd
    (tmp_path / "P09" / "block1-pil" / QUESTIONNAIRES_NAME).write_text("{not json\n")
    with pytest.raises(SessionsError, match=r"questionnaires.jsonl:1: not a questionnaire"):
        load_answers(tmp_path)


def test_the_shipped_protocol_asks_nasa_tlx_and_godspeed() -> None:
    protocol = load_protocol("reactive_vs_proactive")
    assert [q.name for q in protocol.questionnaires] == ["nasa-tlx", "godspeed"]


def test_every_preset_score_lies_within_its_saved_range() -> None:
    from robin_sim.live.questionnaire_presets import godspeed, nasa_tlx

    rng = np.random.default_rng(0)
    for questionnaire in (nasa_tlx(), nasa_tlx(weighted=True), godspeed()):
        ranges = questionnaire.score_ranges()
        for _ in range(20):
            answers: dict[str, object] = {}
            for item in questionnaire.items:
                if item.kind == "choice":
                    answers[item.id] = str(rng.choice(item.choices))
                else:
                    steps = (item.maximum - item.minimum) // item.step
                    answers[item.id] = item.minimum + item.step * int(rng.integers(steps + 1))
            scores = questionnaire.scores(questionnaire.check_answers(answers))
            assert set(scores) <= set(ranges), questionnaire.name
            for name, value in scores.items():
                assert ranges[name][0] <= value <= ranges[name][1], (name, value)
