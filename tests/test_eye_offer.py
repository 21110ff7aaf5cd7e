"""What a look of Robin's eyes offers as a live participant's gesture (robin_sim.live.eye_watch).

:func:`offer_from` decides it from the look's class and confidence, the participant's phase and
the landmarks' label of their newest reading with a hand; adversarial inputs from every class,
phase and landmark label.
"""

from __future__ import annotations

from hypothesis import given
from hypothesis import strategies as st

from robin_sim.live.eye_watch import EYE_GESTURES, THUMB_SIGNS, offer_from
from robin_sim.vision.classifier import CLASSES

PHASES = ("waiting_for_gesture", "waiting_for_thumb", "acting", "idle")
LANDMARKS = (None, *CLASSES, "pointing")


@given(
    label=st.sampled_from(CLASSES),
    confidence=st.floats(0.0, 1.0),
    threshold=st.floats(0.0, 1.0),
    phase=st.sampled_from(PHASES),
    landmarks=st.sampled_from(LANDMARKS),
)
def test_an_offer_is_an_instruction_read_surely_while_waiting_and_no_thumb_is_shown(
    label: str, confidence: float, threshold: float, phase: str, landmarks: str | None
) -> None:
    gesture, withheld = offer_from(label, confidence, threshold, phase, landmarks)
    would = phase == "waiting_for_gesture" and label in EYE_GESTURES and confidence >= threshold
    assert withheld == (would and landmarks in THUMB_SIGNS)
    if would and not withheld:
        assert gesture is EYE_GESTURES[label]
    else:
        assert gesture is None


def test_a_thumb_up_at_the_palm_read_as_release_is_held_back() -> None:
    """The case of the footage: the eyes read release, the landmarks a thumb up."""
    assert offer_from("release", 0.9, 0.5, "waiting_for_gesture", "thumb_up") == (None, True)
    gesture, withheld = offer_from("release", 0.9, 0.5, "waiting_for_gesture", "release")
    assert gesture is EYE_GESTURES["release"] and not withheld
