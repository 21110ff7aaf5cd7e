"""The proactive robot in a physical episode and on the command line (MuJoCo for real)."""

from __future__ import annotations

from pathlib import Path

import pytest

from pil.task.assemble import assemble
from pil.task.runner import steps
from pil.task.spec import parse_run_spec
from pil.task.systems import SYSTEM_SPECS
from pil.task.world import SymbolicWorld
from robin_sim.cli.main import main
from robin_sim.episode.log import read_step_log

DECISION_KEYS = (
    "t",
    "gesture_count",
    "true_gesture",
    "state",
    "action",
    "feedback",
    "proactive",
    "delivered",
    "legs_delivered",
)


@pytest.mark.slow
def test_a_proactive_episode_runs_to_the_end_and_acts_before_gestures(tmp_path: Path) -> None:
    """Seed 1, one table, no video: the anticipations happen physically, as in the study."""
    from robin_sim.episode.run import EpisodeConfig, run_episode

    config = EpisodeConfig(
        tables=1,
        seed=1,
        system="proactive",
        out=tmp_path,
        video=False,
        verify=False,
        progress=False,
    )
    summary = run_episode(config)
    assert summary["status"] == "finished" and summary["system"] == "proactive"
    assert summary["legs_delivered"] == 4 and summary["legs_to_person"] >= 1
    assert summary["person_contacts"] == 0 and summary["physical_failures"] == 0
    assert summary["timeouts"] == 0 and summary["drops"] == 0
    assert summary["anticipated_actions"] >= summary["anticipated_ok"] >= 1
    log = read_step_log(tmp_path / "episode.jsonl")
    anticipated = [e for e in log if e["proactive"]]
    assert len(anticipated) == summary["anticipated_actions"]
    for entry in anticipated:
        earlier = [e for e in log if e["t"] < entry["t"]]
        assert earlier and entry["gesture_count"] == earlier[-1]["gesture_count"]  # no gesture
        if entry["feedback"] == "not ok":
            assert entry["interrupted"]
    parts = assemble(parse_run_spec(system="proactive", rate=1.0, seed=1, params={"tables": 1}))
    assert summary["gestures"] == len(parts.person.script) - summary["anticipated_ok"]
    symbolic = [
        r.to_dict()
        for r in steps(
            parts.learner, parts.person, parts.detector, SymbolicWorld(), **parts.options
        )
    ]
    assert [{k: e[k] for k in DECISION_KEYS} for e in log] == [
        {k: e[k] for k in DECISION_KEYS} for e in symbolic
    ]


def test_the_episode_help_lists_every_system(capsys: pytest.CaptureFixture) -> None:
    with pytest.raises(SystemExit):
        main(["episode", "--help"])
    text = " ".join(capsys.readouterr().out.split())
    assert all(name in text for name in SYSTEM_SPECS) and "proactive" in text


def test_study_command_compares_proactive_with_pil(tmp_path: Path) -> None:
    out = tmp_path / "study"
    code = main(
        [
            "study",
            "--systems",
            "pil,proactive",
            "--reps",
            "3",
            "--rates",
            "0.6,1.0",
            "--out",
            str(out),
            "--no-progress",
        ]
    )
    assert code == 0
    text = (out / "summary.md").read_text()
    assert "## Proactive vs reactive PIL" in text and "gestures saved" in text
    assert (out / "proactive.png").stat().st_size > 5000


def test_the_overlay_shows_an_anticipation_as_no_gesture() -> None:
    from pil.task.records import StepRecord
    from pil.types import Action, Gesture, Hand, State
    from robin_sim.episode.view import EpisodeView
    from robin_sim.render.overlay import overlay_lines

    record = StepRecord(
        t=7,
        gesture_count=6,
        table=0,
        handover=1,
        handover_type="C",
        step=2,
        true_gesture=Gesture.GRASP,
        detected_gesture=None,
        intended_action=Action.CLOSE,
        legs_delivered=1,
        state=State(Gesture.GRASP, Action.OBJECT, Hand.FREE),
        action=Action.CLOSE,
        exploited=True,
        proactive=True,
    )
    view = EpisodeView()
    view.decided(record)
    lines = overlay_lines(view.info)
    assert "person:   -   feedback: -" in lines and "detected: -" in lines
    assert "action:   close (anticipating grasp)" in lines
    view.decided(record._replace(proactive=False))
    assert "person:   grasp   feedback: -" in overlay_lines(view.info)
