"""Whether asking for a thumb gets one: silence after the robot asked, against silence after
it did not.

The robot asks for an explicit thumb when silence says nothing for this teacher and it is
unsure of its action (:mod:`pil.robust.learner`). Asking helps only when the silence was the
person's (who looked away, or waited): then the person answers. A thumb that the cameras
cannot read stays silent however often the robot asks. :class:`Answers` counts the silences
heard after asked and after unasked actions; once ``TRIAL`` asks were answered (or not),
the robot keeps asking only while silence after an ask is at most ``HELPS_BELOW`` of its share
after an action it did not ask about (each share with one silence and one thumb added, a
uniform Beta prior).
"""

from __future__ import annotations

from pil.types import Feedback

TRIAL = 10  # asks before their answers are judged
HELPS_BELOW = 0.5  # asking helps while it at least halves the share of silence


class Answers:
    """Silences after asked and unasked actions (module docstring)."""

    def __init__(self) -> None:
        self.asked = [0, 0]  # [silences, signals] after actions the robot asked about
        self.unasked = [0, 0]

    def heard(self, heard: Feedback, *, asked: bool) -> None:
        """``heard`` after an action (``asked``: the robot asked for a thumb on it)."""
        tally = self.asked if asked else self.unasked
        tally[0] += heard is Feedback.NONE
        tally[1] += 1

    def helps(self) -> bool:
        """True while asking is worth it (module docstring)."""
        if self.asked[1] < TRIAL:
            return True
        after_ask = (self.asked[0] + 1) / (self.asked[1] + 2)
        otherwise = (self.unasked[0] + 1) / (self.unasked[1] + 2)
        return after_ask <= HELPS_BELOW * otherwise
