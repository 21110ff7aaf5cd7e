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
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from tqdm import tqdm

from pil.errors import RobinPilError, check_rate
from pil.experiments.systems import SYSTEMS, check_system, test_parts
from pil.task.parts import PERSON_PARAMS, RunParts, check_params, resolve_scenario
from pil.task.records import StepRecord
from pil.task.runner import steps
from pil.task.scenario import Scenario
from pil.types import Hand, hand_after
from robin_sim.episode.log import StepLog, write_json_atomic
from robin_sim.episode.render_checks import RenderChecks
from robin_sim.episode.summary import EpisodeTotals
from robin_sim.episode.view import EpisodeView
from robin_sim.model.scene import SceneLayout
from robin_sim.person.body import PhysicalBody
from robin_sim.robot.world import PhysicalWorld

LOG_NAME, SUMMARY_NAME, VIDEO_NAME = "episode.jsonl", "summary.json", "episode.mp4"


class EpisodeError(RobinPilError):
    """The episode cannot go on (e.g. the learner's hand state disagrees with physics)."""


@dataclass(frozen=True)
class EpisodeConfig:
    """Everything that defines an episode; the defaults are ``robin-pil episode``'s."""

    tables: int | None = None  # None: the scenario file's, but 1 for the default assembly
    rate: float = 1.0
    seed: int = 0
    system: str = "pil"
    scenario: str | Path | None = None  # an assembly YAML; default scenarios/assembly.yaml
    out: Path = Path("out")
    video: bool = True
    camera: str = "front"
    width: int = 640
    height: int = 480
    fps: int = 30
    shadows: bool = False  # shadows cost about 3x the render time on a CPU (llvmpipe)
    render_workers: int | None = None  # render processes; None: 2 (0 on one CPU), 0: in-process
    policy_panel: bool = True
    eye_inset: bool = True  # the robot's left-eye view as a small inset in the video
    verify: bool = True  # off-screen render checks after grasps, handovers and placements
    progress: bool = True
    params: Mapping[str, Any] = field(default_factory=dict)  # any of pil.task.parts.PARAMS

    def checked(self) -> EpisodeConfig:
        """Validate what can be validated before anything runs."""
        check_rate(self.rate)
        check_system(self.system)
        if self.tables is not None and (int(self.tables) != self.tables or self.tables < 1):
            raise RobinPilError(f"tables must be a whole number >= 1, got {self.tables!r}")
        return self


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
    return test_parts(config.system, config.rate, config.seed, task.scenario, task.values,
                      body=body)  # fmt: skip


def episode_records(
    parts: RunParts, world: PhysicalWorld, view: EpisodeView | None = None
) -> Iterator[StepRecord]:
    """The step loop of ``parts`` on ``world``; ``view`` (if given) follows each step."""
    yield from steps(
        parts.learner, parts.person, parts.detector, world, observer=view, **parts.options
    )


@dataclass(frozen=True)
class EpisodeTask:
    """What an episode's config resolves to: the scenario, its parameters and the scene layout."""

    scenario: Scenario
    values: Mapping[str, Any]
    layout: SceneLayout

    @property
    def legs_total(self) -> int:
        """Legs the person is to receive."""
        return self.scenario.tables * self.scenario.legs_per_table

    @classmethod
    def of(cls, config: EpisodeConfig) -> EpisodeTask:
        """Resolve ``config``: its scenario (tables default to 1 for the paper's assembly) and
        the scene layout (the scenario's ``layout`` section, else the default), checking that
        the layout has the legs and spots the person will point at."""
        tables = config.tables
        if tables is None and config.scenario is None:
            tables = 1  # the main job assembles one table of the paper's assembly
        values = check_params({**config.params, "tables": tables})
        scenario = resolve_scenario(config.scenario, values)
        layout = SceneLayout.from_mapping(scenario.layout) if scenario.layout else SceneLayout()
        if scenario.spots > len(layout.spots) or scenario.legs_per_table > len(layout.legs):
            raise EpisodeError(
                f"scenario {scenario.name!r} needs {scenario.spots} table spots and "
                f"{scenario.legs_per_table} legs per table, but its layout has "
                f"{len(layout.spots)} spots and {len(layout.legs)} legs; add them to its "
                "layout section or lower spots / legs_per_table"
            )
        return cls(scenario, values, layout)


def run_episode(config: EpisodeConfig) -> dict[str, Any]:
    """Run one episode, write its files under ``config.out`` and return the summary."""
    config = config.checked()
    task = EpisodeTask.of(config)
    out = Path(config.out)
    out.mkdir(parents=True, exist_ok=True)
    world = PhysicalWorld(task.layout)
    view = EpisodeView()
    parts = episode_parts(config, task, world)
    if config.policy_panel:
        view.table = parts.learner.table
    totals = EpisodeTotals(timeout_s=float(task.values["handover_timeout"]))
    started = time.perf_counter()
    status, error, recorder = "running", "", None
    try:
        with ExitStack() as stack:
            if config.video:
                from robin_sim.episode.recorder import (
                    VideoRecorder,  # renders: needs the GL backend
                )

                recorder = stack.enter_context(
                    VideoRecorder(
                        world.sim, view, out / VIDEO_NAME, layout=task.layout,
                        width=config.width, height=config.height, fps=config.fps,
                        camera=config.camera, shadows=config.shadows,
                        render_workers=config.render_workers, eye_inset=config.eye_inset,
                    )
                )  # fmt: skip
            checks = stack.enter_context(RenderChecks(world, enabled=config.verify))
            log = stack.enter_context(StepLog(out / LOG_NAME))
            view.update(legs_total=task.legs_total)
            bar = stack.enter_context(
                tqdm(total=task.legs_total, desc="episode", unit="leg", disable=not config.progress)
            )
            _play(episode_records(parts, world, view), parts, world, view, checks, log, bar,
                  totals)  # fmt: skip
        status = "finished"  # the video and the log are closed by now
    except KeyboardInterrupt:
        status = "interrupted"
        raise
    except RobinPilError as problem:
        status, error = "failed", str(problem)
        raise
    finally:
        summary = _summary(config, task, totals, parts, world, started, status, error, recorder)
        write_json_atomic(out / SUMMARY_NAME, summary)
    return summary


def _play(
    records: Iterator[StepRecord],
    parts: RunParts,
    world: PhysicalWorld,
    view: EpisodeView,
    checks: RenderChecks,
    log: StepLog,
    bar: tqdm,
    totals: EpisodeTotals,
) -> None:
    """Check, log and count every step; stop at a hand-state mismatch."""
    hand = Hand.FREE
    for record in records:
        if record.action is None:
            view.asked_to_repeat(record)
        physical = world.hand()
        hand = _expected_hand(hand, record, physical)
        entry = _log_entry(record, world, checks.take(), physical)
        log.write(entry)
        body = parts.person.body
        assert isinstance(body, PhysicalBody)
        ended = world.time if world.last_result is None else world.last_result.ended
        totals.add(record, entry, body.performed_at[record.gesture_count - 1], ended)
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
        **totals.as_summary(world.person_contacts.events, parts.person.interventions, world.time),
        "person": {name: task.values[name] for name in PERSON_PARAMS},
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
