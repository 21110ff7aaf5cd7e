"""What the live stream sends, lowered before physics falls behind real time, raised again.

The physics thread does everything of a live session: physics, the participant's inputs and
the stream's frames (render, the eye inset, JPEG, MP4). On a busy machine it cannot do all of
it at the wall clock's pace; physics must keep the pace (the participant is watching), so the
stream gives way first. :class:`StreamGovernor` looks at how much of each second the pacer
still slept (:class:`~robin_sim.live.pacing.Pacer`: the thread's headroom) and steps through
:data:`LEVELS`: the eye inset off first, then fewer frames. Each frame then stands for several
video frames, so the MP4 keeps its rate and length (and ``states.npz`` every frame's count:
``robin-pil replay`` renders the session again at full quality). A change is logged
(``events.jsonl``, kind ``stream``) and shown on the page.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass


@dataclass(frozen=True, slots=True)
class Quality:
    """One level of the stream: every ``stride``-th video frame is rendered and sent."""

    stride: int
    inset: bool

    def fps(self, video_fps: float) -> float:
        return video_fps / self.stride


LEVELS: tuple[Quality, ...] = (
    Quality(1, True),  # everything
    Quality(1, False),  # no eye inset (about a third of a frame's render time)
    Quality(2, False),
    Quality(3, False),
    Quality(5, False),
)
WINDOW_S = 1.0  # wall s over which the headroom is measured
WARMUP_S = 3.0  # wall s at the start not measured (the first frames: renderers warming up)
LOW = 0.15  # slept less than this share of the window (or slipped twice): one level down
SLIPS = 2  # times physics fell behind within a window that count as falling behind
HIGH = 0.55  # slept more than this share for UP_AFTER_S: one level up
UP_AFTER_S = 6.0


class StreamGovernor:
    """Chooses the stream's level from the physics thread's headroom (see the module doc).

    ``clock`` is the wall clock (monotonic s); ``on_change(level, why)`` is told of each
    change. Call :meth:`observe` with the pacer's total sleep and slips after every tick.
    """

    def __init__(
        self,
        clock: Callable[[], float],
        on_change: Callable[[int, str], None] | None = None,
        *,
        adaptive: bool = True,
        level: int = 0,
    ) -> None:
        self.clock, self.on_change, self.adaptive = clock, on_change, adaptive
        self.level = level  # a checked index of LEVELS (LiveConfig.stream_level)
        self.changes = 0
        self._start = clock() + WARMUP_S
        self._slept0 = 0.0
        self._slips0 = 0
        self._calm_since: float | None = None  # since when every window had headroom

    @property
    def quality(self) -> Quality:
        return LEVELS[self.level]

    def observe(self, slept_s: float, slips: int) -> None:
        """The pacer's totals now; once a window has passed, maybe change level."""
        now = self.clock()
        span = now - self._start
        if not self.adaptive or span < WINDOW_S:
            if span < 0:  # warming up: the window starts afterwards
                self._slept0, self._slips0 = slept_s, slips
            return
        headroom = (slept_s - self._slept0) / span
        slipped = slips - self._slips0 >= SLIPS
        self._start, self._slept0, self._slips0 = now, slept_s, slips
        if (slipped or headroom < LOW) and self.level + 1 < len(LEVELS):
            self._calm_since = None
            why = "fell behind real time" if slipped else f"{headroom:.0%} of the time to spare"
            self._set(self.level + 1, f"the machine is busy ({why})")
        elif headroom > HIGH and self.level > 0:
            if self._calm_since is None:
                self._calm_since = now
            elif now - self._calm_since >= UP_AFTER_S:
                self._calm_since = now
                self._set(self.level - 1, f"time to spare again ({headroom:.0%})")
        else:
            self._calm_since = None

    def hold(self, wall_s: float) -> None:
        """A pause of ``wall_s`` (the pacer slept nothing meanwhile): it is not measured, and
        the calm before it does not count towards raising the stream."""
        self._start += wall_s
        self._calm_since = None

    def _set(self, level: int, why: str) -> None:
        self.level = level
        self.changes += 1
        if self.on_change is not None:
            self.on_change(level, why)

    def state(self, video_fps: float) -> dict[str, object]:
        """For the page: the level, the frames per second sent, the inset, and whether the
        stream is lowered."""
        quality = self.quality
        return {
            "level": self.level,
            "lowered": self.level > 0,
            "fps": round(quality.fps(video_fps), 2),
            "inset": quality.inset,
            "changes": self.changes,
        }
