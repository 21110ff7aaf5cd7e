"""Many simulated sessions of each fitted person: planned, run (resumable), measured.

Each person gets ``sessions_per_person`` simulated sessions, their recorded sessions'
settings taken in turn; session ``k`` of participant ``P`` has the seed
:func:`pil.task.seeds.block_seed` (``seed``, ``P``, ``k``), so the same seed gives the same
sessions and the same results. A session's folder is ``OUT/simulated/<P>/sim<k>``; one whose
``summary.json`` is there with its seed is finished and only measured again (an interrupted
run goes on where it stopped); a folder without it is made anew. Runs go to a ``spawn``
process pool (:class:`pil.worker_pool.SpawnPool`: each worker builds its own scene, leaves
Ctrl-C and SIGTERM to the command and dies with it), or run in this process with ``workers``
0.
"""

from __future__ import annotations

import os
import shutil
from collections.abc import Callable, Sequence
from concurrent.futures import FIRST_COMPLETED, Future, wait
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from pil.experiments.people_fit import FittedPerson
from pil.experiments.people_observed import observe, session_measures
from pil.experiments.people_sources import read_json, read_session
from pil.experiments.sessions_load import SUMMARY_NAME
from pil.regular_files import UnreadableFileError, read_json_file
from pil.task.seeds import block_seed
from pil.worker_pool import SpawnPool
from robin_sim.fitted.session import SessionSetting, simulate

SIMULATED_DIR = "simulated"


@dataclass(frozen=True)
class SimRun:
    """One simulated session to run."""

    person: FittedPerson
    k: int
    setting: SessionSetting
    seed: int

    def folder(self, out: Path) -> Path:
        return out / SIMULATED_DIR / self.person.participant / f"sim{self.k:03d}"


def plan_runs(people: Sequence[FittedPerson], sessions_per_person: int, seed: int) -> list[SimRun]:
    """Every simulated session of every person (see the module doc)."""
    runs = []
    for person in people:
        settings = []
        for s in person.settings:
            if SessionSetting.from_json(s) not in settings:
                settings.append(SessionSetting.from_json(s))
        for k in range(sessions_per_person):
            setting = settings[k % len(settings)]
            runs.append(SimRun(person, k, setting, block_seed(seed, person.participant, k)))
    return runs


def measured(run: SimRun, out: Path) -> dict[str, Any] | None:
    """The finished session's row (None when it is not finished with this seed)."""
    folder = run.folder(out)
    path = folder / SUMMARY_NAME
    if not path.is_file():
        return None
    try:
        summary = read_json_file(path, "summary", "the session's summary")
    except UnreadableFileError:  # cut short or damaged: the session runs again
        return None
    if not isinstance(summary, dict) or (summary.get("live") or {}).get("seed") != run.seed:
        return None
    session = read_session(folder, out, run.person.participant, read_json(path))
    row = session_measures(summary, observe(session.inputs, session.events, session.log))
    return {
        "participant": run.person.participant,
        "session": session.name,
        "seed": run.seed,
        "setting": run.setting.as_json(),
        **row,
    }


def simulate_run(run: SimRun, out: Path) -> dict[str, Any]:
    """Simulate ``run`` (its folder made anew) and measure it."""
    folder = run.folder(out)
    if folder.exists():
        shutil.rmtree(folder)  # an interrupted session: made anew
    simulate(run.person, run.setting, run.seed, folder)
    row = measured(run, out)
    assert row is not None  # just written
    return row


def run_all(
    runs: Sequence[SimRun],
    out: Path,
    workers: int,
    progress: Callable[[int], object] = lambda n: None,
) -> list[dict[str, Any]]:
    """Every run's row, in ``runs`` order (finished ones read back; see the module doc)."""
    rows: dict[int, dict[str, Any]] = {}
    todo = []
    for i, run in enumerate(runs):
        done = measured(run, out)
        if done is None:
            todo.append(i)
        else:
            rows[i] = done
    progress(len(rows))
    os.environ.setdefault("MUJOCO_GL", "egl")
    if todo and workers == 0:
        for i in todo:
            rows[i] = simulate_run(runs[i], out)
            progress(1)
    elif todo:
        pool = SpawnPool(min(workers, len(todo)))
        try:
            futures: dict[Future[dict[str, Any]], int] = {
                pool.submit(simulate_run, runs[i], out): i for i in todo
            }
            pending = set(futures)
            while pending:
                finished, pending = wait(pending, return_when=FIRST_COMPLETED)
                for future in finished:
                    rows[futures[future]] = future.result()
                    progress(1)
        except BaseException:  # an interrupt: the runs in flight are not waited for
            pool.stop()
            raise
        pool.shutdown(wait=True)
    return [rows[i] for i in range(len(runs))]
