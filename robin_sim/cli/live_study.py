"""``robin-pil live --study DIR``: the options a study file decides, refused; the participant
registered (:func:`robin_sim.lab.run.prepare`) and the run's conductor with the study's screens
and journal. A helper of :mod:`robin_sim.cli.live` (not a command)."""

from __future__ import annotations

import argparse
from pathlib import Path
from typing import Any

# options a study file decides (refused with --study): dest -> (option, its default)
STUDY_DECIDES: dict[str, tuple[str, Any]] = {
    "protocol": ("--protocol", None),
    "system": ("--system", "pil"),
    "scenario": ("--scenario", None),
    "session": ("--session", None),
    "out": ("--out", Path("out/live")),
    "seed": ("--seed", "0"),
}


def study_conductor(args: argparse.Namespace, base: Any) -> tuple[Any, Any]:
    """The registered participant's run and its conductor (``base``: the command line's
    session settings: speed, video, webcam, ...)."""
    from robin_sim.lab.run import prepare, refuse_options
    from robin_sim.live.conductor import Conductor
    from robin_sim.live.preflight import check_writable

    decided = STUDY_DECIDES.items()
    refuse_options([o for dest, (o, default) in decided if getattr(args, dest) != default])
    check_writable(args.study)
    study = prepare(args.study, args.participant, base)  # registered: the last check
    questionnaires = study.study.protocol.questionnaires
    conductor = Conductor(study.configs, questionnaires, study.study.screens, study.journal)
    return study, conductor
