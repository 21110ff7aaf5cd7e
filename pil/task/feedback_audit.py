"""How each verdict on an action reached the robot: the thumb the person gave against what the
robot took from it, for auditing a feedback channel (e.g. Robin's eye cameras).

Rows are the person's feedback (``ok``, ``not_ok``, ``none``: silence); columns how the robot
got its verdict: ``read_ok`` / ``read_not_ok`` (the thumb read), ``nothing_read`` (no thumb
read, e.g. one the classifier discarded: taken as OK, eq. 1) and ``stopped_unread`` (an
action the person stopped: taken as not-OK without the thumb being read). A channel that
reads every thumb has no ``stopped_unread``; ``not_ok`` x ``nothing_read`` are refusals the
robot took as approvals.
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping

from pil.task.records import StepRecord
from pil.types import Feedback

TRUE: tuple[str, ...] = ("ok", "not_ok", "none")
VERDICTS: tuple[str, ...] = ("read_ok", "read_not_ok", "nothing_read", "stopped_unread")
TRUE_NAME = {Feedback.OK: "ok", Feedback.NOT_OK: "not_ok", Feedback.NONE: "none"}


def verdict_source(record: StepRecord) -> str:
    """How ``record``'s verdict reached the robot (a column of :data:`VERDICTS`)."""
    if record.interrupted:
        return "stopped_unread"
    heard = record.feedback_read if record.feedback_read is not None else record.feedback
    if heard is Feedback.OK:
        return "read_ok"
    if heard is Feedback.NOT_OK:
        return "read_not_ok"
    return "nothing_read"


def feedback_confusion(records: Iterable[StepRecord]) -> dict[str, dict[str, int]]:
    """The person's feedback against the verdict's source, over the records with an action
    (every cell present, zeros included)."""
    out = {t: dict.fromkeys(VERDICTS, 0) for t in TRUE}
    for record in records:
        if record.action is None or record.feedback is None:
            continue
        out[TRUE_NAME[record.feedback]][verdict_source(record)] += 1
    return out


def confusion_columns(confusion: Mapping[str, Mapping[str, int]] | None) -> dict[str, int | None]:
    """The confusion as flat ``feedback_<true>_<verdict>`` columns (None where absent)."""
    return {
        f"feedback_{t}_{v}": None if confusion is None else int(confusion.get(t, {}).get(v, 0))
        for t in TRUE
        for v in VERDICTS
    }
