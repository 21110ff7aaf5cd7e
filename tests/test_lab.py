"""Study folders (robin_sim.lab): the study file's checks, the registry, the balanced
assignment, and the study's analysis against scipy and statsmodels."""

from __future__ import annotations

import json
import re
import threading
from collections import Counter
from pathlib import Path

import pytest

from robin_sim.lab.assignment import assign, cells
from robin_sim.lab.registry import Registry, RegistryError
from robin_sim.lab.run import prepare
from robin_sim.lab.study_file import StudyError, load_study
from robin_sim.lab.template import init_study
from robin_sim.live.config import LiveConfig

PROTOCOL = """\
name: p
scenario: one_handover
conditions: [pil, proactive, c2]
order: {order}
blocks:
  - types: [A]
"""
BASE = "name: s\nprotocol: protocol.yaml\n"


def study_in(tmp_path: Path, text: str, order: str = "counterbalanced") -> Path:
    folder = tmp_path / "study"
    folder.mkdir(exist_ok=True)
    (folder / "protocol.yaml").write_text(PROTOCOL.format(order=order))
    (folder / "study.yaml").write_text(BASE + text)
    return folder


@pytest.mark.parametrize(
    ("text", "expected"),
    [
        ("designs: within\n", "unknown key 'designs'; valid choices: name, description, protocol"),
        (
            "design: crossover\n",
            "unknown design 'crossover'; valid choices: within, between, mixed",
        ),
        ("groups: [{name: a, conditions: [pil]}]\n", "a within design has no groups"),
        ("design: between\ngroups: [{name: a, conditions: [pil]}]\n", "at least two groups"),
        (
            "design: between\ngroups: [{name: a, conditions: [pil]}, "
            "{name: b, conditions: [c9]}]\n",
            "'c9' is not a condition of the protocol; valid choices: pil, proactive, c2",
        ),
        (
            "design: between\ngroups: [{name: a, conditions: [pil, c2]}, {name: b, conditions: "
            "[proactive]}]\n",
            "each group does one condition; use design: mixed",
        ),
        (
            "design: mixed\ngroups: [{name: a, conditions: [pil]}, {name: b, conditions: [c2]}]\n",
            "a mixed design needs a group with several conditions",
        ),
        ("participants: 0\n", "participants: expected a whole number from 1 to 10000, got 0"),
        ("id_prefix: '7'\n", "id_prefix: expected 1-10 letters"),
        ("practice: {types: [Z]}\n", "practice.types: .* valid choices: A, B"),
        ("limits: {block_seconds: 0.5}\n", "limits.block_seconds must lie in \\[1, 36000\\]"),
        ("limits: {idle: 3}\n", "limits: unknown key 'idle'"),
        ("consent: {agree: yes}\n", "consent: expected a text, or a mapping with 'text'"),
        ("demographics: {items: [{id: age, text: Age, kind: year}]}\n", "unknown kind 'year'"),
        (
            "demographics: {items: [{id: age, text: Age, kind: number, points: 5}]}\n",
            "unknown key 'points'",
        ),
        (
            "demographics: {items: [{id: age, text: Age, kind: number, low: young}]}\n",
            "low: not for a number item; a number item takes min, max, optional",
        ),
        ("debrief: {text: ''}\n", "debrief.text: expected a text of 1 to 8000"),
        ("seed: -1\n", "seed"),
    ],
)
def test_every_mistake_in_a_study_file_is_one_clear_message(tmp_path, text, expected) -> None:
    folder = study_in(tmp_path, text)
    with pytest.raises(Exception, match=expected) as error:
        load_study(folder)
    assert "study.yaml" in str(error.value) or "protocol" in str(error.value)


def test_the_command_line_refuses_a_bad_study_with_exit_2(tmp_path, capsys) -> None:
    from robin_sim.cli.main import main

    folder = study_in(tmp_path, "design: crossover\n")
    assert main(["study-status", str(folder)]) == 2
    assert "unknown design 'crossover'" in capsys.readouterr().err
    assert main(["live", "--study", str(folder), "--no-browser", "--port", "0"]) == 2
    assert not (folder / "registry.json").exists()  # refused before anything was registered
    assert main(["study-status", str(tmp_path / "nowhere")]) == 2
    assert "not a study folder (no study.yaml); make one with robin-pil study-init" in (
        capsys.readouterr().err
    )


@pytest.mark.parametrize("design", ["within", "between", "mixed"])
def test_study_init_writes_a_study_that_loads(tmp_path, design) -> None:
    study = init_study(tmp_path / design, None, design)
    assert study.design == design and study.practice is not None and study.screens.consent
    with pytest.raises(StudyError, match="exists already"):
        init_study(tmp_path / design, None, design)


def _fill(study, statuses):
    entries = []
    for status in statuses:
        group, order = assign(study, entries)
        entries.append({"id": f"P{len(entries) + 1}", "group": group, "order": list(order),
                        "status": status})  # fmt: skip
    return entries


def test_within_assignment_balances_the_latin_square(tmp_path) -> None:
    study = load_study(study_in(tmp_path, "seed: 3\n", order="latin-square"))
    assert len(cells(study)) == 6  # three conditions: a Williams square of 6 rows
    entries = _fill(study, ["completed"] * 12)
    counts = Counter(tuple(e["order"]) for e in entries)
    assert set(counts.values()) == {2} and len(counts) == 6
    firsts = [tuple(e["order"]) for e in entries[:6]]
    assert len(set(firsts)) == 6  # balanced in every round, not only in the end
    again = _fill(
        load_study(study_in(tmp_path, "seed: 3\n", order="latin-square")), ["completed"] * 12
    )
    assert again == entries  # the same seed and registry: the same assignment
    other = _fill(
        load_study(study_in(tmp_path, "seed: 4\n", order="latin-square")), ["completed"] * 6
    )
    assert [e["order"] for e in other] != [e["order"] for e in entries[:6]]


def test_between_and_mixed_assignment_balance_groups_then_orders(tmp_path) -> None:
    text = "design: {d}\ngroups: [{{name: a, conditions: {a}}}, {{name: b, conditions: [c2]}}]\n"
    between = load_study(study_in(tmp_path, text.format(d="between", a="[pil]")))
    entries = _fill(between, ["completed", "declined", "withdrawn", "completed", "completed"])
    filling = Counter(e["group"] for e in entries if e["status"] == "completed")
    assert filling == {"a": 2, "b": 1} or filling == {"a": 1, "b": 2}
    assert entries[1]["group"] == entries[2]["group"]  # a refused place is given again
    mixed = load_study(study_in(tmp_path, text.format(d="mixed", a="[pil, proactive]")))
    entries = _fill(mixed, ["completed"] * 8)
    assert Counter(e["group"] for e in entries) == {"a": 4, "b": 4}
    orders = Counter(tuple(e["order"]) for e in entries if e["group"] == "a")
    assert orders == {("pil", "proactive"): 2, ("proactive", "pil"): 2}


def test_ids_are_never_reused_and_the_lock_gives_each_one_once(tmp_path) -> None:
    folder = study_in(tmp_path, "id_prefix: S\n")
    base = LiveConfig(video=False)
    ids = []

    def register() -> None:
        ids.append(prepare(folder, None, base).participant)

    threads = [threading.Thread(target=register) for _ in range(6)]
    for thread in threads:
        thread.start()
    for thread in threads:
        thread.join()
    assert sorted(ids) == ["S01", "S02", "S03", "S04", "S05", "S06"]
    with pytest.raises(RegistryError, match="'S04' was given already as 'S04' \\(assigned"):
        prepare(folder, "S04", base)
    for written in ("s04", "S4", "S004", "s0004"):  # one participant number, one id
        with pytest.raises(RegistryError, match="was given already as 'S04'"):
            prepare(folder, written, base)
    run = prepare(folder, "lab-7", base)
    assert (
        run.configs[0].out_root == folder / "sessions"
        and run.configs[0].protocol == "protocol.yaml"
    )
    run.release("the port was taken")
    assert "lab-7" not in (folder / "registry.json").read_text()
    (folder / "sessions" / "S07").mkdir(parents=True)
    with pytest.raises(RegistryError, match="S07 exists but 'S07' is not in the registry"):
        prepare(folder, None, base)
    log = [json.loads(x) for x in (folder / "log.jsonl").read_text().splitlines()]
    assert [e["event"] for e in log].count("assigned") == 7 and log[-1]["event"] == "released"
    (folder / "registry.json").write_text("{not json")
    with pytest.raises(RegistryError, match="not a readable registry"):
        Registry(folder, "s").entries()


def test_a_participants_sessions_are_planned_with_their_seeds_and_limits(tmp_path) -> None:
    from pil.task.seeds import block_seed

    text = "seed: 9\npractice: {types: [B], block_seconds: 30}\nlimits: {block_actions: 40}\n"
    run = prepare(study_in(tmp_path, text), "P01", LiveConfig(video=False))
    practice, *blocks = run.configs
    assert (
        practice.practice and practice.handover_types == ("B",) and practice.session == "practice"
    )
    assert (practice.block_seconds, practice.block_actions) == (30.0, None)
    assert practice.system == run.order[0]
    assert [b.session for b in blocks] == [f"block{k + 1}-{s}" for k, s in enumerate(run.order)]
    assert [b.seed for b in blocks] == [block_seed(9, "P01", k) for k in range(3)]
    assert {b.block_actions for b in blocks} == {40} and not any(b.practice for b in blocks)


def test_a_participant_is_withdrawn_once_and_keeps_the_first_reason(
    tmp_path, capsys: pytest.CaptureFixture[str]
) -> None:
    """Issue 39: a second study-withdraw replaced the reason with 'not given' and a new time;
    the refusal of a withdrawn id showed its end time, not its withdrawal time."""
    from robin_sim.cli.main import main
    from robin_sim.lab.registry import Registry

    folder = study_in(tmp_path, "id_prefix: S\n")
    base = LiveConfig(video=False)
    prepare(folder, None, base)
    ended = "2020-01-01T00:00:00+00:00"  # a session that ended long before the withdrawal
    Registry(folder, "x").update("S01", status="completed", ended_utc=ended)
    assert main(["study-withdraw", str(folder), "s1", "--reason", "felt unwell"]) == 0
    entry = Registry(folder, "x").entry("S01")
    assert (entry["status"], entry["reason"]) == ("withdrawn", "felt unwell")
    assert main(["study-withdraw", str(folder), "S01"]) == 2
    assert "withdrawn already" in capsys.readouterr().err
    again = Registry(folder, "x").entry("S01")
    assert again == entry  # the first reason and time stand
    since = re.escape(f"withdrawn since {entry['withdrawn_utc']}")
    with pytest.raises(RegistryError, match=since):
        prepare(folder, "S01", base)
    assert entry["withdrawn_utc"] != ended
