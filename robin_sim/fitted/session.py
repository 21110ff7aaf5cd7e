"""One simulated session of a fitted person: the live engine, unpaced, with no page.

:func:`simulate` builds a session as a recorded one was built (:class:`SessionSetting`: its system,
scenario, handover types, feedback window and caps, from the recorded summary) with the live
session's own parts (:func:`robin_sim.live.run.live_parts`: the live body's tempo, the exact
detector, the within-step memory on, the watchdog), puts a
:class:`~robin_sim.fitted.player.FittedPlayer` at the participant's place and runs the
step loop as fast as physics goes (no pacing, no frames). It writes the files a live session
writes (``inputs.jsonl``, ``events.jsonl``, ``log.jsonl``, ``summary.json`` with a ``live``
block marked ``simulated``), so one reader measures recorded and simulated sessions alike.
"""

from __future__ import annotations

import json
import time
from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from pil.errors import RobinPilError
from pil.experiments.people_fit import FittedPerson
from pil.experiments.sessions_load import EVENTS_NAME, INPUTS_NAME, SESSION_LOG_NAME, SUMMARY_NAME
from pil.task.records import StepRecord
from pil.task.runner import steps
from robin_sim.episode.book import StepBook, run_summary
from robin_sim.episode.log import StepLog, write_json_atomic
from robin_sim.episode.summary import EpisodeTotals
from robin_sim.fitted.player import FittedPlayer
from robin_sim.live.booking import Booking
from robin_sim.live.config import LiveConfig
from robin_sim.live.status import LiveStatus
from robin_sim.robot.world import PhysicalWorld


@dataclass(frozen=True)
class SessionSetting:
    """How a recorded session was run, so a simulated one runs the same way."""

    system: str
    scenario: str
    handover_types: tuple[str, ...] | None
    feedback_window: float
    block_seconds: float | None
    block_actions: int | None

    @classmethod
    def of(cls, summary: Mapping[str, Any]) -> SessionSetting:
        """The setting of a recorded session's summary."""
        live = summary.get("live") or {}
        limits = live.get("limits") or {}
        types = live.get("handover_types")
        return cls(
            system=str(live.get("condition") or summary.get("system")),
            scenario=str(summary.get("scenario")),
            handover_types=None if types is None else tuple(str(t) for t in types),
            feedback_window=float(live.get("feedback_window_s") or 4.0),
            block_seconds=limits.get("block_seconds"),
            block_actions=limits.get("block_actions"),
        )

    @classmethod
    def from_json(cls, data: Mapping[str, Any]) -> SessionSetting:
        """The setting :meth:`as_json` wrote."""
        types = data.get("handover_types")
        return cls(**{**data, "handover_types": None if types is None else tuple(types)})

    def config(self, participant: str, seed: int) -> LiveConfig:
        """The live session's config of this setting, checked (:class:`RobinPilError` when
        the recorded session names something this installation lacks, e.g. a scenario)."""
        return LiveConfig(
            participant=participant,
            system=self.system,
            scenario=self.scenario,
            handover_types=self.handover_types,
            video=False,
            feedback_window=self.feedback_window,
            seed=seed,
            block_seconds=self.block_seconds,
            block_actions=self.block_actions,
        ).checked()

    def as_json(self) -> dict[str, Any]:
        return {
            "system": self.system,
            "scenario": self.scenario,
            "handover_types": None if self.handover_types is None else list(self.handover_types),
            "feedback_window": self.feedback_window,
            "block_seconds": self.block_seconds,
            "block_actions": self.block_actions,
        }


class Stopped(BaseException):
    """Raised between two ticks to end a simulated session (its status)."""

    def __init__(self, status: str) -> None:
        super().__init__(status)
        self.status = status


class _Lines:
    """A JSON-lines file written as the session goes."""

    def __init__(self, path: Path) -> None:
        self._file = path.open("w", encoding="utf-8")

    def write(self, entry: Mapping[str, Any]) -> None:
        self._file.write(json.dumps(entry, default=str) + "\n")

    def close(self) -> None:
        self._file.close()


class _Observer(Booking):
    """The live session's observer, telling the player too."""

    player: FittedPlayer

    def decided(self, record: StepRecord) -> None:
        super().decided(record)
        self.player.decided(record)


def simulate(
    person: FittedPerson, setting: SessionSetting, seed: int, out_dir: Path
) -> dict[str, Any]:
    """One simulated session of ``person`` in ``setting`` with ``seed`` into ``out_dir`` (made
    here; it must not exist); its summary."""
    config = setting.config(person.participant, seed)
    out_dir.mkdir(parents=True)
    started = time.perf_counter()
    inputs, events = _Lines(out_dir / INPUTS_NAME), _Lines(out_dir / EVENTS_NAME)
    log = StepLog(out_dir / SESSION_LOG_NAME)
    player: FittedPlayer | None = None

    def on_event(kind: str, fields: dict[str, Any]) -> None:
        events.write({"event": kind, **fields})
        if kind in ("handed_back", "watchdog") and player is not None:
            player.handed_back()

    from robin_sim.live.run import live_parts  # the live session's own parts

    spec = config.run_spec()
    parts, participant = live_parts(config, on_event)
    world = parts.world
    assert isinstance(world, PhysicalWorld)

    def log_input(raw: dict[str, Any], error: str, sim_time: float) -> None:
        row = {"sim_time": round(sim_time, 4), "raw": raw, "accepted": not error, "error": error}
        inputs.write(row)

    player = FittedPlayer(person, participant, np.random.default_rng(seed), log_input)
    totals = EpisodeTotals(timeout_s=spec.person.handover_timeout)
    book = StepBook(parts, world, log, totals, strict=False)

    def booked(record: StepRecord) -> None:
        book.add(record)
        participant.legs_delivered = record.legs_delivered
        assert player is not None
        player.gave_turn()

    def tick(sim: Any) -> None:
        participant.poll()
        assert player is not None
        player(sim)
        holding = participant.verdict_pending
        seconds, actions = setting.block_seconds, setting.block_actions
        capped = (seconds is not None and world.time >= seconds) or (
            actions is not None and participant.actions_started > actions
        )
        if capped and not holding:
            raise Stopped("capped")
        if participant.ended and not holding and participant.phase != "waiting_for_gesture":
            raise Stopped("ended")

    observer = _Observer(LiveStatus(config), participant, None, booked)
    observer.player = player
    remove = world.sim.add_observer(tick)
    status, error = "failed", ""
    try:
        for record in steps(
            parts.learner, participant, parts.detector, world, observer=observer, **parts.options
        ):
            if record is not observer.last:  # a repeat request: booked here, as live
                booked(record)
        done = participant.legs_delivered >= participant.legs_total
        status = "finished" if done else "ended"
    except Stopped as stopped:
        status = stopped.status
    except Exception as problem:  # saved as failed, with the error (as a live session is)
        error = str(problem) if isinstance(problem, RobinPilError) else repr(problem)
    finally:
        remove()
        inputs.close()
        events.close()
        log.close()
    summary = run_summary(
        spec=spec,
        run=parts,
        totals=totals,
        world=world,
        wall=time.perf_counter() - started,
        status=status,
        error=error,
    )
    summary["live"] = {
        "participant": person.participant,
        "session": out_dir.name,
        "condition": setting.system,
        "seed": seed,
        "handover_types": None if setting.handover_types is None else list(setting.handover_types),
        "feedback_window_s": setting.feedback_window,
        "limits": {"block_seconds": setting.block_seconds, "block_actions": setting.block_actions},
        "simulated": True,
    }
    write_json_atomic(out_dir / SUMMARY_NAME, summary)
    return summary
