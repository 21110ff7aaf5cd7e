"""A small study end to end in headless chromium, then everything a lab does with it.

Four participants come to a between-subjects study (learner: PIL from scratch; trained: the
robot pre-trained, c2), each through the page: consent, demographics, a practice block (ended
by its time cap), two blocks of their condition with a questionnaire after each (a Likert item,
a reverse-scored one, an attention check, a slider), and the debrief. P02 declines consent:
nothing of theirs is kept but the refusal, and P03 takes the free place in the assignment. The
study folder then holds the registry, the log, the three CSV files and an archive whose manifest
checks (and a changed file fails the check); the report runs with the mixed model; an id is
never given twice; a withdrawn participant is marked and left out; and the replay page of P01's
first block shows its events and jumps to step 5.
"""

from __future__ import annotations

import csv
import json
import shutil
import zipfile
from pathlib import Path

import pytest
from study_driver import fast_base, run_participant

from robin_sim.cli.main import main
from robin_sim.lab.registry import RegistryError
from robin_sim.lab.run import prepare

pytestmark = pytest.mark.slow
SPEED = 6.0
# seed 1: P01 goes to learner, P03 (after P02's refusal) and P04 to trained
STUDY = """\
name: pilot
protocol: protocol.yaml
design: between
groups:
  - {name: learner, conditions: [pil]}
  - {name: trained, conditions: [c2]}
participants: 3
seed: 1
consent: {text: You teach a simulated robot. You may stop at any time., agree: I agree}
demographics:
  items:
    - {id: age, text: Your age, kind: number, min: 18, max: 99}
    - {id: hand, text: Your dominant hand, kind: choice, choices: [left, right]}
    - {id: remarks, text: Anything else, kind: text, optional: true}
practice: {types: [A], block_seconds: 3}
limits: {inactivity_seconds: 600}
debrief: {text: Thank you. One robot had learnt the task before you came.}
"""
PROTOCOL = """\
name: pilot
scenario: one_handover
conditions: [pil, c2]
order: fixed
blocks:
  - {types: [A], repeat: 2}
instructions: "Block {block} of {blocks}: work with {label}."
questionnaires:
  - name: ease
    points: 5
    items:
      - {id: clear, text: Robin understood me, subscale: fluency}
      - {id: slow, text: I waited for Robin, reverse: true, subscale: fluency}
      - {id: check, text: Please choose 4 here, attention: 4}
      - {id: liking, text: How much did you like working with Robin, kind: vas}
"""


def rows(path: Path) -> list[dict[str, str]]:
    with path.open(newline="") as file:
        return list(csv.DictReader(file))


def test_a_small_study_from_consent_to_report(browser, tmp_path: Path, capsys) -> None:
    folder = tmp_path / "pilot"
    folder.mkdir()
    (folder / "study.yaml").write_text(STUDY)
    (folder / "protocol.yaml").write_text(PROTOCOL)
    runs = {}
    for k, (video, decline) in enumerate(
        [(True, False), (False, True), (False, False), (False, False)]
    ):
        run, outcome = run_participant(
            browser, folder, fast_base(SPEED, video), decline=decline, age=30 + k
        )
        runs[run.participant] = (run.group, outcome)
    assert runs == {
        "P01": ("learner", "finished"),
        "P02": ("trained", "declined"),
        "P03": ("trained", "finished"),
        "P04": ("trained", "finished"),
    }
    check_registry_and_log(folder)
    check_ids_are_never_reused(folder, capsys)
    check_report(folder, capsys)
    check_exports_and_archive(folder, capsys)
    check_withdrawal(folder, tmp_path, capsys)
    check_replay(folder, browser)


def check_registry_and_log(folder: Path) -> None:
    registry = json.loads((folder / "registry.json").read_text())["participants"]
    assert [(p["id"], p["status"]) for p in registry] == [
        ("P01", "completed"),
        ("P02", "declined"),
        ("P03", "completed"),
        ("P04", "completed"),
    ]
    assert registry[0]["sessions"] == [
        "sessions/P01/practice",
        "sessions/P01/block1-pil",
        "sessions/P01/block2-pil",
    ]
    assert not (folder / "sessions" / "P02").exists()  # the refusal only: registry and log
    log = [json.loads(line) for line in (folder / "log.jsonl").read_text().splitlines()]
    p01 = [e["event"] for e in log if e["participant"] == "P01"]
    assert p01 == [
        "assigned", "consent", "demographics",
        "block_started", "block_ended",  # practice, capped by its time
        "block_started", "block_ended", "block",  # block 1 and its questionnaire
        "block_started", "block_ended", "block",
        "debrief", "run_over",
    ]  # fmt: skip
    practice = next(e for e in log if e["event"] == "block_ended" and e["practice"])
    assert practice["status"] == "capped" and practice["limits"]["reached"] == "time"
    assert [e["event"] for e in log if e["participant"] == "P02"] == [
        "assigned",
        "consent",
        "run_over",
    ]
    summary = json.loads((folder / "sessions/P01/practice/summary.json").read_text())
    assert summary["status"] == "capped" and summary["live"]["practice"] is True
    assert summary["live"]["protocol"] == "protocol.yaml"  # relative to the study folder
    events = (folder / "sessions/P01/practice/events.jsonl").read_text()
    assert '"event": "limit"' in events


def check_ids_are_never_reused(folder: Path, capsys) -> None:
    with pytest.raises(
        RegistryError, match="never reused: leave out --participant for the next one \\(P05\\)"
    ):
        prepare(folder, "P03", fast_base(SPEED, False))
    with pytest.raises(RegistryError, match="'P02' was given already as 'P02' \\(declined"):
        prepare(folder, "P02", fast_base(SPEED, False))
    capsys.readouterr()
    command = ["live", "--study", str(folder), "--participant", "P01", "--no-browser"]
    assert main([*command, "--port", "0"]) == 2
    assert "an id is never reused" in capsys.readouterr().err
    assert main(["live", "--study", str(folder), "--seed", "3", "--no-browser"]) == 2
    assert "--seed with --study" in capsys.readouterr().err
    assert main(["study-status", str(folder)]) == 0
    shown = capsys.readouterr().out
    assert "| P02 | trained | c2 | declined | 0 / 3 |" in shown
    assert "planned 3: 3 completed, 0 left" in shown
    assert "Next: P05 would go to group learner (pil)" in shown


def check_report(folder: Path, capsys) -> None:
    assert main(["report", str(folder)]) == 0
    capsys.readouterr()
    text = (folder / "report" / "study.md").read_text()
    assert "Design: **between**. 3 participants analysed" in text and "P02 (declined)" in text
    assert "| blocks | sim_time_s | `value ~ C(condition) + position` | 6 / 3 |" in text
    models = rows(folder / "report" / "study_models.csv")
    terms = {(m["outcome"], m["term"]) for m in models}
    assert ("sim_time_s", "C(condition)[T.c2]") in terms and ("sim_time_s", "position") in terms
    tests = rows(folder / "report" / "study_tests.csv")
    welch = next(t for t in tests if t["outcome"] == "actions")
    assert welch["design"] == "between" and welch["test"] == "welch t" and welch["n"] == "1/2"
    order = rows(folder / "report" / "study_order.csv")
    assert {(o["condition"], o["position"]) for o in order if o["outcome"] == "actions"} >= {
        ("all", "1"),
        ("all", "2"),
    }
    sessions = rows(folder / "report" / "sessions.csv")
    assert {s["participant"] for s in sessions} == {"P01", "P03", "P04"}
    practice = [s for s in sessions if s["practice"] == "True"]
    assert len(practice) == 3 and all(s["counted"] == "False" for s in practice)
    assert all(s["summary"].startswith("sessions/") for s in sessions)  # relative paths


def check_exports_and_archive(folder: Path, capsys) -> None:
    capsys.readouterr()
    assert main(["study-export", str(folder)]) == 0
    printed = capsys.readouterr().out.split()
    archive = Path(printed[-1])
    trials = rows(folder / "exports" / "trials.csv")
    people = json.loads((folder / "registry.json").read_text())["participants"]
    sessions = [s for p in people if p["status"] == "completed" for s in p["sessions"]]
    steps = sum(len((folder / s / "log.jsonl").read_text().splitlines()) for s in sessions)
    assert len(trials) == steps > 4 * 6  # every step of the six blocks (c2: 4 each)
    first = trials[0]
    assert (first["participant"], first["group"], first["condition"]) == ("P01", "learner", "pil")
    assert all(t["session"].startswith("sessions/") and t["seed"] for t in trials)
    assert {t["action"] for t in trials if t["condition"] == "c2"} == {
        "object",
        "close",
        "human",
        "open",
    }
    wide = {r["participant"]: r for r in rows(folder / "exports" / "questionnaires_wide.csv")}
    assert set(wide) == {"P01", "P03", "P04"}
    assert wide["P01"]["demographics_age"] == "30" and wide["P01"]["demographics_hand"] == "right"
    # slow is reverse-scored: the answer 1 (of 5) scores 5
    assert wide["P01"]["pil_1_ease_slow"] == "1" and wide["P01"]["pil_1_ease_score_slow"] == "5.0"
    assert wide["P03"]["c2_2_ease_check_check"] == "1"  # the attention check passed
    assert wide["P01"]["pil_2_ease_liking"] == "52"  # the slider moved twice with the keys
    long = rows(folder / "exports" / "long.csv")
    kinds = {(r["source"], r["kind"]) for r in long}
    assert kinds == {
        ("block", "measure"),
        ("questionnaire", "answer"),
        ("questionnaire", "score"),
        ("questionnaire", "attention"),
        ("demographics", "answer"),
    }
    assert main(["study-verify", str(archive)]) == 0
    assert "files match the manifest" in capsys.readouterr().out
    with zipfile.ZipFile(archive) as zipped:
        manifest = json.loads(zipped.read("manifest.json"))
        names = zipped.namelist()
    assert {"registry.json", "log.jsonl", "study.yaml", "exports/trials.csv"} <= set(names)
    assert manifest["robin_pil"]["version"] and set(manifest["models"]) == {"scene", "robot"}
    assert (
        manifest["protocol"]["name"] == "protocol.yaml" and len(manifest["files"]) == len(names) - 1
    )
    changed = archive.with_name("changed.zip")
    with zipfile.ZipFile(archive) as source, zipfile.ZipFile(changed, "w") as target:
        for name in source.namelist():
            data = source.read(name)
            target.writestr(name, data + b"x" if name == "log.jsonl" else data)
    assert main(["study-verify", str(changed)]) == 2
    assert "log.jsonl: changed" in capsys.readouterr().err


def check_withdrawal(folder: Path, tmp_path: Path, capsys) -> None:
    copy = tmp_path / "withdrawn"
    shutil.copytree(folder, copy)
    assert main(["study-withdraw", str(copy), "P04", "--reason", "asked to leave"]) == 0
    entry = json.loads((copy / "registry.json").read_text())["participants"][3]
    assert (entry["status"], entry["reason"]) == ("withdrawn", "asked to leave")
    assert (
        main(["report", str(copy)]) == 0 and main(["study-export", str(copy), "--no-archive"]) == 0
    )
    capsys.readouterr()
    assert "P04 (withdrawn)" in (copy / "report" / "study.md").read_text()
    assert "P04" not in (copy / "report" / "sessions.csv").read_text()
    assert "P04" not in (copy / "exports" / "trials.csv").read_text()
    assert main(["study-status", str(copy)]) == 0
    assert "Next: P05 would go to group trained (c2)" in capsys.readouterr().out  # place free


def check_replay(folder: Path, browser) -> None:
    import asyncio
    import threading

    from robin_sim.live.server import bind
    from robin_sim.render.state_log import load_states
    from robin_sim.replay.annotations import timeline, with_log_overlay
    from robin_sim.replay.render import ReplayRenderer
    from robin_sim.replay.serve import serve_replay

    session = folder / "sessions/P01/block1-pil"
    recorded = load_states(session / "states.npz")
    marks = timeline(session, recorded)
    kinds = {m["kind"] for m in marks["markers"]}
    assert {"step", "gesture", "thumb", "questionnaire"} <= kinds
    assert len(marks["steps"]) >= 5
    sock = bind("127.0.0.1", 0)
    loop = asyncio.new_event_loop()
    stop = asyncio.Event()
    served = serve_replay(recorded, sock, stop, marks)
    thread = threading.Thread(target=loop.run_until_complete, args=(served,), daemon=True)
    thread.start()
    try:
        page = browser.new_page()
        page.goto(f"http://127.0.0.1:{sock.getsockname()[1]}/")
        page.wait_for_function("() => window.robinReplay && window.robinReplay.shown === 0")
        assert page.locator(".mark").count() == len(marks["markers"])
        assert page.locator("#events tr[data-kind='thumb']").count() >= 2
        page.locator("#step").fill("5")
        page.locator("#step").press("Enter")
        at = next(s["time"] for s in marks["steps"] if s["step"] == 5)
        times = [s.time - recorded.states[0].time for s in recorded.states]
        index = min(range(len(times)), key=lambda i: (abs(times[i] - at), -i))  # the nearest
        page.wait_for_function(f"() => window.robinReplay.shown === {index}")
        assert page.locator("#shown-step").inner_text().startswith("step 5 at")
        page.close()
    finally:
        loop.call_soon_threadsafe(stop.set)
        thread.join(30)
        loop.close()
    overlaid = with_log_overlay(recorded, session)
    with ReplayRenderer(recorded) as plain, ReplayRenderer(overlaid) as burnt:
        a, b = plain.render(index), burnt.render(index)
    from robin_sim.render.overlay import policy_panel_box

    rows = a.shape[0]  # the overlay's text panels: along the bottom, left of the P(a|s) panel
    panel = (slice(round(0.8 * rows), rows), slice(0, policy_panel_box(a.shape)[0]))
    assert abs(a[panel].astype(int) - b[panel].astype(int)).mean() > 5  # text burnt in
