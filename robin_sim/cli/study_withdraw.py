"""``robin-pil study-withdraw DIR ID``: a participant withdrawn from a study.

The registry marks them ``withdrawn`` (with the reason and the time) and the study's log says
so; their data stay in the folder but are left out of the exports and the report, and their
place in the assignment is free for the next participant. ``--delete-data`` also removes their
session folder. Their id is never given again.
"""

from __future__ import annotations

import argparse
from pathlib import Path


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """The command's options."""
    parser.add_argument("dir", type=Path, metavar="DIR", help="the study folder")
    parser.add_argument("participant", metavar="ID", help="the participant's id")
    parser.add_argument("--reason", default="", help="why, for the registry (default: none given)")
    parser.add_argument(
        "--delete-data",
        action="store_true",
        help="also remove the participant's session folder (their answers and sessions)",
    )


def run(args: argparse.Namespace) -> int:
    """Mark the participant withdrawn (and delete their data when asked)."""
    import shutil

    from robin_sim.lab.plan import sessions_dir
    from robin_sim.lab.registry import Registry, RegistryError, since, utc_now
    from robin_sim.lab.study_file import load_study
    from robin_sim.lab.study_log import StudyLog

    study = load_study(args.dir)
    registry = Registry(study.folder, study.name)
    before = registry.entry(study.canonical_id(args.participant))  # names the ids if absent
    participant = before["id"]
    if before["status"] == "withdrawn":  # the first withdrawal's reason and time stand
        raise RegistryError(
            f"{participant} was withdrawn already (since {since(before)}, reason: "
            f"{before.get('reason') or 'not given'}); nothing changed"
        )
    reason = str(args.reason).strip()[:300]
    registry.update(
        participant, status="withdrawn", reason=reason or "not given", withdrawn_utc=utc_now()
    )
    folder = sessions_dir(study) / participant
    deleted = bool(args.delete_data) and folder.exists()
    if deleted:
        shutil.rmtree(folder)
    StudyLog(study.folder).write(
        participant, "withdrawn", reason=reason, was=before["status"], deleted=deleted
    )
    print(
        f"robin-pil study-withdraw: {participant} withdrawn (was {before['status']})"
        + ("; their session folder was deleted" if deleted else "; data kept, never analysed")
    )
    return 0
