"""Running entrants over tracks, conditions and a seed block into a :class:`Journal`.

:class:`Entrant` names an agent (a reference name of :data:`pil.bench.entrants.REFERENCE` with
its parameters, or ``pkg.module:factory``); :func:`run_bench` runs every (track, condition,
entrant, seed) the journal does not have yet, in a pool of ``workers`` processes or here,
appending each finished run. The rows are the same whatever the workers (each run depends on
its seed alone). An entrant that is not a reference agent runs under
:class:`pil.bench.guard.TimeLimit`: anything its code does wrong ends the bench with one
:class:`pil.bench.entrants.EntrantError` naming the agent, the track, the condition and the
seed; the runs finished before are kept.
"""

from __future__ import annotations

import functools
import json
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field
from typing import Any

from pil.bench.entrants import REFERENCE, EntrantError, Factory, load_factory, reference
from pil.bench.guard import DECISION_TIMEOUT, TimeLimit, guard_factory
from pil.bench.journal import Journal
from pil.bench.processes import RunEndedError, run_ordered
from pil.bench.suite import Suite, Track
from pil.bench.tracks import run_track
from pil.folder_lock import FolderLock


@dataclass(frozen=True)
class Entrant:
    """An agent in the benchmark: its name in the results, and how to build it."""

    name: str
    spec: str
    params: Mapping[str, Any] = field(default_factory=dict)

    def factory(self) -> Factory:
        """The factory ``factory(seed) -> agent``."""
        return _factory(self.spec, json.dumps(dict(self.params), sort_keys=True))

    @property
    def external(self) -> bool:
        """Not one of the reference agents."""
        return self.spec not in REFERENCE


@functools.lru_cache(maxsize=64)
def _factory(spec: str, params: str) -> Factory:
    if spec in REFERENCE:
        return reference(spec, json.loads(params))
    return load_factory(spec)


Task = tuple[str, str, Entrant, int, bool]


Runner = Callable[[Suite, Track, str, int, Factory, bool], dict[str, Any]]


def _run(
    suite: Suite, task: Task, runner: Runner = run_track, seconds: float = DECISION_TIMEOUT
) -> dict[str, Any]:
    """One run's row; an external entrant's calls run under a limit of ``seconds`` each."""
    track, condition, entrant, seed, quick = task
    factory = entrant.factory()  # an entrant that cannot be loaded says so by its spec
    if not entrant.external:
        row = runner(suite, suite.track(track), condition, seed, factory, quick)
    else:
        try:
            with TimeLimit(seconds) as limit:
                guarded = guard_factory(factory, limit)
                row = runner(suite, suite.track(track), condition, seed, guarded, quick)
        except EntrantError as error:
            raise EntrantError(
                f"--agent {entrant.name} on track {track}, condition {condition}, seed {seed}: "
                f"{error}"
            ) from None
    params = json.dumps(dict(entrant.params), sort_keys=True)
    return {
        "track": track,
        "condition": condition,
        "agent": entrant.name,
        "seed": seed,
        "params": params,
        **row,
    }


def plan(
    suite: Suite,
    entrants: Sequence[Entrant],
    tracks: Sequence[str],
    seeds: Sequence[int],
    quick: bool,
    conditions: Sequence[str] | None = None,
) -> list[Task]:
    """Every run, in a fixed order (``conditions``: only these of each track's)."""
    return [
        (track, condition, entrant, seed, quick)
        for track in tracks
        for condition in suite.track_conditions(track, quick)
        if conditions is None or condition in conditions
        for entrant in entrants
        for seed in seeds
    ]


def run_bench(
    suite: Suite,
    entrants: Sequence[Entrant],
    tracks: Sequence[str],
    journal: Journal,
    seeds: Sequence[int],
    *,
    workers: int = 1,
    progress: Callable[[int], None] | None = None,
    conditions: Sequence[str] | None = None,
    runner: Runner = run_track,
    decision_timeout: float = DECISION_TIMEOUT,
) -> list[dict[str, Any]]:
    """Run what ``journal`` lacks; return all its rows for these entrants and tracks.
    ``runner``: how one run is made (default :func:`pil.bench.tracks.run_track`, learner only;
    the physical track's comes from ``robin_sim``); ``decision_timeout``: the limit of each
    call into an external entrant, in seconds."""
    quick = bool(journal.stamp["quick"])
    every = plan(suite, entrants, tracks, seeds, quick, conditions)
    todo = [t for t in every if (t[0], t[1], t[2].name, t[3]) not in journal.done]
    journal.start()
    with FolderLock(journal.out):  # one command at a time appends to the journal
        work = functools.partial(_run, suite, runner=runner, seconds=decision_timeout)
        _execute(todo, journal, workers, progress, work, len(every) - len(todo))
    names = {e.name for e in entrants}
    wanted = set(tracks)
    return [r for r in journal.rows if r["agent"] in names and r["track"] in wanted]


def _execute(
    todo: Sequence[Task],
    journal: Journal,
    workers: int,
    progress: Callable[[int], None] | None,
    work: Callable[[Task], dict[str, Any]],
    done: int,
) -> None:
    """Run ``todo`` here or in watched processes (:mod:`pil.bench.processes`: several
    workers, or an external entrant's runs), appending each finished run to ``journal``."""
    if progress is not None and done:
        progress(done)
    watched = workers > 1 or any(task[2].external for task in todo)
    try:
        if watched:
            rows = (row for _, row in run_ordered(work, todo, workers))
        else:
            rows = (work(task) for task in todo)
        for row in rows:
            journal.add([row])
            if progress is not None:
                progress(1)
    except RunEndedError as ended:
        task: Task = ended.task  # type: ignore[assignment]
        track, condition, entrant, seed, _ = task
        who = f"--agent {entrant.name}" if entrant.external else f"agent {entrant.name}"
        raise EntrantError(
            f"{who} on track {track}, condition {condition}, seed {seed}: {ended}"
        ) from None
