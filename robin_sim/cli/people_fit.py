"""``robin-pil people --from-sessions DIR``: simulated people fitted to recorded ones.

Every consented participant's sessions under DIR (:mod:`pil.experiments.people_sources`) are
fitted (:mod:`pil.experiments.people_fit`); each fitted person runs
``--sessions-per-person`` simulated sessions (:mod:`robin_sim.fitted.runs`), and the
simulated sessions are compared with the recorded ones
(:mod:`pil.experiments.people_compare`). Written to ``--out``: ``people/<P>.json`` (the fitted
people), ``simulated/<P>/sim<k>/`` (the simulated sessions' files), ``recorded.csv`` and
``simulated.csv`` (one row per session), ``comparison.csv``, ``comparison.md`` and
``comparison.png``. A helper of :mod:`robin_sim.cli.people`, not a command of its own.
"""

from __future__ import annotations

import argparse
from pathlib import Path
from typing import Any

from pil.errors import RobinPilError
from pil.regular_files import read_json_file
from robin_sim.cli.options import whole_number

MAX_WORKERS = 16  # --workers of robin-pil people (both of its physical modes)
DEFAULT_SESSIONS = 20
MAX_SESSIONS = 1000
SIM_ROW_COLUMNS = ("participant", "session", "seed", "status", "legs_delivered")
REFUSED_WITH = {  # options of the other two studies: refused with --from-sessions
    "appearance": "--appearance",
    "person": "--person",
    "people": "--people",
    "tables": "--tables",
}


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """The two options of this mode (``--workers``, ``--seed``, ``--out`` are shared)."""
    parser.add_argument(
        "--from-sessions",
        type=Path,
        default=None,
        metavar="DIR",
        help="fit a simulated person to each consented participant of the recorded live "
        "sessions in DIR (a study folder, or a folder of them), run their simulated sessions "
        "and compare them with the recorded ones (default: off, the mappings study)",
    )
    parser.add_argument(
        "--sessions-per-person",
        type=whole_number,
        default=DEFAULT_SESSIONS,
        metavar="K",
        help=f"with --from-sessions: simulated sessions of each fitted person, 1 to "
        f"{MAX_SESSIONS} (default: {DEFAULT_SESSIONS})",
    )


def check(args: argparse.Namespace) -> None:
    """Every option of this mode, before anything is read or written."""
    given = [
        flag for dest, flag in REFUSED_WITH.items() if getattr(args, dest) not in (None, False)
    ]
    if given:
        raise RobinPilError(
            f"{', '.join(given)} with --from-sessions: those choose the mappings or the "
            "appearance study; leave them out"
        )
    if args.seeds != 1:
        raise RobinPilError(
            "--seeds with --from-sessions: every simulated session has its own seed"
        )
    k = args.sessions_per_person
    if not 1 <= k <= MAX_SESSIONS:
        raise RobinPilError(f"--sessions-per-person must be 1 to {MAX_SESSIONS}, got {k}")
    if not 0 <= args.workers <= MAX_WORKERS:
        raise RobinPilError(f"--workers must be 0 to {MAX_WORKERS}, got {args.workers}")


def _checked(setting: Any, who: str, name: str) -> None:
    """The recorded session's setting can be run here (else one message, exit 2)."""
    try:
        setting.config(who, 0)
    except RobinPilError as error:
        raise RobinPilError(f"{name}: its setting cannot be simulated: {error}") from None


def run(args: argparse.Namespace) -> int:
    """Fit, simulate, compare (see the module doc); bad input raises before anything runs."""
    from pil.experiments import people_compare as compare
    from pil.experiments.people_fit import fit_person, write_person
    from pil.experiments.people_observed import COMPARED_MEASURES, observe, session_measures
    from pil.experiments.people_sources import find_sources
    from pil.outdir import claimed_out_dir
    from robin_sim.cli.options import progress_bar
    from robin_sim.fitted.runs import plan_runs, run_all
    from robin_sim.fitted.session import SessionSetting

    check(args)
    sources = find_sources(args.from_sessions)  # consent, readable files: else exit 2
    recorded: list[dict[str, Any]] = []
    people = []
    for who, sessions in sorted(sources.sessions.items()):
        observed = [observe(s.inputs, s.events, s.log) for s in sessions]
        for s in sessions:
            _checked(SessionSetting.of(s.summary), who, s.name)
        settings = [SessionSetting.of(s.summary).as_json() for s in sessions]
        names = [{"session": s.name, "sha256": s.sha256} for s in sessions]
        people.append(fit_person(who, observed, names, settings))
        for session, seen, setting in zip(sessions, observed, settings, strict=True):
            row = session_measures(session.summary, seen)
            recorded.append(
                {"participant": who, "session": session.name, "setting": setting, **row}
            )
    with claimed_out_dir(args.out) as out:
        (out / "people").mkdir(exist_ok=True)
        for person in people:
            write_person(person, out / "people" / f"{person.participant}.json")
        runs = plan_runs(people, args.sessions_per_person, args.seed)
        with progress_bar(len(runs), "fitted people", args) as bar:
            simulated = run_all(runs, out, args.workers, progress=bar.update)
        columns = (*SIM_ROW_COLUMNS[:2], *SIM_ROW_COLUMNS[3:], *COMPARED_MEASURES)
        compare.write_csv(recorded, columns, out / "recorded.csv")
        compare.write_csv(simulated, (*SIM_ROW_COLUMNS, *COMPARED_MEASURES), out / "simulated.csv")
        rows = compare.compare(recorded, simulated)
        written = [
            compare.write_csv(rows, compare.COMPARISON_COLUMNS, out / "comparison.csv"),
            out / "comparison.md",
            compare.figure(recorded, simulated, out / "comparison.png"),
        ]
        fitted = [
            read_json_file(out / "people" / f"{p.participant}.json", "settings", "a fitted person")
            for p in people
        ]
        ended: dict[str, dict[str, int]] = {}
        for row in simulated:
            counts = ended.setdefault(row["participant"], {})
            counts[str(row["status"])] = counts.get(str(row["status"]), 0) + 1
        text = compare.markdown(rows, fitted, sources.left_out, args.sessions_per_person, ended)
        (out / "comparison.md").write_text(text + "\n", encoding="utf-8")
    inside = [r["inside"] for r in rows if r.get("inside") is not None]
    print(
        f"{len(people)} fitted people, {len(simulated)} simulated sessions; recorded values "
        f"inside the simulated 95 % range: {sum(inside)} of {len(inside)}; wrote "
        + ", ".join(str(p) for p in written)
    )
    return 0
