"""``robin-pil report``: summary table, paired tests and figures for a results CSV.

Works on a sweep's ``results.csv`` and on a study CSV (:mod:`pil.experiments.results_report`).

Given a folder instead, the report looks at what it holds: a study folder (``study.yaml``, from
``robin-pil study-init``) gets the study's analysis (:mod:`robin_sim.lab.exports`); live sessions
(``<participant>/<session>/summary.json`` with a ``"live"`` block, from ``robin-pil live``) get
the sessions report (:mod:`pil.experiments.sessions_report`); a study or sweep folder is
reported from its ``runs.csv`` / ``results.csv``; anything else is refused naming both.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from pil.experiments.results_report import BASELINE, METRICS
from pil.file_names import RESULTS_NAME, RUNS_NAME

RESULTS_FILES: tuple[str, ...] = (RESULTS_NAME, RUNS_NAME)  # a sweep's, a study's


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """The report's options."""
    parser.add_argument(
        "results",
        type=Path,
        metavar="RESULTS",
        help="a results CSV (a sweep's results.csv or a study's runs.csv), a sweep or study "
        "folder, or a folder of live sessions (e.g. out/live)",
    )
    parser.add_argument(
        "--out",
        type=Path,
        default=None,
        help="output directory (default: 'report' next to the CSV, or inside the folder)",
    )
    parser.add_argument(
        "--metrics",
        default=None,
        metavar="A,B",
        help=f"metrics to summarise (default: those of {', '.join(METRICS)} "
        "present, plus the physical ones)",
    )
    parser.add_argument(
        "--baseline",
        default=None,
        help="system every other system is compared with (default: pil; results CSVs only)",
    )


def run(args: argparse.Namespace) -> int:
    """Write the report and list its files."""
    from pil.errors import InvalidChoiceError
    from pil.experiments.report import ReportError, load_rows

    if args.results.is_dir():
        return run_folder(args)
    if not args.results.exists() and args.results.suffix != ".csv":
        from pil.experiments.sessions_report import EXPECTED

        raise ReportError(
            f"{args.results}: no such file or folder; expected a results CSV, a "
            f"study or sweep folder, or {EXPECTED}"
        )
    metrics = None if args.metrics is None else [m.strip() for m in args.metrics.split(",")]
    baseline = BASELINE if args.baseline is None else args.baseline
    rows = load_rows(args.results)
    if "system" not in rows[0]:  # e.g. /etc/passwd: one column, no run in it
        raise ReportError(
            f"{args.results}: not a results CSV: no 'system' column (its header: "
            f"{', '.join(str(c) for c in list(rows[0])[:6])[:120]}); give a sweep's "
            "results.csv or a study's runs.csv"
        )
    systems = sorted({str(row.get("system")) for row in rows})
    if baseline not in systems:  # asked for by name: an unknown one is an error
        raise InvalidChoiceError("baseline system", baseline, systems)
    out = args.out if args.out is not None else args.results.parent / "report"
    from pil.experiments.results_report import write_report

    for path in write_report(args.results, out, metrics=metrics, baseline=baseline):
        print(path)
    return 0


def run_study(args: argparse.Namespace) -> int:
    """A study folder: its analysis by design, with the sessions and questionnaires reports of
    the participants analysed (robin_sim.lab.exports.write_report)."""
    from pil.errors import RobinPilError
    from robin_sim.lab.exports import write_report
    from robin_sim.lab.study_file import load_study

    if args.metrics is not None or args.baseline is not None:
        raise RobinPilError(
            "--metrics and --baseline are for a results CSV; a study is reported on all its "
            "measures and questionnaire scores, with the model its design calls for"
        )
    study = load_study(args.results)
    for path in write_report(study, args.out):
        print(path)
    return 0


def run_folder(args: argparse.Namespace) -> int:
    """A folder: live sessions, else a study or sweep folder's results, else an error."""
    from pil.errors import RobinPilError
    from pil.experiments.sessions_report import (
        EXPECTED,
        load_sessions,
        unreported_sessions,
        write_sessions_report,
    )

    folder = args.results
    from robin_sim.lab.study_file import STUDY_NAME

    if (folder / STUDY_NAME).is_file():
        return run_study(args)
    rows = load_sessions(folder)  # a corrupt summary.json raises here, before anything is written
    if rows:
        if args.metrics is not None or args.baseline is not None:
            raise RobinPilError(
                "--metrics and --baseline are for a results CSV; a sessions folder is reported "
                "on all its measures, every pair of conditions compared"
            )
        out = args.out if args.out is not None else folder / "report"
        from pil.experiments.questionnaire_report import load_answers, write_answers_report

        answers = load_answers(folder)  # a damaged answer raises before anything is written
        for path in write_sessions_report(rows, folder, out):
            print(path)
        for path in write_answers_report(folder, out, answers):  # after the blocks, if any
            print(path)
        for where, why in unreported_sessions(folder):  # listed in report.md too
            print(f"robin-pil report: not reported: {where}: {why}", file=sys.stderr)
        return 0
    for name in RESULTS_FILES:
        if (folder / name).is_file():
            args.results = folder / name
            return run(args)
    unreported = unreported_sessions(folder)
    found = (
        f" ({len(unreported)} session folders have no readable summary, e.g. "
        f"{unreported[0][0]}: {unreported[0][1]})"
        if unreported
        else ""
    )
    raise RobinPilError(
        f"{folder}: nothing to report{found}; expected {EXPECTED}, or a study or sweep folder "
        f"(with {' or '.join(RESULTS_FILES)}), or a results CSV"
    )
