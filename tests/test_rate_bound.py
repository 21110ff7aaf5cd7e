"""The smallest detection rate and the loop's bound on performances agree (issue 39)."""

from __future__ import annotations

from pil.learner import Learner
from pil.task.detector import Detector
from pil.task.params import MIN_RATE, RATE
from pil.task.person import ScriptedPerson
from pil.task.runner import MAX_PERFORMANCES, steps
from pil.task.scenario import load_scenario
from pil.task.world import SymbolicWorld


def test_a_gesture_repeated_until_read_is_read_within_the_bound_at_the_smallest_rate() -> None:
    assert (1 - MIN_RATE) ** MAX_PERFORMANCES < 1e-15
    assert RATE.smallest == MIN_RATE


def test_manual_repetition_at_the_smallest_rate_runs_to_the_end() -> None:
    """Before, 0.001 was accepted and the run stopped: 1000 performances without a reading."""
    scenario = load_scenario()
    for seed in range(3):
        person = ScriptedPerson.for_types(scenario, scenario.draw_types(4, seed), seed)
        detector = Detector(MIN_RATE, seed, deck_size=len(person.script))
        records = list(steps(Learner(seed), person, detector, SymbolicWorld(), manual=True))
        assert records[-1].legs_delivered == 4
        assert person.next_step(records[-1].state.hand) is None  # type: ignore[union-attr]
