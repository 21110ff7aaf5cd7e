"""The vocabulary of the task: gestures G, feedback F, actions A, hand states H, and the state s.

Enums accept the paper's names as strings (``Gesture("give me")``, ``Action.parse("object")``);
an unknown name raises :class:`pil.errors.InvalidChoiceError` listing the valid ones.
"""

from __future__ import annotations

from dataclasses import dataclass
from enum import StrEnum
from typing import Self

from pil.errors import InvalidChoiceError


class _NamedEnum(StrEnum):
    """A string enum whose values are the paper's names; parsing is forgiving about case."""

    @classmethod
    def _kind(cls) -> str:
        return cls.__name__.lower()

    @classmethod
    def _missing_(cls, value: object) -> Self | None:
        if isinstance(value, str):
            wanted = value.strip().lower().replace("_", " ")
            for member in cls:
                if wanted in (member.value, member.name.lower().replace("_", " ")):
                    return member
        return None

    @classmethod
    def parse(cls, value: str | Self) -> Self:
        """Return the member named ``value`` or raise an error naming the valid choices."""
        try:
            return cls(value)
        except ValueError:
            raise InvalidChoiceError(cls._kind(), value, [m.value for m in cls]) from None

    def __str__(self) -> str:
        return self.value


class Gesture(_NamedEnum):
    """Instruction gestures G (IMHG names: pointing, give me, grasp close, grasp open)."""

    POINTING = "pointing"
    GIVE_ME = "give me"
    GRASP = "grasp"
    RELEASE = "release"


class Action(_NamedEnum):
    """Robot manipulation actions A."""

    OPEN = "open"
    CLOSE = "close"
    OBJECT = "object"
    HUMAN = "human"
    LOCATION = "location"


class Hand(_NamedEnum):
    """State of the robot's hand H: free (no object) or occupied (an object in it)."""

    FREE = "free"
    OCCUPIED = "occupied"


class Feedback(_NamedEnum):
    """Feedback F (thumb up / thumb down); ``NONE`` (no feedback) counts as OK."""

    OK = "ok"
    NOT_OK = "not ok"
    NONE = "none"

    @property
    def approves(self) -> bool:
        """True for OK and for no feedback (eq. 1 gives eta = 1)."""
        return self is not Feedback.NOT_OK


@dataclass(frozen=True, slots=True)
class State:
    """The system state s_t = <g_t, a_t, h_t>.

    ``gesture`` is the detected (or corrected) gesture, ``previous_action`` the robot's last
    action that got OK, ``hand`` the state of the robot's hand. Strings are parsed.
    """

    gesture: Gesture
    previous_action: Action
    hand: Hand

    def __post_init__(self) -> None:
        object.__setattr__(self, "gesture", Gesture.parse(self.gesture))
        object.__setattr__(self, "previous_action", Action.parse(self.previous_action))
        object.__setattr__(self, "hand", Hand.parse(self.hand))

    def key(self) -> str:
        """A stable text key, e.g. ``"pointing|open|free"`` (used in saved tables and logs)."""
        return f"{self.gesture.value}|{self.previous_action.value}|{self.hand.value}"

    @classmethod
    def from_key(cls, key: str) -> State:
        """Inverse of :meth:`key`."""
        parts = key.split("|")
        if len(parts) != 3:
            raise InvalidChoiceError("state key", key, ["gesture|previous_action|hand"])
        gesture, action, hand = parts
        return cls(Gesture.parse(gesture), Action.parse(action), Hand.parse(hand))

    def __str__(self) -> str:
        return f"<{self.gesture}, {self.previous_action}, {self.hand}>"


GESTURES: tuple[Gesture, ...] = tuple(Gesture)
ACTIONS: tuple[Action, ...] = tuple(Action)
HANDS: tuple[Hand, ...] = tuple(Hand)
START_ACTION = Action.OPEN
START_HAND = Hand.FREE
# The one source of "an approved close fills the hand, an approved open empties it".
HAND_AFTER: dict[Action, Hand] = {Action.CLOSE: Hand.OCCUPIED, Action.OPEN: Hand.FREE}
# The six hand signs a person shows, by the one name the person's poses, the eye cameras'
# classes, the live webcam reader and the live page share: each gesture's own name
# (``give_me``) and the two thumbs.
SIGN_OF: dict[Gesture | Feedback, str] = {
    **{gesture: gesture.name.lower() for gesture in Gesture},
    Feedback.OK: "thumb_up",
    Feedback.NOT_OK: "thumb_down",
}
SIGNS: dict[str, Gesture | Feedback] = {name: sign for sign, name in SIGN_OF.items()}
SIGN_NAMES: tuple[str, ...] = tuple(SIGNS)  # pointing, give_me, grasp, release, thumbs


def sign_label(name: str) -> str:
    """A sign's name as people read it: ``"give me"``, ``"thumb up"``."""
    return name.replace("_", " ")


def hand_after(action: Action, hand: Hand) -> Hand:
    """The hand state an approved ``action`` leaves (:data:`HAND_AFTER`; others keep ``hand``)."""
    return HAND_AFTER.get(action, hand)
