"""A physical episode: the scripted person gestures, the PIL learner decides, Robin acts in MuJoCo.

The episode drives the same learner, person, detector and scenario files as the learner-only study
(:func:`robin_sim.episode.physical_assembly.assemble_physical`, :func:`pil.task.runner.steps`); only
the world differs (:class:`robin_sim.robot.world.PhysicalWorld`). With the same seed and every
action succeeding physically, its decisions equal the learner-only run's. It writes
``episode.jsonl`` (a line per step, flushed as it happens), ``summary.json`` and, unless ``video``
is off, ``episode.mp4``. Ctrl-C leaves a playable MP4, the log of every finished
step and a summary marked interrupted.
"""

from __future__ import annotations

import time
from collections.abc import Iterator
from contextlib import ExitStack
from typing import Any

from tqdm import tqdm

from pil.errors import RobinPilError
from pil.file_names import EPISODE_LOG_NAME, SUMMARY_NAME, VIDEO_NAME
from pil.outdir import claimed_out_dir
from pil.task.assemble import Run
from pil.task.records import StepRecord
from robin_sim.episode.book import StepBook, run_summary, vision_of
from robin_sim.episode.config import (
    FINISHED,
    TIME_LIMIT,
    EpisodeConfig,
    EpisodeError,
    EpisodeSpec,
)
from robin_sim.episode.interrupts import InterruptGuard
from robin_sim.episode.log import SUMMARY_RESERVE, StepLog, write_json_atomic
from robin_sim.episode.physical_assembly import assemble_physical
from robin_sim.episode.render_checks import RenderChecks
from robin_sim.episode.summary import EpisodeTotals
from robin_sim.episode.view import EpisodeView
from robin_sim.robot.world import PhysicalWorld

__all__ = [
    "EpisodeConfig",
    "EpisodeError",
    "EpisodeSpec",
    "StepBook",
    "run_episode",
    "run_summary",
]


def run_episode(config: EpisodeConfig | EpisodeSpec) -> dict[str, Any]:
    """Run one episode, write its files under its ``out`` folder and return the summary.

    An :class:`EpisodeConfig` is parsed here (:func:`~robin_sim.episode.config.parse_episode`:
    bad input is refused before anything is built or written); an :class:`EpisodeSpec` is
    used as it is.
    """
    spec = config if isinstance(config, EpisodeSpec) else config.spec()
    video, scenario = spec.video, spec.run.scenario
    parts = assemble_physical(spec)  # the scenario layout's world, the body, learner, detector
    world = parts.world
    if not isinstance(world, PhysicalWorld):
        raise EpisodeError(f"an episode runs in a physical world, got {type(world).__name__}")
    if video.record:
        from robin_sim.render.renderer import camera_id

        camera_id(world.sim.model, video.camera)
    legs_total = scenario.tables * scenario.legs_per_table
    # Ctrl-C / SIGTERM from here on: acted on between ticks
    with InterruptGuard() as guard, ExitStack() as claim:
        # the first thing written: the folder, locked (a second run into it is refused here)
        out = claim.enter_context(claimed_out_dir(spec.out))
        view = EpisodeView(table=parts.learner.table if video.policy_panel else None)
        totals = EpisodeTotals(timeout_s=spec.run.person.handover_timeout)
        started = time.perf_counter()
        status, error, recorder = "running", "", None
        try:
            # an earlier run's files are replaced now, so that a kill -9 leaves only this run's
            write_json_atomic(
                out / SUMMARY_NAME,
                _summary(spec, totals, parts, world, started, status, error, None),
                reserve=SUMMARY_RESERVE,
            )
            for stale in (EPISODE_LOG_NAME, VIDEO_NAME):
                (out / stale).unlink(missing_ok=True)
            with ExitStack() as stack:
                stack.callback(world.sim.add_observer(guard.check))
                if video.record:
                    from robin_sim.episode.recorder import VideoRecorder  # needs the GL backend
                    from robin_sim.render.state_log import STATES_NAME

                    recorder = stack.enter_context(
                        VideoRecorder(
                            world.sim,
                            view,
                            out / VIDEO_NAME,
                            layout=world.layout,
                            width=video.width,
                            height=video.height,
                            fps=video.fps,
                            camera=video.camera,
                            shadows=video.shadows,
                            # a signal already noted: one frame, rendered here, is enough
                            render_workers=0 if guard.requested else video.render_workers,
                            eye_inset=video.eye_inset,
                            readings=vision_of(parts),
                            states=out / STATES_NAME,
                        )
                    )
                checks = stack.enter_context(RenderChecks(world, enabled=spec.verify))
                log = stack.enter_context(StepLog(out / EPISODE_LOG_NAME))
                view.update(legs_total=legs_total)
                bar = stack.enter_context(progress_bar(legs_total, spec.progress))
                guard.check()  # a signal during start-up
                book = StepBook(parts, world, log, totals, checks)
                limit = spec.time_limit_s, legs_total
                stopped = _play(parts.steps(view), book, view, bar, limit)
            status = TIME_LIMIT if stopped else FINISHED  # the video and the log are closed now
            guard.check()  # a signal while the video was being finished
        except KeyboardInterrupt:
            status = "interrupted"
            raise
        except Exception as problem:
            detail = str(problem) if isinstance(problem, RobinPilError) else repr(problem)
            status, error = "failed", detail
            raise
        finally:
            summary = _summary(spec, totals, parts, world, started, status, error, recorder)
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
    limit: tuple[float, int],
) -> bool:
    """Check, log and count every step (:class:`StepBook`); stop at a hand-state mismatch.
    ``limit``: the simulated seconds and the legs of the episode; True when the simulated time
    reached those seconds with legs still to deliver (no step is taken after that one)."""
    limit_s, legs_total = limit
    for record in records:
        view.finished(record)
        if record.action is None:
            view.asked_to_repeat(record)
        book.add(record)
        bar.update(record.legs_delivered - bar.n)
        bar.set_postfix(step=record.t, sim=f"{book.world.time:.0f}s")
        if book.world.time >= limit_s and record.legs_delivered < legs_total:
            return True
    return False


def _summary(
    spec: EpisodeSpec,
    totals: EpisodeTotals,
    run: Run,
    world: PhysicalWorld,
    started: float,
    status: str,
    error: str,
    recorder: Any,
) -> dict[str, Any]:
    summary = run_summary(
        spec=spec.run,
        run=run,
        totals=totals,
        world=world,
        wall=time.perf_counter() - started,
        status=status,
        error=error,
    )
    summary["sim_time_limit_s"] = spec.time_limit_s
    if recorder is not None:
        timing, video = recorder.timing, spec.video
        summary["video"] = {
            "path": VIDEO_NAME,  # relative to the run's folder, as every path of a summary
            "camera": video.camera,
            "size": [video.width, video.height],
            "fps": video.fps,
            "frames": recorder.writer.frames_written,  # after a full disk: the frames kept
            "render_s": round(timing.render_s, 3),
            "encode_s": round(timing.encode_s, 3),
        }
    return summary
