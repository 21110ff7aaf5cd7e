"""The live participant's "That was wrong": taking back an action of Robin's that stood.

An action stands when the participant lets it (a thumb up, or no thumb in the feedback window).
For :data:`TAKE_BACK_WINDOW_S` s of simulated time after that, while it is the participant's
turn, the "That was wrong" button (key :data:`robin_sim.live.inputs.TAKE_BACK_SHORTCUT`) takes
it back: at the loop's next safe point (before the next instruction,
:func:`pil.task.runner.steps`) the learner withdraws that approval
(:meth:`pil.task.step_phases.StepPhases.take_back`) and the participant's guide asks for the
instruction again. :class:`TakeBacks` keeps what stood and what the participant's own
bookkeeping was before it, and says in plain words why a take-back is refused. Pure Python.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

from pil.types import Action

TAKE_BACK_WINDOW_S = 10.0  # s of simulated time after an action stands that it can be taken back


@dataclass(frozen=True, slots=True)
class Stood:
    """An action that stood: which, its step number, when (sim s), and the participant's
    bookkeeping before it (restored when it is taken back)."""

    action: Action
    t: int
    at: float
    delivered: bool
    before: Any


class TakeBacks:
    """What the participant may take back now, and the take-back asked for (see module doc)."""

    def __init__(self, window: float = TAKE_BACK_WINDOW_S) -> None:
        self.window = window
        self.last: Stood | None = None  # the action that stood last (None: none to take back)
        self.requested = False  # accepted from the page, not yet seen by the physics thread
        self.asked = False  # a take-back waits for the loop's safe point
        self.count = 0  # approvals taken back

    def stood(self, stood: Stood) -> None:
        """An action stood (the one before it can no longer be taken back)."""
        self.last, self.requested, self.asked = stood, False, False

    def gone(self) -> None:
        """Robin acts again: what stood before is no longer the last action to take back."""
        self.last, self.requested, self.asked = None, False, False

    def left(self, now: float) -> float | None:
        """Sim seconds left to take back the action that stood last (None: nothing to take)."""
        last = self.last
        if last is None or last.delivered or self.requested or self.asked:
            return None
        left = last.at + self.window - now
        return left if left > 0 else None

    def refusal(self, now: float, your_turn: bool) -> str:
        """Why a take-back cannot be taken now, in the page's words ("": it can)."""
        last = self.last
        if not your_turn:
            return (
                "Robin is acting now: thumb down stops a wrong move. 'That was wrong' takes "
                "back an action that already stood, while it is your turn."
            )
        if last is None or self.requested or self.asked:  # one take-back per action
            return (
                "There is no action of Robin's to take back: 'That was wrong' takes back the "
                "last action that stood (thumb up, or no thumb), once."
            )
        if last.delivered:
            return (
                f"Robin's '{last.action.value}' delivered the leg; a delivered leg cannot be "
                "taken back."
            )
        ago = now - last.at
        if ago > self.window:
            return (
                f"Too late to take back Robin's '{last.action.value}': it stood {ago:.0f} s ago "
                f"and 'That was wrong' works for {self.window:g} s after an action stands. "
                "Go on with your next gesture."
            )
        return ""

    def request(self) -> None:
        """A take-back :meth:`refusal` accepted (from the page's thread): a second one before
        the physics thread sees it is refused."""
        self.requested = True

    def ask(self, your_turn: bool) -> str:
        """A take-back accepted by :meth:`refusal` reaches the physics thread: it waits for the
        loop's safe point; "" or, when Robin took a gesture in between, why it is too late."""
        self.requested = False
        if your_turn and self.last is not None:
            self.asked = True
            return ""
        return "Too late to take it back: Robin already acts on your next gesture."

    def taken(self, what: str) -> tuple[Stood | None, str]:
        """The loop took the approval back (``what``; "" when it had none): the action the
        participant asked to take back (None: none was asked for) and what the page says."""
        if not self.asked:
            return None, ""
        taken, self.last, self.asked = self.last, None, False
        if taken is None or not what:
            return taken, "Robin had no approved action left to take back."
        self.count += 1
        return taken, (
            f"Robin took back its '{taken.action.value}' (you said it was wrong). Make the "
            "gesture for that step again."
        )
