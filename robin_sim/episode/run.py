"""A physical episode: the scripted person gestures, the PIL learner decides, Robin acts in MuJoCo.

The episode drives the same learner, person, detector and scenario files as the learner-only
study (:func:`pil.task.parts.build_parts`, :func:`pil.task.runner.steps`); only the world differs
(:class:`robin_sim.robot.world.PhysicalWorld`). With the same seed and every action succeeding
physically, its decisions equal the learner-only run's. It writes ``episode.jsonl`` (a line per
step, flushed as it happens), ``summary.json`` and, unless ``video`` is off, ``episode.mp4``.
Ctrl-C leaves a playable MP4, the log of every finished step and a summary marked interrupted.
"""

from __future__ import annotations

import time
from collections.abc import Iterator
from contextlib import ExitStack
from dataclasses import replace
from pathlib import Path
from typing import TYPE_CHECKING, Any

from tqdm import tqdm

from pil.errors import RobinPilError
from pil.experiments.systems import SYSTEMS, test_parts
from pil.outdir import claimed_out_dir
from pil.task.parts import PERSON_PARAMS, RunParts
from pil.task.records import StepRecord
from pil.task.runner import steps
from pil.types import Hand, hand_after
from robin_sim.episode.config import EpisodeConfig, EpisodeError, EpisodeTask
from robin_sim.episode.interrupts import InterruptGuard
from robin_sim.episode.log import SUMMARY_RESERVE, StepLog, write_json_atomic
from robin_sim.episode.reading import vision_detector
from robin_sim.episode.render_checks import RenderChecks
from robin_sim.episode.summary import EpisodeTotals
from robin_sim.episode.view import EpisodeView
from robin_sim.person.body import PhysicalBody
from robin_sim.robot.world import PhysicalWorld

if TYPE_CHECKING:
    from robin_sim.vision.detector import VisionDetector

LOG_NAME, SUMMARY_NAME, VIDEO_NAME = "episode.jsonl", "summary.json", "episode.mp4"
__all__ = ["EpisodeConfig", "EpisodeError", "EpisodeTask", "run_episode"]


def _expected_hand(before: Hand, record: StepRecord, physical: Hand) -> Hand:
    """The hand state the learner's approved actions imply after ``record``; after an action
    that was not approved, what physics shows (a drop, a leg caught by a rejected close)."""
    if record.action is None:
        return before
    if record.feedback is None or not record.feedback.approves:
        return physical
    return hand_after(record.action, before)


def episode_parts(config: EpisodeConfig, task: EpisodeTask, world: PhysicalWorld) -> RunParts:
    """Learner, person (with a :class:`PhysicalBody` in ``world``) and detector of ``config``:
    the study's parts, so that the same seed gives the same decisions."""
    body = PhysicalBody(world, seed=config.seed)
    parts = test_parts(
        config.system, config.rate, config.seed, task.scenario, task.values, body=body
    )
    if task.vision is None:
        return parts
    return replace(parts, detector=vision_detector(world, body.display, task.vision, config.seed))


def _vision(parts: RunParts) -> VisionDetector | None:
    """The run's detector if it reads with the eye cameras (``--detector vision``)."""
    from robin_sim.vision.detector import VisionDetector

    return parts.detector if isinstance(parts.detector, VisionDetector) else None


def episode_records(
    parts: RunParts, world: PhysicalWorld, view: EpisodeView | None = None
) -> Iterator[StepRecord]:
    """The step loop of ``parts`` on ``world``; ``view`` (if given) follows each step."""
    yield from steps(
        parts.learner, parts.person, parts.detector, world, observer=view, **parts.options
    )


def run_episode(config: EpisodeConfig) -> dict[str, Any]:
    """Run one episode, write its files under ``config.out`` and return the summary."""
    config = config.checked()  # bad input: refused here, before anything is built or written
    task = EpisodeTask.of(config)
    world = PhysicalWorld(task.layout)
    if config.video:
        from robin_sim.render.renderer import camera_id, check_frame_size

        check_frame_size(world.sim.model, config.width, config.height)
        camera_id(world.sim.model, config.camera)
    parts = episode_parts(config, task, world)  # a bad camera condition is refused here
    # Ctrl-C / SIGTERM from here on: acted on between ticks
    with InterruptGuard() as guard, ExitStack() as claim:
        # the first thing written: the folder, locked (a second run into it is refused here)
        out = claim.enter_context(claimed_out_dir(config.out))
        view = EpisodeView(table=parts.learner.table if config.policy_panel else None)
        totals = EpisodeTotals(timeout_s=float(task.values["handover_timeout"]))
        started = time.perf_counter()
        status, error, recorder = "running", "", None
        try:
            # an earlier run's files are replaced now, so that a kill -9 leaves only this run's
            write_json_atomic(
                out / SUMMARY_NAME,
                _summary(config, task, totals, parts, world, started, status, error, None),
                reserve=SUMMARY_RESERVE,
            )
            for stale in (LOG_NAME, VIDEO_NAME):
                (out / stale).unlink(missing_ok=True)
            with ExitStack() as stack:
                stack.callback(world.sim.add_observer(guard.check))
                if config.video:
                    from robin_sim.episode.recorder import VideoRecorder  # needs the GL backend
                    from robin_sim.render.state_log import STATES_NAME

                    recorder = stack.enter_context(
                        VideoRecorder(
                            world.sim,
                            view,
                            out / VIDEO_NAME,
                            layout=task.layout,
                            width=config.width,
                            height=config.height,
                            fps=config.fps,
                            camera=config.camera,
                            shadows=config.shadows,
                            # a signal already noted: one frame, rendered here, is enough
                            render_workers=0 if guard.requested else config.render_workers,
                            eye_inset=config.eye_inset,
                            readings=_vision(parts),
                            states=out / STATES_NAME,
                        )
                    )
                checks = stack.enter_context(RenderChecks(world, enabled=config.verify))
                log = stack.enter_context(StepLog(out / LOG_NAME))
                view.update(legs_total=task.legs_total)
                bar = stack.enter_context(progress_bar(task.legs_total, config.progress))
                guard.check()  # a signal during start-up
                book = StepBook(parts, world, log, totals, checks)
                _play(episode_records(parts, world, view), book, view, bar)
            status = "finished"  # the video and the log are closed by now
            guard.check()  # a signal while the video was being finished
        except KeyboardInterrupt:
            status = "interrupted"
            raise
        except Exception as problem:
            detail = str(problem) if isinstance(problem, RobinPilError) else repr(problem)
            status, error = "failed", detail
            raise
        finally:
            summary = _summary(config, task, totals, parts, world, started, status, error, recorder)
            write_json_atomic(out / SUMMARY_NAME, summary)
    return summary


def progress_bar(legs: int, enabled: bool = True, **options: Any) -> tqdm:
    """The episode's bar over legs. Its time left is the whole episode's: the mean wall time
    per leg so far times the legs to go (``smoothing=0``; tqdm's default weighs the last
    updates, and a step that delivers no leg made it read one leg's time)."""
    return tqdm(total=legs, desc="episode", unit="leg", disable=not enabled, smoothing=0, **options)


def _play(
    records: Iterator[StepRecord],
    book: StepBook,
    view: EpisodeView,
    bar: tqdm,
) -> None:
    """Check, log and count every step (:class:`StepBook`); stop at a hand-state mismatch."""
    for record in records:
        view.finished(record)
        if record.action is None:
            view.asked_to_repeat(record)
        book.add(record)
        bar.update(record.legs_delivered - bar.n)
        bar.set_postfix(step=record.t, sim=f"{book.world.time:.0f}s")


class StepBook:
    """Logs and counts each step of a physical run and checks the learner's hand state against
    physics (shared by the episode and the live session)."""

    def __init__(
        self,
        parts: RunParts,
        world: PhysicalWorld,
        log: StepLog,
        totals: EpisodeTotals,
        checks: RenderChecks | None = None,
        *,
        strict: bool = True,
    ) -> None:
        self.parts, self.world, self.log, self.totals, self.checks = (
            parts,
            world,
            log,
            totals,
            checks,
        )
        self.strict = strict  # False: a mismatch is logged and physics taken as it is
        self.hand = Hand.FREE  # what the learner's approved actions imply
        self._readings = getattr(parts.detector, "records", None)  # the eyes' readings, if any
        self._logged = 0

    def add(self, record: StepRecord) -> dict[str, Any]:
        """Log and count ``record``; its log entry. :class:`EpisodeError` when the learner's
        hand state and physics disagree (not ``strict``: ``hand_mismatch`` in the entry)."""
        world = self.world
        physical = world.hand()
        self.hand = _expected_hand(self.hand, record, physical)
        check = None if self.checks is None else self.checks.take()
        entry = _log_entry(record, world, check, physical)
        if physical is not self.hand and not self.strict:
            entry["hand_mismatch"] = self.hand.value  # what the approvals implied
            self.hand = physical
        if self._readings is not None:
            entry["vision"] = [reading.as_dict() for reading in self._readings[self._logged :]]
            self._logged = len(self._readings)
        self.log.write(entry)
        body = self.parts.person.body
        assert isinstance(body, PhysicalBody)
        ended = world.time if world.last_result is None else world.last_result.ended
        self.totals.add(record, entry, body.performed_at[record.gesture_count - 1], ended)
        if physical is not self.hand:
            raise EpisodeError(
                f"step {record.t}: the learner's hand state is {self.hand.value} but physics "
                f"reads {physical.value} ({record.detail or 'no detail'})"
            )
        return entry


def _log_entry(
    record: StepRecord, world: PhysicalWorld, check: dict[str, Any] | None, physical: Hand
) -> dict[str, Any]:
    entry = record.to_dict()
    entry["hand_physics"] = physical.value
    entry["sim_time"] = round(world.time, 4)
    entry["leg_positions"] = [[round(float(v), 4) for v in p] for p in world.leg_positions()]
    entry["palm_position"] = [round(float(v), 4) for v in world.human.palm_centre()]
    if check is not None:
        entry["render_check"] = check
    return entry


def _summary(
    config: EpisodeConfig,
    task: EpisodeTask,
    totals: EpisodeTotals,
    parts: RunParts,
    world: PhysicalWorld,
    started: float,
    status: str,
    error: str,
    recorder: Any,
) -> dict[str, Any]:
    summary = run_summary(
        config.system,
        config.rate,
        config.seed,
        task,
        totals,
        parts,
        world,
        time.perf_counter() - started,
        status,
        error,
    )
    if recorder is not None:
        timing = recorder.timing
        summary["video"] = {
            "path": str(Path(config.out) / VIDEO_NAME),
            "camera": config.camera,
            "size": [config.width, config.height],
            "fps": config.fps,
            "frames": recorder.writer.frames_written,  # after a full disk: the frames kept
            "render_s": round(timing.render_s, 3),
            "encode_s": round(timing.encode_s, 3),
        }
    return summary


def run_summary(
    system: str,
    rate: float,
    seed: int,
    task: EpisodeTask,
    totals: EpisodeTotals,
    parts: RunParts,
    world: PhysicalWorld,
    wall: float,
    status: str,
    error: str,
) -> dict[str, Any]:
    """The summary fields of a physical run (the episode's and the live session's)."""
    summary: dict[str, Any] = {
        "status": status,
        "error": error,
        "system": system,
        "system_name": SYSTEMS[system],
        "rate": rate,
        "seed": seed,
        "scenario": task.scenario.name,
        "tables": task.scenario.tables,
        "legs_total": task.legs_total,
        **totals.as_summary(world.person_contacts.events, parts.person.interventions, world.time),
        "person": {name: task.values[name] for name in PERSON_PARAMS},
        "sim_time_s": round(world.time, 3),
        "wall_time_s": round(wall, 3),
        "real_time_factor": round(world.time / wall, 3) if wall > 0 else None,
    }
    vision = _vision(parts)
    if vision is not None:
        summary["vision"] = vision.summary()
    return summary
