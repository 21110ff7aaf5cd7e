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
from collections.abc import Iterator, Mapping
from contextlib import ExitStack
from dataclasses import asdict, dataclass
from pathlib import Path
from typing import Any

from tqdm import tqdm

from pil.errors import RobinPilError
from pil.experiments.systems import SYSTEMS, test_parts
from pil.outdir import check_out_dir
from pil.task.runner import StepRecord, steps
from pil.types import Action, Hand
from robin_sim.episode.config import EpisodeConfig, EpisodeError, EpisodeTask
from robin_sim.episode.interrupts import InterruptGuard
from robin_sim.episode.log import StepLog, write_json_atomic
from robin_sim.episode.render_checks import RenderChecks
from robin_sim.person.narration import EpisodeView, Narrator
from robin_sim.robot.world import PhysicalWorld

LOG_NAME, SUMMARY_NAME, VIDEO_NAME = "episode.jsonl", "summary.json", "episode.mp4"
__all__ = ["EpisodeConfig", "EpisodeError", "EpisodeTask", "run_episode"]


@dataclass
class EpisodeTotals:
    """Running totals for the summary."""

    gestures: int = 0
    actions: int = 0
    rejected: int = 0
    corrections: int = 0  # instruction gestures whose state the learner corrected
    repeats: int = 0
    legs_delivered: int = 0  # Algorithm 1's count (handed over or placed)
    legs_to_person: int = 0
    legs_placed: int = 0
    physical_failures: int = 0
    render_checks: int = 0
    render_disagreements: int = 0


def _expected_hand(before: Hand, record: StepRecord) -> Hand:
    """The hand state that the learner's approved actions imply after ``record``."""
    if record.action is None or record.feedback is None or not record.feedback.approves:
        return before
    if record.action is Action.CLOSE:
        return Hand.OCCUPIED
    if record.action is Action.OPEN:
        return Hand.FREE
    return before


def episode_records(
    config: EpisodeConfig,
    task: EpisodeTask,
    world: PhysicalWorld,
    narrator: Narrator | None = None,
) -> Iterator[StepRecord]:
    """The step loop of ``config`` on ``world`` (learner, person and detector as in the study)."""
    parts = test_parts(config.system, config.rate, config.seed, task.scenario, task.values)
    if narrator is not None:
        narrator.table = parts.learner.table if config.policy_panel else None
    hook = None if narrator is None else narrator.before_action
    yield from steps(
        parts.learner, parts.person, parts.detector, world, before_action=hook, **parts.options
    )


def run_episode(config: EpisodeConfig) -> dict[str, Any]:
    """Run one episode, write its files under ``config.out`` and return the summary."""
    config = config.checked()  # bad input: refused here, before anything is built or written
    task = EpisodeTask.of(config)
    world = PhysicalWorld(task.layout, seed=config.seed)
    if config.video:
        from robin_sim.render.renderer import camera_id, check_frame_size

        check_frame_size(world.sim.model, config.width, config.height)
        camera_id(world.sim.model, config.camera)
    with InterruptGuard() as guard:  # Ctrl-C / SIGTERM from here on: acted on between ticks
        out = check_out_dir(config.out)  # the first thing written: the folder
        view = EpisodeView()
        narrator = Narrator(world, view)
        totals = EpisodeTotals()
        started = time.perf_counter()
        status, error, recorder = "running", "", None
        try:
            with ExitStack() as stack:
                stack.callback(world.sim.add_observer(guard.check))
                if config.video:
                    from robin_sim.episode.recorder import VideoRecorder  # needs the GL backend

                    recorder = stack.enter_context(
                        VideoRecorder(
                            world.sim, view, out / VIDEO_NAME, layout=task.layout,
                            width=config.width, height=config.height, fps=config.fps,
                            camera=config.camera, shadows=config.shadows,
                            render_workers=config.render_workers,
                        )
                    )  # fmt: skip
                checks = stack.enter_context(RenderChecks(world, enabled=config.verify))
                log = stack.enter_context(StepLog(out / LOG_NAME))
                view.update(legs_total=task.legs_total)
                bar = stack.enter_context(
                    tqdm(total=task.legs_total, desc="episode", unit="leg",
                         disable=not config.progress)
                )  # fmt: skip
                guard.check()  # a signal during start-up
                _play(episode_records(config, task, world, narrator), world, narrator, checks,
                      log, bar, totals)  # fmt: skip
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
            summary = _summary(config, task, totals, world, started, status, error, recorder)
            write_json_atomic(out / SUMMARY_NAME, summary)
    return summary


def _play(
    records: Iterator[StepRecord],
    world: PhysicalWorld,
    narrator: Narrator,
    checks: RenderChecks,
    log: StepLog,
    bar: tqdm,
    totals: EpisodeTotals,
) -> None:
    """Narrate, check, log and count every step; stop at a hand-state mismatch."""
    hand = Hand.FREE
    for record in records:
        narrator.after_step(record)
        hand = _expected_hand(hand, record)
        physical = world.hand()
        entry = _log_entry(record, world, checks.take(), physical)
        log.write(entry)
        _count(totals, record, entry)
        bar.update(record.legs_delivered - bar.n)
        bar.set_postfix(step=record.t, sim=f"{world.time:.0f}s")
        if physical is not hand:
            raise EpisodeError(
                f"step {record.t}: the learner's hand state is {hand.value} but physics "
                f"reads {physical.value} ({record.detail or 'no detail'})"
            )


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


def _count(totals: EpisodeTotals, record: StepRecord, entry: Mapping[str, Any]) -> None:
    new_gesture = record.gesture_count != totals.gestures
    totals.gestures = record.gesture_count
    totals.actions = record.t
    totals.legs_delivered = record.legs_delivered
    if record.action is None:
        totals.repeats += 1
        return
    totals.rejected += record.feedback is not None and not record.feedback.approves
    totals.corrections += new_gesture and record.corrected_gesture is not None
    totals.physical_failures += record.succeeded is False
    if record.delivered:
        to_person = record.state is not None and record.state.previous_action is Action.HUMAN
        totals.legs_to_person += to_person
        totals.legs_placed += not to_person
    check = entry.get("render_check")
    if check is not None:
        totals.render_checks += 1
        totals.render_disagreements += not check["agrees"]


def _summary(
    config: EpisodeConfig,
    task: EpisodeTask,
    totals: EpisodeTotals,
    world: PhysicalWorld,
    started: float,
    status: str,
    error: str,
    recorder: Any,
) -> dict[str, Any]:
    wall = time.perf_counter() - started
    summary: dict[str, Any] = {
        "status": status,
        "error": error,
        "system": config.system,
        "system_name": SYSTEMS[config.system],
        "rate": config.rate,
        "seed": config.seed,
        "scenario": task.scenario.name,
        "tables": task.scenario.tables,
        "legs_total": task.legs_total,
        **asdict(totals),
        "sim_time_s": round(world.time, 3),
        "wall_time_s": round(wall, 3),
        "real_time_factor": round(world.time / wall, 3) if wall > 0 else None,
    }
    if recorder is not None:
        timing = recorder.timing
        summary["video"] = {
            "path": str(Path(config.out) / VIDEO_NAME),
            "camera": config.camera,
            "size": [config.width, config.height],
            "fps": config.fps,
            "frames": timing.frames_written,
            "render_s": round(timing.render_s, 3),
            "encode_s": round(timing.encode_s, 3),
        }
    return summary
