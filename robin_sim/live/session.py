"""One live session: a participant in the loop, physics paced, frames streamed, logged.

:class:`LiveSession` builds the run's parts as an episode does (the system's learner, the exact
detector: a click is what it is; the scenario and the block's handover types; the seed) with a
:class:`~robin_sim.live.participant.LiveParticipant` in the scripted person's place, and runs
:func:`pil.task.runner.steps` in a physics thread, paced by :class:`~robin_sim.live.pacing.Pacer`
with frames from :class:`~robin_sim.live.frames.FrameStream`. Each step is logged and counted
by the episode's own :class:`~robin_sim.episode.run.StepBook`. Messages come from any thread
(:meth:`LiveSession.receive` / :meth:`LiveSession.submit`) and are written to ``inputs.jsonl``;
:meth:`LiveSession.stop` ends the session between two ticks and saves everything
(:mod:`robin_sim.live.files`). A step is logged and counted as soon as the learner has its
feedback (the loop's observer ``received``), before the participant carries a delivered leg
away, so a stop at any moment keeps every step the learner has received. For the experimenter,
:meth:`LiveSession.pause` holds physics between two ticks and :meth:`LiveSession.note` saves a
timestamped note in the session folder.
"""

from __future__ import annotations

import threading
import time
from collections import deque
from collections.abc import Callable, Mapping
from typing import Any

from pil.errors import RobinPilError
from pil.task.detector import CAMERAS
from pil.task.records import StepRecord
from pil.task.runner import steps
from robin_sim.live.acting import apply_input, apply_reading
from robin_sim.live.booking import Booking, tail_entry
from robin_sim.live.capping import BlockWatch
from robin_sim.live.config import LiveConfig
from robin_sim.live.files import SessionFiles, session_folder
from robin_sim.live.frames import Frame, FrameHub
from robin_sim.live.holds import Holds
from robin_sim.live.inputs import LiveInput, LiveInputError, parse_input
from robin_sim.live.limits import BlockLimits
from robin_sim.live.mirror import HandMirror
from robin_sim.live.participant import LiveParticipant
from robin_sim.live.picking import Picker
from robin_sim.live.run import LiveRun, pacing_figures
from robin_sim.live.status import LiveStatus
from robin_sim.live.webcam import Webcam
from robin_sim.person.body import PhysicalBody

__all__ = ["Frame", "LiveConfig", "LiveSession"]
# capped: a study block that reached its time or action cap (robin_sim.live.capping)
STATUSES = ("finished", "ended", "capped", "closed", "interrupted", "failed")
STOP_WAIT_S = 60.0  # s stop() waits for the physics thread to save
LOG_TAIL = 40  # steps kept for the experimenter's view
PAUSE_POLL_S = 0.05  # s between looks at the pause while paused


class SessionStopped(BaseException):
    """Raised in the physics thread between two ticks to end the session (not an error)."""

    def __init__(self, status: str) -> None:
        super().__init__(status)
        self.status = status


class LiveSession:
    """A live session (see the module doc and the live page's contract)."""

    def __init__(self, config: LiveConfig) -> None:
        self.config = config.checked()
        self.out_dir = session_folder(self.config)  # refuses an existing folder
        self.done = threading.Event()
        self.hub = FrameHub()
        self.view = LiveStatus(self.config)
        self.view.session = self.out_dir.name
        self._lock = threading.Lock()
        self._stop_status: str | None = None
        self._summary: dict[str, Any] | None = None
        self._thread: threading.Thread | None = None
        self._participant: LiveParticipant | None = None
        self._picker: Picker | None = None
        self._pacer: Any = None
        self._run_parts: LiveRun | None = None
        self._files: SessionFiles | None = None
        self.holds = Holds()  # physics holds: paused, the page away, the participant inactive
        self._paused = self.holds.held
        caps = self.config.limits
        self.caps = (
            BlockWatch(caps, lambda on: self.holds.hold("inactive", on), self.log_event)
            if caps != BlockLimits()
            else None
        )
        self.log_tail: deque[dict[str, Any]] = deque(maxlen=LOG_TAIL)  # the newest steps
        # --webcam: the participant's hand read from the tracker's landmarks (None: off)
        self.webcam = (
            Webcam(
                self.config.width,
                self.config.height,
                calibrate=self.config.calibrate,
                eyes_read=self.config.detector == CAMERAS,
            )
            if self.config.webcam
            else None
        )

    # --- the contract --------------------------------------------------------------------------
    def start(self) -> None:
        """Make the session's folder and start the physics thread."""
        with self._lock:
            if self._thread is not None or self.done.is_set():
                raise RobinPilError(f"session {self.out_dir} has been started or stopped already")
            self._files = SessionFiles(self.out_dir, self.config)  # the folder: new, or refused
            self._thread = threading.Thread(target=self._run, name="live-physics", daemon=True)
            self._thread.start()

    def receive(self, raw: str | bytes | Mapping[str, Any]) -> LiveInput:
        """Check and act on a raw message from the page (logged either way); its input.
        :class:`LiveInputError` says what was wrong."""
        try:
            item = parse_input(raw, self.config.width, self.config.height)
        except LiveInputError as error:
            self.record_input(raw, str(error))
            raise
        self.submit(item)
        return item

    def submit(self, item: LiveInput) -> None:
        """Act on a checked message (thread-safe; logged with wall time).
        :class:`LiveInputError` when it cannot be acted on now (says why)."""
        if item.kind == "hand":
            self._hand(item)
            return
        if self.caps is not None:
            self.caps.input()
        try:
            self._act(item)
        except LiveInputError as error:
            self.record_input(item.as_dict(), str(error))
            raise
        except Exception as problem:  # logged and refused: the session goes on
            refused = LiveInputError(f"{item.kind}: could not be acted on ({problem!r:.200})")
            self.record_input(item.as_dict(), str(refused))
            raise refused from None
        self.record_input(item.as_dict(), "")

    def subscribe(self, callback: Callable[[Frame], None]) -> Callable[[], None]:
        """Call ``callback`` (in the physics thread) for each new frame; returns unsubscribe."""
        return self.hub.subscribe(callback)

    def latest_frame(self) -> Frame | None:
        """The last frame streamed (None before the first)."""
        return self.hub.latest

    @property
    def body(self) -> PhysicalBody | None:
        """The participant's simulated body once the scene is built (None before): its hand
        (``body.hand``) and the world (``body.world``), to read physics, not to drive it."""
        participant = self._participant
        return None if participant is None else participant.body

    @property
    def mirror(self) -> HandMirror | None:
        """What drives the person's hand from the webcam's readings (None: no webcam, or the
        scene not built yet); its ``errors_mm`` say how closely the fingertips follow."""
        run = self._run_parts
        return None if run is None else run.mirror

    @property
    def picker(self) -> Picker | None:
        """What resolves clicks (None before the scene is built); its ``project`` maps a world
        point to the frame pixel where it is seen."""
        return self._picker

    def status(self) -> dict[str, Any]:
        """Where the session stands, JSON-ready (thread-safe)."""
        participant, summary, pacer = self._participant, self._summary, self._pacer
        status = self.view.status(participant, None if summary is None else summary["status"])
        status["behind_s"] = None if pacer is None else round(pacer.behind_s, 3)  # lost pace
        run = self._run_parts  # what the stream sends now (lowered on a busy machine)
        status["stream"] = None if run is None else run.governor.state(self.config.fps)
        files = self._files
        # inputs taken so far: the page clears a shown error once this grows
        status["inputs_accepted"] = 0 if files is None else files.inputs - files.rejected
        status["paused"] = self.paused
        status["webcam"] = None if self.webcam is None else self.webcam.status()
        status["notice"] = "" if participant is None else participant.notice
        if self.caps is not None and self.caps.notice():
            status["notice"] = self.caps.notice()
        status["practice"] = self.config.practice
        left = None if participant is None else participant.window_left()
        status["feedback_left_s"] = None if left is None else round(left, 1)
        # "That was wrong": sim seconds left to take back the action that stood last
        back = None if participant is None else participant.take_back_left()
        status["take_back_left_s"] = None if back is None else round(back, 1)
        status["page_away"] = "page" in self.holds
        if self.paused and status["phase"] != "done":
            status["message"] = self.holds.message()
        return status

    def stop(self, status: str = "ended") -> dict[str, Any]:
        """End the session between two ticks and save everything; the summary (idempotent:
        the first status given stands)."""
        if status not in STATUSES:
            raise RobinPilError(f"unknown session status {status!r}; valid: {', '.join(STATUSES)}")
        with self._lock:
            if self._stop_status is None:
                self._stop_status = status
            thread = self._thread
            if thread is None:  # never started: nothing to save
                self.done.set()
                self._summary = {"status": self._stop_status, "error": "", "started": False}
                return self._summary
        if thread is threading.current_thread():
            return {"status": self._stop_status, "saving": True}  # saved when the tick returns
        self.done.wait(STOP_WAIT_S)
        return dict(self._summary or {"status": self._stop_status, "saving": True})

    # --- the experimenter ----------------------------------------------------------------------
    def pause(self, paused: bool) -> None:
        """The experimenter holds physics (and the stream) between two ticks, or lets it run
        on (thread-safe; a page that is away still holds it)."""
        self.holds.hold("experimenter", paused)

    def away(self, away: bool) -> None:
        """The participant's page lost its connection (physics holds: no action runs and no
        feedback window passes unseen), or came back (thread-safe)."""
        self.holds.hold("page", away)

    @property
    def paused(self) -> bool:
        """Physics holds (the experimenter paused, or the participant's page is away)."""
        return self._paused.is_set()

    def note(self, text: str) -> dict[str, Any]:
        """Save an experimenter's note with its time in the session folder; the entry."""
        files, participant = self._files, self._participant
        if files is None:
            raise LiveInputError(
                "note: this block has not started, so it has no folder yet; "
                "write the note once it runs"
            )
        sim_time = None if participant is None else round(participant.body.world.time, 4)
        return files.log_note(text, sim_time)

    def log_event(self, kind: str, fields: dict[str, Any]) -> None:
        """One line of the session's ``events.jsonl`` (with the sim time; nothing before the
        session's folder exists)."""
        files, participant = self._files, self._participant
        if files is None:
            return
        sim_time = None if participant is None else round(participant.body.world.time, 4)
        files.log_event(kind, {"sim_time": sim_time, **fields})

    def recent_events(self) -> list[dict[str, Any]]:
        """The newest lines of ``events.jsonl`` but the frequent ``acts`` (for the
        experimenter's view)."""
        files = self._files
        return [] if files is None else list(files.recent_events)

    def pacing(self) -> dict[str, Any]:
        """The stream's and the pacer's figures now (for the experimenter)."""
        return pacing_figures(self._run_parts, self.config.speed, self.paused)

    # --- messages ------------------------------------------------------------------------------
    def reading_reply(self) -> dict[str, Any] | None:
        """The page's answer to the last hand reading (None without one)."""
        webcam = self.webcam
        if webcam is None or webcam.last is None:
            return None
        return webcam.reply(webcam.last)

    def _hand(self, item: LiveInput) -> None:
        """A tracker reading: read, acted on if it decides a gesture, and logged with what
        became of it (:func:`~robin_sim.live.acting.apply_reading`)."""
        try:
            reading = apply_reading(
                item, self.webcam, self._participant, self._picker, self.view, self.done.is_set()
            )
        except LiveInputError as problem:
            self.record_input(item.as_dict(), str(problem))
            raise
        run = self._run_parts
        if run is not None and run.mirror is not None and item.hand is not None:
            run.mirror.take(item.hand)  # applied on the physics thread at the next tick
        self.record_input(item.as_dict(), "", reading=reading)

    def _act(self, item: LiveInput) -> None:
        if self.done.is_set():
            raise LiveInputError("the session has ended; nothing more is taken")
        apply_input(item, self._participant, self._picker, self.webcam, self.view)

    def record_input(self, raw: object, error: str, reading: dict[str, Any] | None = None) -> None:
        """One line of ``inputs.jsonl`` (``error`` empty: accepted), also for messages that
        never reach :meth:`receive`: over the rate limit, a questionnaire's (none before the
        session's folder exists)."""
        files, participant = self._files, self._participant
        sim_time = None if participant is None else round(participant.body.world.time, 4)
        if files is not None:
            files.log_input(raw, error, sim_time, reading=reading)

    # --- the physics thread --------------------------------------------------------------------
    def _on_tick(self, _: object) -> None:
        participant = self._participant
        # A verdict given but not yet received by the learner (the thumb being shown): the stop
        # waits the moment until the step is logged, so no approved step is ever lost.
        holding = participant is not None and participant.verdict_pending
        if self._stop_status is not None and not holding:
            raise SessionStopped(self._stop_status)
        if self._paused.is_set() and not holding:
            self._hold()
        if participant is not None:
            participant.poll()
            caps = self.caps
            if caps is not None:
                world = participant.body.world
                capped = caps.tick(world.time, participant.actions_started, participant.phase)
                if capped and not holding:
                    raise SessionStopped("capped")
            if participant.ended and not holding and participant.phase != "waiting_for_gesture":
                # "end" while the robot acts or waits for a thumb: no verdict is made up
                raise SessionStopped("ended")

    def _hold(self) -> None:
        """Wait while paused (a stop or the participant's End still ends the session); the
        pacer skips the pause."""
        started = time.monotonic()
        participant = self._participant
        while self._paused.is_set() and self._stop_status is None:
            if participant is not None:
                participant.poll()  # the participant's End still ends the session
                if participant.ended:
                    break
            time.sleep(PAUSE_POLL_S)
        if self._pacer is not None:
            self._pacer.skip(time.monotonic() - started)
        if self._stop_status is not None:
            raise SessionStopped(self._stop_status)

    def _run(self) -> None:
        files = self._files
        assert files is not None
        status, error, run = "failed", "", None
        try:
            run = LiveRun(self.config, files.out_dir, self.hub, self._on_tick, self._event)
            with run:
                self._participant, self._picker = run.participant, run.picker
                self._pacer, self._run_parts = run.pacer, run
                self.view.table = getattr(run.parts.learner, "table", None)
                if self.webcam is not None:
                    self.webcam.start()
                    if run.eyes is not None:  # no eye offer while the landmarks read a thumb
                        run.eyes.landmarks = self.webcam.hand_label
                self._on_tick(None)  # a stop during start-up
                parts = run.parts
                observer = Booking(
                    self.view, run.participant, self.webcam, lambda r: self.book(run, r)
                )
                for record in steps(
                    parts.learner,
                    run.participant,
                    parts.detector,
                    run.world,
                    observer=observer,
                    **parts.options,
                ):
                    if record is not observer.last:  # a repeat request: no feedback to receive
                        self.book(run, record)
            done = run.participant.legs_delivered >= run.participant.legs_total
            status = "finished" if done else "ended"
        except SessionStopped as stopped:
            status = stopped.status
        except Exception as problem:  # saved as failed, with the error
            error = str(problem) if isinstance(problem, RobinPilError) else repr(problem)
        finally:
            if run is not None:
                run.close()  # the MP4 is complete from here on
            vision = None if self.webcam is None else self.webcam.summary()
            if vision is not None and run is not None and run.eyes is not None:
                vision["eyes"] = run.eyes.summary()  # what Robin's eyes read of the hand
            limits = None if self.caps is None else self.caps.status()
            self._summary = files.save(status, error, run, vision=vision, limits=limits)
            self.done.set()

    def _event(self, kind: str, fields: dict[str, Any]) -> None:
        """What the participant did of itself, to ``events.jsonl``; a step taken back is
        marked in the experimenter's tail of the log."""
        files = self._files
        if files is not None:
            files.log_event(kind, fields)
        if kind == "take_back" and fields.get("done"):
            for k, entry in enumerate(self.log_tail):  # a new dict: the view may read the old
                if entry.get("t") == fields.get("t"):
                    self.log_tail[k] = {**entry, "taken_back": True}

    def book(self, run: LiveRun, record: StepRecord) -> None:
        """Log and count ``record`` (the learner has its feedback)."""
        entry = run.book.add(record)
        self.log_tail.append(tail_entry(entry))
        run.participant.legs_delivered = record.legs_delivered
        self.view.finished(record, run.totals)
