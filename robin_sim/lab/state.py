"""Where a study stands (``robin-pil study-status DIR``): who ran, what is left, what is not
finished, and where the next participant would go.

Built from the registry (:mod:`robin_sim.lab.registry`), the study's log (the blocks each
participant ended) and the assignment (:mod:`robin_sim.lab.assignment`). Pure Python.
"""

from __future__ import annotations

from collections import Counter
from typing import Any

from pil.experiments.report import markdown_table
from robin_sim.lab.assignment import assign, cells
from robin_sim.lab.registry import FILLING, PARTICIPANT_STATUSES, Registry, next_number
from robin_sim.lab.study_file import Study
from robin_sim.lab.study_log import StudyLog


def study_state(study: Study) -> dict[str, Any]:
    """The study's state as JSON-ready fields (see :func:`state_text`)."""
    entries = Registry(study.folder, study.name).entries()
    ended: Counter[str] = Counter()
    last: dict[str, str] = {}
    for line in StudyLog(study.folder).entries():
        if line.get("event") == "block_ended":
            ended[line["participant"]] += 1
            last[line["participant"]] = f"{line.get('session')} {line.get('status')}"
    people = []
    for entry in entries:
        blocks = len(entry.get("order", ())) and _blocks_of(study, entry)
        people.append(
            {
                **entry,
                "blocks_ended": ended[entry["id"]],
                "blocks_planned": blocks,
                "last_block": last.get(entry["id"], ""),
            }
        )
    counts = Counter(e["status"] for e in entries)
    filled = Counter((e["group"], tuple(e["order"])) for e in entries if e["status"] in FILLING)
    group, order = assign(study, entries)
    return {
        "study": study.name,
        "design": study.design,
        "protocol": study.protocol_ref,
        "seed": study.seed,
        "planned": study.planned,
        "counts": {s: counts.get(s, 0) for s in PARTICIPANT_STATUSES},
        "left": None if study.planned is None else max(0, study.planned - counts["completed"]),
        "cells": [
            {"group": g, "order": list(o), "participants": filled.get((g, o), 0)}
            for g, o in cells(study)
        ],
        "participants": people,
        "next": {
            "id": study.participant_id(next_number(entries, study.id_prefix)),
            "group": group,
            "order": list(order),
        },
    }


def _blocks_of(study: Study, entry: dict[str, Any]) -> int:
    practice = 1 if study.practice is not None else 0
    return practice + len(study.protocol.blocks_in(entry["order"]))


def state_text(state: dict[str, Any]) -> str:
    """The state as the command prints it (Markdown tables)."""
    counts = state["counts"]
    lines = [
        f"# Study {state['study']}",
        "",
        f"design {state['design']}, protocol {state['protocol']}, study seed {state['seed']}",
        "",
        ", ".join(f"{n} {status}" for status, n in counts.items()),
    ]
    if state["planned"] is not None:
        lines.append(
            f"planned {state['planned']}: {counts['completed']} completed, {state['left']} left"
        )
    lines += ["", "## Assignment (participants in each group and condition order)", ""]
    lines.append(
        markdown_table(
            ["group", "order", "participants"],
            [[c["group"], " then ".join(c["order"]), c["participants"]] for c in state["cells"]],
        )
    )
    people = state["participants"]
    lines += ["", "## Participants", ""]
    lines.append(
        markdown_table(
            ["id", "group", "order", "status", "blocks", "started", "ended", "last block"],
            [
                [
                    p["id"],
                    p["group"],
                    " then ".join(p["order"]),
                    p["status"] + (f" ({p['reason']})" if p.get("reason") else ""),
                    f"{p['blocks_ended']} / {p['blocks_planned']}",
                    p.get("started_utc") or "-",
                    p.get("ended_utc") or "-",
                    p["last_block"] or "-",
                ]
                for p in people
            ],
        )
        if people
        else "none yet"
    )
    unfinished = [p["id"] for p in people if p["status"] in ("unfinished", "running")]
    lines += ["", "Unfinished: " + (", ".join(unfinished) if unfinished else "none")]
    nxt = state["next"]
    lines.append(
        f"Next: {nxt['id']} would go to group {nxt['group']} ({' then '.join(nxt['order'])})"
    )
    return "\n".join(lines) + "\n"
