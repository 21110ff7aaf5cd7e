"""The rule table of invalid states (pil.validity)."""

from __future__ import annotations

import pytest

from pil.types import ACTIONS, GESTURES, HANDS, Action, Gesture, Hand, State
from pil.validity import ALL_STATES, RULES, VALID_STATES, broken_rules, is_valid, why_invalid

# Every state that occurs in Table I of the paper (the three handover types, steps 1-23).
TABLE_ONE_STATES = [
    ("pointing", "open", "free"),
    ("grasp", "object", "free"),
    ("give me", "close", "occupied"),
    ("release", "human", "occupied"),
    ("pointing", "close", "occupied"),
    ("release", "location", "occupied"),
    ("pointing", "object", "free"),
    ("pointing", "human", "occupied"),
]

# (state, name of a rule it must break)
INVALID = [
    (("grasp", "human", "occupied"), "grasp while occupied"),  # Table I, t = 21, misdetected
    (("grasp", "close", "occupied"), "grasp while occupied"),
    (("release", "open", "free"), "release while free"),
    (("release", "object", "free"), "release while free"),
    (("give me", "open", "free"), "give me while free"),
    (("pointing", "open", "occupied"), "occupied after open"),
    (("pointing", "close", "free"), "free after close"),
    (("pointing", "human", "free"), "free at human or location"),
    (("pointing", "location", "free"), "free at human or location"),
    (("pointing", "object", "occupied"), "occupied at object"),
    (("grasp", "open", "free"), "grasp away from a leg"),
]


@pytest.mark.parametrize("parts", TABLE_ONE_STATES)
def test_every_table_one_state_is_valid(parts: tuple[str, str, str]) -> None:
    state = State(*parts)
    assert is_valid(state)
    assert why_invalid(state) is None
    assert broken_rules(state) == ()


@pytest.mark.parametrize(("parts", "rule"), INVALID)
def test_listed_invalid_states_are_invalid_with_a_reason(
    parts: tuple[str, str, str], rule: str
) -> None:
    state = State(*parts)
    assert not is_valid(state)
    assert rule in [r.name for r in broken_rules(state)]
    reason = why_invalid(state)
    assert reason is not None
    assert reason.startswith(broken_rules(state)[0].name + ": ")
    assert len(reason) > len(broken_rules(state)[0].name) + 10


def test_exactly_twelve_valid_states() -> None:
    assert len(ALL_STATES) == len(GESTURES) * len(ACTIONS) * len(HANDS) == 40
    assert len(set(ALL_STATES)) == 40
    assert len(VALID_STATES) == 12
    free = {s for s in VALID_STATES if s.hand is Hand.FREE}
    assert free == {
        State("pointing", "open", "free"),
        State("pointing", "object", "free"),
        State("grasp", "object", "free"),
    }
    occupied = {s for s in VALID_STATES if s.hand is Hand.OCCUPIED}
    assert occupied == {
        State(g, a, "occupied")
        for g in (Gesture.POINTING, Gesture.GIVE_ME, Gesture.RELEASE)
        for a in (Action.CLOSE, Action.HUMAN, Action.LOCATION)
    }


def test_every_rule_but_the_first_is_needed() -> None:
    """Each later rule rejects a state no other rule rejects; the first one is implied by
    'grasp away from a leg' + 'occupied at object' but kept to name the paper's reason."""
    for rule in RULES[1:]:
        alone = [s for s in ALL_STATES if broken_rules(s) == (rule,)]
        assert alone, f"rule {rule.name!r} is covered by the others"
    first = RULES[0]
    assert first.name == "grasp while occupied"
    assert all(len(broken_rules(s)) > 1 for s in ALL_STATES if first.matches(s))


def test_table_one_misdetection_names_the_papers_reason() -> None:
    reason = why_invalid(State("grasp", "human", "occupied"))
    assert reason is not None and reason.startswith("grasp while occupied")


def test_rules_are_documented_in_the_module_docstring() -> None:
    import pil.validity

    doc = pil.validity.__doc__ or ""
    for rule in RULES:
        assert rule.name in doc
    assert len({r.name for r in RULES}) == len(RULES)


def test_rule_match_uses_every_field() -> None:
    rule = next(r for r in RULES if r.name == "grasp while occupied")
    assert rule.matches(State("grasp", "close", "occupied"))
    assert not rule.matches(State("grasp", "object", "free"))
    assert not rule.matches(State("release", "close", "occupied"))


def test_text_keys_and_bad_input() -> None:
    assert is_valid("give me|close|occupied")
    assert why_invalid("grasp|human|occupied").startswith("grasp while occupied")  # type: ignore[union-attr]
    with pytest.raises(TypeError):
        is_valid(("grasp", "human", "occupied"))  # type: ignore[arg-type]
