"""The run behind the live page: one session, or a protocol's blocks one after another.

A session starts when the participant's (controlling) tab connects; a protocol block first shows
its instruction screen (phase ``instructions``) and starts on the tab's ``start`` message. When a
session ends by itself (``finished``, or ``ended`` by the participant), the next block's screen
follows; after the last one the run is over. With questionnaires (the protocol's), each block that
ends by itself is followed by them (phase ``questionnaire``), one at a time, before the next
block; the answers go to the block's ``questionnaires.jsonl``. A participant's page that does
not come back after losing its connection (the server waits for it) stops the running session
as ``closed``, a signal as ``interrupted``, and either ends the run: the server then stops.
A study's run (:mod:`robin_sim.lab`) has screens around its blocks (:mod:`robin_sim.live.screens`):
consent first (a decline ends the run, ``declined``), its demographics form, and the debrief
after the last block; each step is told to the study's journal.
"""

from __future__ import annotations

import asyncio
import logging
from collections.abc import Callable, Sequence
from typing import Any

from pil.experiments.study_export import DEMOGRAPHICS_NAME
from robin_sim.live.commands import Command
from robin_sim.live.inputs import LiveInputError, parse_input
from robin_sim.live.journal import block_fields
from robin_sim.live.questioning import Questioning
from robin_sim.live.questionnaires import Questionnaire
from robin_sim.live.screens import Screens, between_status
from robin_sim.live.session import Frame, LiveConfig, LiveSession

LOG = logging.getLogger(__name__)
POLL_S = 0.1  # how often the end of a running session is looked for
ASKED_AFTER = ("finished", "ended", "capped")  # sessions followed by the questionnaires
DECLINED = "declined"  # the run's outcome when the participant does not consent

FrameSink = Callable[[Frame], None]
Journal = Callable[[str, dict[str, Any]], None]  # a study's log across participants


class Conductor:
    """The sessions of one run, in order (each validated when the conductor is made)."""

    def __init__(
        self,
        configs: Sequence[LiveConfig],
        questionnaires: Sequence[Questionnaire] = (),
        screens: Screens | None = None,
        journal: Journal | None = None,
    ) -> None:
        """``screens``: a study's consent, demographics and debrief around the blocks;
        ``journal``: told of each step of the run (consent, blocks, answers, the end)."""
        if not configs:
            raise ValueError("a live run needs at least one session")
        self.configs = tuple(config.checked() for config in configs)
        self.sessions = tuple(LiveSession(config) for config in self.configs)
        self.width, self.height = self.configs[0].width, self.configs[0].height
        self.index = 0
        # waiting | consent | instructions | starting | running | questionnaire | debrief | done
        self.phase = "waiting"
        self.screens = screens or Screens()
        self.journal: Journal = journal or (lambda kind, fields: None)
        self._last_status = ""  # the last block's status, the run's outcome after the debrief
        self._asking = "block"  # what the questionnaire phase asks: "block" or "demographics"
        self.questionnaires = tuple(questionnaires)
        self._questioning: Questioning | None = None  # the block's questionnaires, while shown
        self.results: list[dict[str, Any]] = []  # each ended session's final status
        self.outcome: str | None = None
        self._loop: asyncio.AbstractEventLoop | None = None
        self._on_frame: FrameSink | None = None
        self._unsubscribe: Callable[[], None] | None = None
        self._over: asyncio.Event | None = None
        self._watcher: asyncio.Task[None] | None = None
        self._lock: asyncio.Lock | None = None
        self._away = False  # the participant's page has lost its connection

    @property
    def session(self) -> LiveSession:
        return self.sessions[self.index]

    def attach(self, loop: asyncio.AbstractEventLoop, on_frame: FrameSink) -> None:
        """Bind to the server's event loop; ``on_frame`` gets every frame (physics thread)."""
        self._loop, self._on_frame = loop, on_frame
        self._over, self._lock = asyncio.Event(), asyncio.Lock()

    # --- what the page shows ----------------------------------------------------------------
    def status(self) -> dict[str, Any]:
        """The running session's status, or the screen before / between / after sessions."""
        config = self.configs[self.index]
        extra = {
            "blocks": len(self.configs),
            "block_number": self.index + 1,
            "out_dir": str(self.session.out_dir),
            "practice": config.practice,
        }
        if self.phase == "running":
            return {**self.session.status(), **extra}
        last = self.results[-1] if self.results else {}
        asking = None if self._questioning is None else self._questioning.status()
        return between_status(self.phase, config, self.outcome, extra, last, self.screens, asking)

    def latest_frame(self) -> Frame | None:
        """The running session's newest frame (for a tab that has just connected)."""
        return self.session.latest_frame() if self.phase == "running" else None

    # --- events from the tabs and the server ------------------------------------------------
    async def participant_arrived(self) -> None:
        """The controlling tab connected: show the first screen or start the session."""
        if self.phase == "waiting":
            if self.screens.consent is not None:
                self.phase = "consent"
            else:
                await self._demographics()

    async def participant_left(self) -> None:
        """No participant's page is there any more (the server waited for it to come back):
        save what runs as ``closed``; the run is over."""
        await self._end("closed")

    def page_away(self, away: bool, **fields: Any) -> None:
        """The participant's page lost its connection (``away``) or came back: the running
        session holds meanwhile, and the event is logged in its ``events.jsonl``."""
        self._away = away
        if self.phase == "running":
            self.session.away(away)
            self.session.log_event("disconnected" if away else "reconnected", fields)

    def interrupt(self) -> None:
        """SIGINT / SIGTERM: save what runs as ``interrupted`` (from the event loop)."""
        assert self._loop is not None
        self._loop.create_task(self._end("interrupted"))

    async def receive(self, raw: str | bytes) -> dict[str, Any] | None:
        """One message from the participant's tab, checked by
        :func:`~robin_sim.live.inputs.parse_input`: a running session takes it (and logs it,
        refused or not, in ``inputs.jsonl``); else only ``start`` on an instruction screen is
        valid. :class:`LiveInputError` says what was wrong. Returns the reply to a webcam
        reading (what it was read as), else None."""
        if self.phase == "running":
            item = self.session.receive(raw)  # parse_input, then submit; both logged
            return self.session.reading_reply() if item.kind == "hand" else None
        if self.phase == "questionnaire" and self._questioning is not None:
            questioning = self._questioning
            if questioning.receive(raw):  # LiveInputError when not valid
                await self._after_questions()
            return None
        item = parse_input(raw, self.width, self.height)
        if item.kind == "hand":
            return None  # a reading between sessions: nothing to read it for
        if self.phase in ("consent", "debrief"):
            await self._screen(item.kind, item.consent)
        elif item.kind == "start" and self.phase == "instructions":
            await self._start()
        elif item.kind == "start":
            raise LiveInputError("start: no instruction screen is shown")
        else:
            shown = "the instructions: press Start" if self.phase == "instructions" else "none"
            raise LiveInputError(f"{item.kind}: no session is running (showing {shown})")
        return None

    async def command(self, item: Command) -> dict[str, Any] | None:
        """An experimenter's command (:mod:`robin_sim.live.experimenter`); a saved note's
        entry, else None. :class:`LiveInputError` says why it cannot be done now."""
        assert self._loop is not None
        session = self.session
        if item.kind == "note":
            return session.note(item.text)
        if item.kind == "end":
            await self._end("ended")
            return None
        if self.phase == "questionnaire" and item.kind == "next_block":
            await self._after_questions()  # the experimenter skips the rest of them
            return None
        if self.phase != "running":
            raise LiveInputError(f"{item.kind}: no block is running now ({self.phase})")
        if item.kind in ("pause", "resume"):
            session.pause(item.kind == "pause")
        else:  # next_block: this one is saved as ended; the watcher shows the next
            session.pause(False)
            await self._loop.run_in_executor(None, lambda: session.stop("ended"))
        return None

    async def finished(self) -> str:
        """Wait for the end of the run; its final status."""
        assert self._over is not None
        await self._over.wait()
        assert self.outcome is not None
        return self.outcome

    # --- the sequence -----------------------------------------------------------------------
    async def _screen(self, kind: str, value: str | None) -> None:
        """A message on the consent or the debrief screen."""
        if self.phase == "consent" and kind == "consent":
            self.journal("consent", {"value": value})
            if value == "agree":
                await self._demographics()
            else:  # nothing is kept but the refusal (the study's log and registry)
                self._over_with(DECLINED)
        elif self.phase == "debrief" and kind == "finish":
            self.journal("debrief", {})
            self._over_with(self._last_status)
        else:
            wanted = "consent (agree or decline)" if self.phase == "consent" else "finish"
            raise LiveInputError(f"{kind}: the {self.phase} screen is shown; send {wanted}")

    async def _demographics(self) -> None:
        """The study's demographics form, else the first block."""
        form = self.screens.demographics
        if form is None:
            await self._enter(0)
            return
        self.phase, self._asking = "questionnaire", "demographics"
        self._questioning = Questioning.form(form, self.configs[0], DEMOGRAPHICS_NAME)

    async def _enter(self, index: int) -> None:
        self.index = index
        if self.configs[index].protocol is not None:
            self.phase = "instructions"
        else:
            await self._start()

    async def _start(self) -> None:
        assert self._lock is not None and self._loop is not None
        async with self._lock:
            if self.phase in ("starting", "running", "done"):
                return
            self.phase = "starting"
            session = self.session
            await self._loop.run_in_executor(None, session.start)
            if self.phase == "done":  # ended while starting: stop it at once
                assert self.outcome is not None  # set together with the phase "done"
                await self._loop.run_in_executor(None, session.stop, self.outcome)
                return
            assert self._on_frame is not None
            self._unsubscribe = session.subscribe(self._on_frame)
            session.away(self._away)  # a page that is away holds the new block too
            self.phase = "running"
            self.journal("block_started", block_fields(session))
            self._watcher = self._loop.create_task(self._watch(session))

    async def _watch(self, session: LiveSession) -> None:
        """Wait for ``session`` to end by itself; then the next block or the end."""
        while not session.done.is_set():
            await asyncio.sleep(POLL_S)
        assert self._lock is not None
        async with self._lock:
            if self.phase != "running" or session is not self.session:
                return
            self._close(session)
            asked = self.questionnaires and not session.config.practice
            if asked and session.status().get("status") in ASKED_AFTER:
                self.phase, self._asking = "questionnaire", "block"
                self._questioning = Questioning(
                    self.questionnaires, session.out_dir, self.configs[self.index], inputs=session
                )
                return
            await self._next()

    async def _after_questions(self) -> None:
        assert self._lock is not None
        async with self._lock:
            if self.phase == "questionnaire":
                asked = self._questioning
                self._questioning = None
                done = (
                    [] if asked is None else [q.name for q in asked.questionnaires[: asked.index]]
                )
                self.journal(
                    self._asking, {"block": self.configs[self.index].block, "answered": done}
                )
                if self._asking == "demographics":
                    await self._enter(0)
                else:
                    await self._next()

    async def _next(self) -> None:
        """The next block's screen, or the end of the run after the last block."""
        if self.index + 1 < len(self.sessions):
            await self._enter(self.index + 1)
        elif self.screens.debrief is not None:
            self.phase, self._last_status = "debrief", self.results[-1]["status"]
        else:
            self._over_with(self.results[-1]["status"])

    def _close(self, session: LiveSession) -> None:
        if self._unsubscribe is not None:
            self._unsubscribe()
            self._unsubscribe = None
        status = session.status()
        self.results.append(status)
        self.journal("block_ended", block_fields(session, status))

    async def _end(self, status: str) -> None:
        """Stop the running session with ``status`` (saved) and end the run."""
        assert self._lock is not None and self._loop is not None
        if self.phase == "done":
            return
        if self.phase == "starting":  # _start stops it when session.start returns
            self._over_with(status)
            return
        async with self._lock:
            if self.phase == "done":
                return
            if self.phase == "running":
                session = self.session
                try:
                    await self._loop.run_in_executor(None, session.stop, status)
                except Exception:  # the run still ends; the session's own summary says more
                    LOG.exception("saving the session as %s failed", status)
                self._close(session)
            self._over_with(status)

    def _over_with(self, status: str) -> None:
        if self.phase != "done":
            self.journal("run_over", {"outcome": status})
        self.phase, self.outcome = "done", status
        assert self._over is not None
        self._over.set()
