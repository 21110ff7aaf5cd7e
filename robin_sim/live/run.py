"""The parts of one live session, built in its physics thread like an episode's.

:class:`LiveRun` builds, through the one assembly
(:func:`robin_sim.episode.physical_assembly.assemble_physical`, as the episode), the world of the
session's scenario, the simulated hand, the system's learner and the exact detector; then the
participant in the scripted person's place, the picker, the frame stream (MP4 included), the pacer
and the step log; with ``--webcam`` the mirror that lets the
participant's landmarks drive the person's hand (:mod:`.mirror`), and with ``--detector vision``
Robin's eyes on that hand (:mod:`.eye_watch`); the mirrored hand is held up where Robin reads
signs (:mod:`.show_hand`).
Build, use and close it in one thread: the renderers' OpenGL contexts belong to it.
"""

from __future__ import annotations

import time
from collections.abc import Callable
from dataclasses import replace
from pathlib import Path
from typing import Any

from pil.errors import RobinPilError

# the session's step log (an episode's is episode.jsonl), as the study's exports read it
from pil.experiments.sessions_load import SESSION_LOG_NAME as LOG_NAME
from pil.file_names import VIDEO_NAME  # the same file name as an episode's
from pil.task.assemble import Run
from pil.task.detector import CAMERAS
from pil.types import Action, Hand
from robin_sim.closing import ClosesOnExit
from robin_sim.control.simulator import Simulator
from robin_sim.episode.book import StepBook
from robin_sim.episode.log import StepLog
from robin_sim.episode.physical_assembly import assemble_physical
from robin_sim.episode.summary import EpisodeTotals
from robin_sim.figure.articulated import has_articulated_hand
from robin_sim.live.config import LiveConfig
from robin_sim.live.eye_watch import EyeWatch
from robin_sim.live.frames import FrameHub, FrameStream
from robin_sim.live.mirror import HandMirror
from robin_sim.live.pacing import Pacer
from robin_sim.live.participant import LiveParticipant
from robin_sim.live.picking import Picker
from robin_sim.live.quality import StreamGovernor
from robin_sim.live.show_hand import ShowHand
from robin_sim.person.body import LIVE, PhysicalBody
from robin_sim.render.state_log import STATES_NAME
from robin_sim.robot.world import PhysicalWorld


def live_parts(
    config: LiveConfig,
    on_event: Callable[[str, dict[str, Any]], None] | None = None,
) -> tuple[Run, LiveParticipant]:
    """The checked ``config``'s run (assembled as an episode, in a world of the scenario's
    layout, with the live body's tempo) with a :class:`LiveParticipant` in the scripted
    person's place: a live session's, or a simulated participant's
    (:mod:`robin_sim.fitted.session`)."""
    spec = config.run_spec()
    scripted = assemble_physical(spec, tempo=LIVE)  # the world of the scenario's layout too
    body = scripted.person.body
    assert isinstance(body, PhysicalBody)
    scenario = spec.scenario
    types, seen = [], set()
    for step in scripted.person.script:  # the block's handovers, in the scenario's order
        if step.intent.handover not in seen:
            seen.add(step.intent.handover)
            types.append(scenario.type_named(step.handover_type))
    anticipate = getattr(scripted.learner, "anticipate", None)  # baselines have none

    def robot_anticipates(previous: Action, hand: Hand) -> bool:
        return anticipate is not None and anticipate(previous, hand) is not None

    participant = LiveParticipant(
        body,
        types,
        scenario.legs_per_table,
        config.feedback_window,
        robot_anticipates,
        limits=config.watchdog,
        on_event=on_event,
    )
    # The participant in the scripted person's place (pil.task.person.Person); after the
    # watchdog's gestures handed back in a row, Robin proposes an action on the next one
    loop = replace(scripted.loop, ask_after=config.watchdog.handed_back + 1)
    return replace(scripted, person=participant, loop=loop), participant  # type: ignore[arg-type]


class LiveRun(ClosesOnExit):
    """World, parts, participant, picker, stream, pacer and log of a session (module doc)."""

    def __init__(
        self,
        config: LiveConfig,
        out_dir: Path,
        hub: FrameHub,
        hook: Callable[[Simulator], None],
        on_event: Callable[[str, dict[str, Any]], None] | None = None,
    ) -> None:
        self.config = config
        self.spec = config.run_spec()  # the checked config's learner side, typed
        self.parts, self.participant = live_parts(config, on_event)
        world = self.parts.world
        assert isinstance(world, PhysicalWorld)
        self.world = world
        self.body = self.participant.body
        # --webcam: the participant's landmarks drive the person's hand (robin_sim.live.mirror)
        self.mirror: HandMirror | None = None
        self.show_hand: ShowHand | None = None
        if config.webcam and has_articulated_hand(self.world.model):
            self.mirror = HandMirror(self.world.model, self.world.data)
            self.world.sim.add_controller(self.mirror.tick)  # after the hand's own blends
            # the mirrored hand held up where Robin reads signs, not hanging at rest
            self.show_hand = ShowHand(self.body.hand, self.mirror, self.body.tempo.hand_speed)
            self.world.sim.add_controller(self.show_hand.tick)
        # --detector vision: Robin's eyes read the mirrored hand (robin_sim.live.eye_watch)
        self.eyes: EyeWatch | None = None
        if config.detector == CAMERAS:
            if self.mirror is None:
                raise RobinPilError(
                    "--detector vision needs the articulated person's hand in the scene"
                )
            self.eyes = EyeWatch(self.world.model, self.world.data, self.mirror, self.spec.seed)
            self.eyes.participant = self.participant
            self.world.sim.add_controller(self.eyes.tick)  # after the mirror
        self.totals = EpisodeTotals(timeout_s=self.spec.person.handover_timeout)
        self.stream: FrameStream | None = None
        self.pacer: Pacer | None = None
        self.on_event = on_event
        self.log: StepLog | None = None
        try:
            self.picker = Picker(self.world.layout, config.width, config.height)
            self.stream = FrameStream(
                self.world.layout,
                hub,
                config.width,
                config.height,
                video=out_dir / VIDEO_NAME if config.video else None,
                video_fps=int(config.fps),
                eye_inset=config.eye_inset,
                render_workers=config.render_workers,
                eye_worker=config.eye_worker,
                reflections=config.reflections,
                spots=self.picker.spot_pixels(),
                on_state=self.picker.show,
                legs=self.picker.leg_pixels,
                states=out_dir / STATES_NAME if config.video else None,  # --no-video: none
            )
            self.log = StepLog(out_dir / LOG_NAME)
            # A participant may approve an action that failed: the hand is then what physics says
            # (the loop does the same), and the log notes the mismatch.
            self.book = StepBook(self.parts, self.world, self.log, self.totals, strict=False)
            self.governor = StreamGovernor(
                time.monotonic,
                self._stream_changed,
                adaptive=config.adaptive_stream,
                level=config.stream_level,
            )
            self.pacer = Pacer(
                self.world.sim, config.speed, config.fps, self.stream, hook, governor=self.governor
            )
        except BaseException:
            self.close()
            raise

    def _stream_changed(self, level: int, why: str) -> None:
        """The governor lowered or raised the stream: logged (``events.jsonl``)."""
        if self.on_event is not None:
            quality = self.governor.state(self.config.fps)
            self.on_event("stream", {"sim_time": round(self.world.time, 4), **quality, "why": why})

    def close(self) -> None:
        """Stop pacing, finish the stream and the MP4, close the log (idempotent)."""
        if self.eyes is not None:
            self.eyes.close()
        try:
            if self.pacer is not None:
                self.pacer.close()
        finally:
            try:
                if self.stream is not None:
                    self.stream.close()
            finally:
                if self.log is not None:
                    self.log.close()


def pacing_figures(run: LiveRun | None, speed: float, paused: bool) -> dict[str, Any]:
    """The stream's and the pacer's figures of a running session now."""
    stream = None if run is None else run.stream
    pacer = None if run is None else run.pacer
    stats = None if stream is None else stream.stats
    figures: dict[str, Any] = {
        "frames": 0,
        "stream_fps": None,
        "latency_ms": None,
        "frame_ms": None,
        "behind_s": None if pacer is None else round(pacer.behind_s, 3),
        "slips": None if pacer is None else pacer.slips,
        "lag_s": None if pacer is None else round(pacer.lag_s, 3),
        "speed": speed,
        "paused": paused,
        "stream": None if run is None else run.governor.state(run.config.fps),
    }
    if stats is not None and stats.frames:
        figures.update(
            frames=stats.frames,
            stream_fps=None if stats.fps is None else round(stats.fps, 2),
            latency_ms={"median": stats.latency_ms(0.5), "p95": stats.latency_ms(0.95)},
            frame_ms=round((stats.render_s + stats.encode_s) / stats.frames * 1000, 1),
        )
    return figures
