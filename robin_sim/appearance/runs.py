"""The appearance study's runs: each person, each classifier, each repetition, one episode.

A run is a physical episode without video read by Robin's eye cameras (PIL, the people file's
assembly and tables) with the person's looks; ``fixed`` reads with the shipped gesture model,
``adapted`` with the model adapting to the person (``adapt``). Repetition ``r`` of every person
and classifier has the same seed (:func:`pil.experiments.study.rep_seeds`), so the two
classifiers see the same handover order and the same performances: their runs pair.

Each finished run is one JSON file in ``OUT/runs`` (its row and its per-table rows), written
whole or not at all, with its episode log beside it; a run whose file exists is not run again,
so an interrupted study (Ctrl-C to the process group, or SIGTERM) resumes where it stopped.
Runs go to a :class:`pil.worker_pool.SpawnPool` (each worker builds its own scene and OpenGL
context); on an interrupt its workers are ended at once, the episodes in flight not waited for.
"""

from __future__ import annotations

import json
import os
from collections.abc import Callable
from concurrent.futures import FIRST_COMPLETED, Future, wait
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from pil.atomic import write_text_atomic
from pil.file_names import EPISODE_LOG_NAME, SUMMARY_NAME
from pil.regular_files import UnreadableFileError, read_json_file, read_jsonl_file
from pil.task.feedback_audit import confusion_columns
from pil.worker_pool import SpawnPool
from robin_sim.appearance.people import AppearancePeople, Looks

CLASSIFIERS: tuple[str, ...] = ("fixed", "adapted")
RUNS_DIR = "runs"
RESULT_FORMAT = 2  # of a run's result file: one of another format runs again


@dataclass(frozen=True, slots=True)
class AppearanceRun:
    """One run of the study."""

    person: Looks
    classifier: str
    rep: int
    seed: int
    tables: int
    scenario: str | None

    @property
    def run_id(self) -> str:
        return f"{self.person.name}-{self.classifier}-{self.rep:03d}"


def plan_runs(people: AppearancePeople, reps: int, seeds: list[int]) -> list[AppearanceRun]:
    """Every run of the study, by person, repetition and classifier."""
    return [
        AppearanceRun(person, classifier, rep, seeds[rep], people.tables, people.scenario_file)
        for person in people.people
        for rep in range(reps)
        for classifier in CLASSIFIERS
    ]


def table_rows(log: list[dict[str, Any]]) -> list[dict[str, Any]]:
    """Per table, from an episode log: the eye cameras' gesture readings, how many were read
    right, the detection rate, what the shipped model reads right in the very same views
    (adapting runs; otherwise the same), and the robot's actions."""
    tables: dict[int, dict[str, int]] = {}
    for record in log:
        row = tables.setdefault(
            int(record["table"]), {"readings": 0, "read_right": 0, "shipped_right": 0}
        )
        row["actions"] = row.get("actions", 0) + (record.get("action") is not None)
        for reading in record.get("vision") or []:
            if reading["kind"] != "gesture":
                continue
            row["readings"] += 1
            row["read_right"] += reading["read"] == reading["shown"]
            row["shipped_right"] += reading.get("shipped", reading["read"]) == reading["shown"]
    out = []
    for table, row in sorted(tables.items()):
        n = row["readings"]
        out.append(
            {
                "table": table + 1,
                "readings": n,
                "read_right": row["read_right"],
                "detection_rate": row["read_right"] / n if n else None,
                "shipped_detection_rate": row["shipped_right"] / n if n else None,
                "actions": row.get("actions", 0),
            }
        )
    return out


def run_one(run: AppearanceRun, out: Path) -> dict[str, Any]:
    """Run ``run`` as an episode into ``out/runs/<id>`` and write its result file."""
    from robin_sim.episode.config import EpisodeConfig
    from robin_sim.episode.run import run_episode
    from robin_sim.render.gl_backend import ensure_gl_backend

    ensure_gl_backend()
    folder = out / RUNS_DIR / run.run_id
    params = {k: v for k, v in run.person.values().items() if v is not None}
    params.update(detector="vision", adapt=run.classifier == "adapted")
    config = EpisodeConfig(
        tables=run.tables,
        seed=run.seed,
        scenario=run.scenario,
        out=folder,
        video=False,
        verify=False,
        progress=False,
        params=params,
    )
    error = ""
    try:
        summary = run_episode(config.spec())
    except KeyboardInterrupt:
        raise
    except Exception as problem:  # the run failed: recorded, the study goes on
        error = str(problem)
        summary = read_json_file(folder / SUMMARY_NAME, "summary", "the run's summary")
    log = read_jsonl_file(folder / EPISODE_LOG_NAME, "log", "the run's step log")
    vision = summary.get("vision") or {}
    row = {
        "person": run.person.name,
        "classifier": run.classifier,
        "rep": run.rep,
        "seed": run.seed,
        **run.person.values(),
        "status": summary["status"],
        "error": error,
        "tables": run.tables,
        "legs_delivered": summary["legs_delivered"],
        "legs_total": summary["legs_total"],
        "gestures": summary["gestures"],
        "actions": summary["actions"],
        "detection_rate": vision.get("detection_rate"),
        "shipped_detection_rate": vision.get("shipped_detection_rate")
        or vision.get("detection_rate"),
        "misread": vision.get("misread"),
        "discarded": vision.get("discarded"),
        "no_hand": vision.get("no_hand"),
        "feedback_misread": vision.get("feedback_misread"),
        "examples": (vision.get("adapt") or {}).get("examples", 0),
        **confusion_columns(summary.get("feedback_confusion")),
    }
    tables = [
        {"person": run.person.name, "classifier": run.classifier, "rep": run.rep, **t}
        for t in table_rows(log)
    ]
    result = {"format": RESULT_FORMAT, "row": row, "tables": tables}
    write_text_atomic(out / RUNS_DIR / f"{run.run_id}.json", json.dumps(result, indent=1) + "\n")
    return result


def finished(out: Path, run: AppearanceRun) -> dict[str, Any] | None:
    """The result of ``run`` when its file is whole, else None (it runs again)."""
    path = out / RUNS_DIR / f"{run.run_id}.json"
    if not path.is_file():
        return None
    try:
        result = read_json_file(path, "summary", "a finished run", finite=True)
    except UnreadableFileError:  # cut short or damaged: it runs again
        return None
    if not isinstance(result, dict) or not isinstance(result.get("row"), dict):
        return None
    if result.get("format") != RESULT_FORMAT:
        return None
    row = result["row"]
    same = row.get("seed") == run.seed and row.get("tables") == run.tables
    same = same and all(row.get(k) == v for k, v in run.person.values().items())
    return result if same else None


def run_all(
    runs: list[AppearanceRun],
    out: Path,
    workers: int,
    progress: Callable[[int], object] = lambda n: None,
) -> list[dict[str, Any]]:
    """Every run's result, in ``runs`` order; finished runs are read back, the others run in
    a spawn pool of ``workers`` processes (0: in this process)."""
    results: dict[str, dict[str, Any]] = {}
    todo = []
    for run in runs:
        done = finished(out, run)
        if done is None:
            todo.append(run)
        else:
            results[run.run_id] = done
    progress(len(results))
    os.environ.setdefault("MUJOCO_GL", "egl")
    if todo and workers == 0:
        for run in todo:
            results[run.run_id] = run_one(run, out)
            progress(1)
    elif todo:
        pool = SpawnPool(min(workers, len(todo)))
        try:
            futures: dict[Future[dict[str, Any]], AppearanceRun] = {
                pool.submit(run_one, run, out): run for run in todo
            }
            pending = set(futures)
            while pending:
                done_now, pending = wait(pending, return_when=FIRST_COMPLETED)
                for future in done_now:
                    results[futures[future].run_id] = future.result()
                    progress(1)
        except BaseException:  # an interrupt: the runs in flight are not waited for
            pool.stop()
            raise
        pool.shutdown(wait=True)
    return [results[run.run_id] for run in runs]
