"""A study's exports and report, from its folder: the registry says who is analysed.

:func:`write_exports` writes ``exports/trials.csv``, ``exports/questionnaires_wide.csv`` and
``exports/long.csv`` (:mod:`pil.experiments.study_export`); :func:`write_report` the study's
analysis (:mod:`pil.experiments.study_report`) beside the sessions and questionnaires reports
of the participants analysed (declined and withdrawn ones left out). Paths in every file are
relative to the study folder.
"""

from __future__ import annotations

from pathlib import Path

from pil.atomic import write_text_atomic
from pil.experiments.study_export import (
    EXCLUDED,
    LONG_COLUMNS,
    TRIAL_COLUMNS,
    long_rows,
    study_blocks,
    trial_rows,
    wide_rows,
)
from pil.experiments.sweep_store import rows_to_csv
from robin_sim.lab.registry import Registry
from robin_sim.lab.study_file import Study

EXPORTS_DIR = "exports"
REPORT_DIR = "report"


def write_exports(study: Study, out: Path | None = None) -> list[Path]:
    """The three CSV files (into ``out``, default the study's ``exports`` folder)."""
    out = study.folder / EXPORTS_DIR if out is None else Path(out)
    people = Registry(study.folder, study.name).entries()
    blocks = study_blocks(study.folder, people)
    wide, columns = wide_rows(study.folder, people, blocks)
    return [
        write_text_atomic(out / "trials.csv", rows_to_csv(trial_rows(blocks), TRIAL_COLUMNS)),
        write_text_atomic(out / "questionnaires_wide.csv", rows_to_csv(wide, columns)),
        write_text_atomic(
            out / "long.csv", rows_to_csv(long_rows(study.folder, people, blocks), LONG_COLUMNS)
        ),
    ]


def write_report(study: Study, out: Path | None = None) -> list[Path]:
    """The study's report (into ``out``, default the study's ``report`` folder)."""
    from pil.experiments.questionnaire_report import (
        SUMMARY_COLUMNS,
        answers_markdown,
        load_answers,
        summarize_answers,
    )
    from pil.experiments.sessions_report import load_sessions, write_sessions_report
    from pil.experiments.study_report import write_study_report

    out = study.folder / REPORT_DIR if out is None else Path(out)
    people = Registry(study.folder, study.name).entries()
    analysed = {p["id"] for p in people if p.get("status") not in EXCLUDED}
    conditions = [c.system for c in study.protocol.conditions]
    written = write_study_report(study.folder, study.name, study.design, conditions, people, out)
    rows = [r for r in load_sessions(study.folder) if r["participant"] in analysed]
    if rows:
        written += write_sessions_report(rows, study.folder, out)
    answers = [a for a in load_answers(study.folder) if a["participant"] in analysed]
    if answers:
        written.append(write_text_atomic(out / "questionnaires.md", answers_markdown(answers)))
        table = rows_to_csv(summarize_answers(answers), SUMMARY_COLUMNS)
        written.append(write_text_atomic(out / "questionnaires.csv", table))
    return written
