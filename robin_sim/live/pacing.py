"""Physics paced to the wall clock, with frames at the stream's rate.

:class:`Pacer` is a :class:`~robin_sim.control.simulator.Simulator` observer. After every control
tick it first runs the session's own hook (stop requests, the participant's inputs), then hands
a frame to the :class:`~robin_sim.live.frames.FrameStream` when one is due, then sleeps until the
wall clock has caught up with ``speed`` x the simulated time: physics never runs ahead of it.
When physics falls behind (a slow frame, a busy machine) the pacer does not race to catch up
(which would show the participant a burst of fast motion): once it is more than
:data:`MAX_LAG_S` behind it moves its reference forward and counts the time lost
(:attr:`Pacer.behind_s`, :attr:`Pacer.slips`).

Frames are due on simulated time, one every ``speed / fps`` s, so at pace the stream runs at
``fps`` frames per wall second, and each frame stands for one frame of the MP4. With a
:class:`~robin_sim.live.quality.StreamGovernor` the stream may render only every
``stride``-th due frame (a busy machine), which then stands for all the frames owed since.
"""

from __future__ import annotations

import time
from collections.abc import Callable

from robin_sim.control.simulator import Simulator
from robin_sim.live.frames import FrameStream
from robin_sim.live.quality import StreamGovernor
from robin_sim.render.renderer import FrameClock

MAX_LAG_S = 0.25  # s of wall time physics may fall behind before the pacer lets it go


class Pacer:
    """Keeps ``sim`` at ``speed`` x wall time and renders frames at ``fps`` (see module doc)."""

    def __init__(
        self,
        sim: Simulator,
        speed: float,
        fps: float,
        stream: FrameStream | None = None,
        hook: Callable[[Simulator], None] | None = None,
        clock: Callable[[], float] = time.monotonic,
        governor: StreamGovernor | None = None,
    ) -> None:
        self.sim, self.speed, self.stream, self.hook, self._clock = sim, speed, stream, hook, clock
        self.governor = governor
        self._owed = 0  # video frames due and not rendered yet (the governor's stride)
        self.frames = FrameClock(fps / speed, sim.control_dt)
        self._sim0 = sim.time
        self._wall0 = clock()
        self.behind_s = 0.0  # wall time lost to falling behind
        self.slips = 0  # times physics fell more than MAX_LAG_S behind
        self.slept_s = 0.0
        self._remove: Callable[[], None] | None = sim.add_observer(self)

    def __call__(self, sim: Simulator) -> None:
        if self.hook is not None:
            self.hook(sim)
        due = self.frames.frames_due(sim.time - self._sim0)
        governor = self.governor
        if due and self.stream is not None:
            self._owed += due
            quality = None if governor is None else governor.quality
            if quality is None or self._owed >= quality.stride:
                inset = quality is None or quality.inset
                sim.prepare_view()
                self.stream.capture(sim.model, sim.data, self._owed, inset=inset)
                self._owed = 0
        ahead = self._wall0 + (sim.time - self._sim0) / self.speed - self._clock()
        if ahead > 0:
            time.sleep(ahead)
            self.slept_s += ahead
        elif -ahead > MAX_LAG_S:
            self.slips += 1
            self.behind_s += -ahead
            self._wall0 -= ahead  # from here on, pace from where physics is now
        if governor is not None:
            governor.observe(self.slept_s, self.slips)

    def skip(self, wall_s: float) -> None:
        """Pace on as if ``wall_s`` s of wall time had not passed (a pause: no lag counted)."""
        self._wall0 += wall_s
        if self.governor is not None:
            self.governor.hold(wall_s)

    @property
    def lag_s(self) -> float:
        """How far (wall s) physics is behind its pace now (negative: ahead, sleeping)."""
        return self._clock() - (self._wall0 + (self.sim.time - self._sim0) / self.speed)

    def close(self) -> None:
        """Stop pacing (idempotent); frames still owed are rendered now (the MP4's length)."""
        if self._owed and self.stream is not None:
            self.sim.prepare_view()
            self.stream.capture(self.sim.model, self.sim.data, self._owed, inset=False)
            self._owed = 0
        if self._remove is not None:
            self._remove()
            self._remove = None
