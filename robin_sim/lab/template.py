"""``robin-pil study-init``'s starting point: a study file and a small protocol to edit.

:func:`init_study` writes ``study.yaml`` (commented: every field a lab sets) and, unless a
protocol is named, ``protocol.yaml`` (two conditions, one short block each, counterbalanced,
NASA-TLX and a custom questionnaire after each block) into a new folder, then loads the study
to check it. Nothing is overwritten.
"""

from __future__ import annotations

from pathlib import Path

from pil.atomic import write_text_atomic
from pil.errors import RobinPilError, quote
from pil.regular_files import UnreadableFileError, read_kind_text
from robin_sim.lab.study_file import DESIGNS, STUDY_NAME, Study, StudyError, load_study
from robin_sim.live.protocol import find_protocol, load_protocol

PROTOCOL_NAME = "protocol.yaml"
PROTOCOL = """\
name: pilot
description: two robots, one short block each, in a counterbalanced order
scenario: one_handover
conditions:                   # system keys; participants see only the labels
  - {system: pil, label: Robot A}
  - {system: proactive, label: Robot B}
order: counterbalanced        # fixed | counterbalanced | latin-square
blocks:
  - types: [A]                # one handover of type A per block
instructions: |
  Block {block} of {blocks}: you work with {label}.
  Hand over {handovers} table leg(s) with your gestures; thumb up or down tells the robot
  how it did.
questionnaires:
  - nasa-tlx                  # or {preset: nasa-tlx, weighted: true} for the pairwise weights
  - name: ease
    title: Working with the robot
    points: 5
    items:
      - {id: understood, text: The robot understood what I meant., subscale: fluency}
      - {id: waited, text: I often had to wait for the robot., reverse: true, subscale: fluency}
      - {id: check, text: Please choose 4 for this statement., attention: 4}
"""
GROUPS = {
    "within": "",
    "between": "groups:                       # each participant is assigned one group\n{groups}",
    "mixed": "groups:                       # a within factor in the first group\n{groups}",
}
STUDY = """\
name: {name}
description: a pilot study of the live page
protocol: {protocol}        # a protocol file beside this one, or a shipped protocol's name
design: {design}                  # within | between | mixed
{groups_block}participants: 12              # planned; robin-pil study-status shows what is left
id_prefix: P                  # participant ids P01, P02, ...
seed: 0                       # the study seed: every block's seed derives from it
consent:
  title: Taking part in this study
  text: |
    You will teach a simulated robot which action you mean by each of your gestures. The
    session takes about 20 minutes and is recorded (your clicks and keys, the robot's
    actions, your answers), with a participant number instead of your name. You may stop
    at any time without giving a reason.
  agree: I agree to take part
  decline: I do not agree
demographics:
  items:
    - {{id: age, text: Your age in years, kind: number, min: 18, max: 99}}
    - {{id: hand, text: Your dominant hand, kind: choice, choices: [left, right, both]}}
    - id: robots
      text: Have you worked with robots before?
      kind: choice
      choices: [never, a few times, often]
    - {{id: remarks, text: Anything you want to tell us, kind: text, optional: true}}
practice:                     # a practice block before the first: never analysed
  types: [A]
  block_seconds: 60           # s of simulated time
limits:                       # every block's caps
  block_seconds: 900          # s of simulated time
  block_actions: 120          # robot actions
  inactivity_seconds: 120     # the session holds and asks whether the participant is there
debrief:
  text: |
    Thank you! The two robots differed in one way: one of them acted before your gesture
    when it expected what came next. Please do not tell future participants.
"""


def init_study(folder: Path, protocol: str | None, design: str) -> Study:
    """Write a new study folder (see the module doc); the loaded study."""
    folder = Path(folder)
    if design not in DESIGNS:
        raise StudyError(f"--design {quote(design)}: valid choices: " + ", ".join(DESIGNS))
    if (folder / STUDY_NAME).exists():
        raise StudyError(
            f"{folder / STUDY_NAME} exists already; a study is never overwritten: choose "
            "another folder"
        )
    copies: dict[str, str] = {}  # files written beside study.yaml: name -> text
    if protocol is None:
        systems, ref = ["pil", "proactive"], PROTOCOL_NAME
        copies[PROTOCOL_NAME] = PROTOCOL
    else:
        path = find_protocol(protocol)
        loaded = load_protocol(path)  # checked here
        systems, ref = [c.system for c in loaded.conditions], protocol
        if Path(protocol).is_file():  # a file of the lab's: copied, so the folder holds it
            ref = PROTOCOL_NAME
            copies[PROTOCOL_NAME] = _read(Path(protocol), "the protocol")
            scenario = loaded.scenario
            if scenario is not None and Path(scenario).is_file():
                copies[Path(scenario).name] = _read(Path(scenario), "the scenario")
    groups = ""
    if design == "between":
        groups = "".join(
            f"  - {{name: g{k + 1}, conditions: [{s}]}}\n" for k, s in enumerate(systems)
        )
    elif design == "mixed":
        every = ", ".join(systems)
        groups = (
            f"  - {{name: both, conditions: [{every}]}}\n"
            f"  - {{name: one, conditions: [{systems[0]}]}}\n"
        )
    text = STUDY.format(
        name=folder.resolve().name,
        protocol=ref,
        design=design,
        groups_block=GROUPS[design].format(groups=groups),
    )
    made = not folder.exists()
    folder.mkdir(parents=True, exist_ok=True)
    written = [write_text_atomic(folder / name, body) for name, body in copies.items()]
    written.append(write_text_atomic(folder / STUDY_NAME, text))
    try:
        return load_study(folder)
    except RobinPilError:  # e.g. a copied protocol whose scenario lies elsewhere: nothing left
        for path in written:
            path.unlink(missing_ok=True)
        if made:
            folder.rmdir()
        raise


def _read(path: Path, what: str) -> str:
    """A lab's file to copy into the study folder, through the guarded reader."""
    try:
        return read_kind_text(path, "settings", what)
    except UnreadableFileError as error:
        raise StudyError(str(error)) from None
