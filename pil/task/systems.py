"""The registry of study systems (the paper's five, section IV-B, and ours and baselines).

A system says how its learner learns and is tested: from scratch or pre-trained (at the test
rate d or at 100 %), with correction or manual repetition, which agent of
:data:`pil.agents.AGENTS`, and parameters it sets. :func:`pil.task.assemble.assemble` builds a
run of any of them; add an entry to make a new one selectable everywhere.

* ``pil``: Proactive Incremental Learning from scratch, with correction, on the test tables.
* ``c1``: pre-trained at the test rate d, with correction; ``c2``: at 100 %, with correction.
* ``c3``: pre-trained at d, manual repetition (the person repeats a misread gesture);
  ``c4``: at 100 %, manual repetition.
* ``proactive`` (ours): ``pil`` that acts on the likely next state before its gesture
  (:mod:`pil.anticipation`); ``pil-halve`` (ours): a not-OK halves the refused count;
  ``pil-robust`` (ours): the robust PIL rule (``learner=robust``, :mod:`pil.robust`).
* ``bandit``, ``tamer``: the baselines of :mod:`pil.agents`, from scratch, same person, detector
  and counting (they act on the detected state as it is: no correction).

Pre-training is a PIL run (with correction) on ``training_tables`` tables (5 x 4 = 20
handovers, each handover type exactly twice); its gestures and actions are reported apart
(``train_gestures``, ``train_actions``) and added to the totals, as the paper does. A run's
sub-seeds derive from its seed alone, not from the system or the rate, so the systems of one
repetition face the same handover order and detector deck (common random numbers).
"""

from __future__ import annotations

from collections.abc import Iterator, Mapping
from dataclasses import dataclass, field
from typing import Any

from pil.errors import InvalidChoiceError


@dataclass(frozen=True, slots=True)
class SystemSpec:
    """How one study system learns and is tested.

    ``trained_at``: None (from scratch), "d" (pre-trained at the test rate) or "full" (at 100 %);
    ``manual``: the person repeats a misread gesture (no correction); ``agent``: a key of
    :data:`pil.agents.AGENTS` (pre-training is always a PIL run); ``params``: run parameters
    (:data:`pil.task.params.PARAMS`) this system sets for its test run.
    """

    description: str
    trained_at: str | None = None
    manual: bool = False
    agent: str = "pil"
    params: Mapping[str, Any] = field(default_factory=dict)  # parameters it overrides


DEFAULT_SYSTEM = "pil"  # a run spec's system unless one is named

SYSTEM_SPECS: dict[str, SystemSpec] = {
    "pil": SystemSpec("PIL from scratch, with correction"),
    "c1": SystemSpec("pre-trained at d, with correction", "d"),
    "c2": SystemSpec("pre-trained at 100 %, with correction", "full"),
    "c3": SystemSpec("pre-trained at d, manual repetition", "d", manual=True),
    "c4": SystemSpec("pre-trained at 100 %, manual repetition", "full", manual=True),
    "bandit": SystemSpec("epsilon-greedy contextual bandit from scratch", agent="bandit"),
    "tamer": SystemSpec("TAMER-style feedback regression from scratch", agent="tamer"),
    "pil-halve": SystemSpec(
        "PIL from scratch, a not-OK halves the refused count (ours)",
        params={"adaptation": "halve"},
    ),
    "pil-robust": SystemSpec(
        "PIL's robust rule from scratch: weighed thumbs and silence, asks when unsure (ours)",
        params={"learner": "robust"},
    ),
    "proactive": SystemSpec(
        "PIL from scratch, acting on the likely next state before its gesture (ours)",
        params={"proactive": True},
    ),
}
PAPER_SYSTEMS: tuple[str, ...] = ("pil", "c1", "c2", "c3", "c4")


class _Descriptions(Mapping[str, str]):
    """A read-only view: system name -> description, always in step with SYSTEM_SPECS."""

    def __getitem__(self, name: str) -> str:
        return SYSTEM_SPECS[name].description

    def __iter__(self) -> Iterator[str]:
        return iter(SYSTEM_SPECS)

    def __len__(self) -> int:
        return len(SYSTEM_SPECS)


SYSTEMS: Mapping[str, str] = _Descriptions()


def check_system(system: str, label: str = "system") -> str:
    """``system`` if it is one of :data:`SYSTEMS`, else an error naming them (``label``: its
    name in the message, e.g. ``--systems: system``)."""
    if system not in SYSTEM_SPECS:
        raise InvalidChoiceError(label, system, SYSTEM_SPECS)
    return system
