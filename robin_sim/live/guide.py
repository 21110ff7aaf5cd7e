"""What the live page tells the participant to do, in plain words.

:func:`guide` turns the handover now asked for (its type's steps, how many of them the
participant has let stand, the leg it is about) into the page's ``guide`` block: one goal
("Ask Robin to give you the red leg (leg 1)."), the next step as an instruction, and every step
as a checklist. Legs and spots are numbered from 1 for people; their colours are the scene's
(:data:`robin_sim.model.scene.LEG_COLOUR_NAMES`). Pure Python: no MuJoCo.
"""

from __future__ import annotations

from typing import Any

from pil.task.scenario import HandoverType
from pil.task.script import LegsSeen
from pil.task.world import Target
from pil.types import Action, Gesture, Hand, State
from pil.validity import is_valid
from robin_sim.model.scene import LEG_COLORS, LEG_COLOUR_NAMES

# The key of each gesture's button on the page.
KEYS = {Gesture.GRASP: "R", Gesture.GIVE_ME: "G", Gesture.RELEASE: "L"}


def leg_colour(leg: int) -> str:
    """The colour name of leg ``leg`` (0-based) as the scene paints it."""
    return LEG_COLOUR_NAMES[leg % len(LEG_COLOUR_NAMES)]


def leg_rgb(leg: int) -> str:
    """The CSS colour of leg ``leg`` (0-based), e.g. ``rgb(217, 64, 51)``."""
    r, g, b, _ = LEG_COLORS[leg % len(LEG_COLORS)]
    return f"rgb({round(r * 255)}, {round(g * 255)}, {round(b * 255)})"


def leg_name(leg: int) -> str:
    """How the page names leg ``leg`` (0-based): "the red leg (leg 1)"."""
    return f"the {leg_colour(leg)} leg (leg {leg + 1})"


def target_name(target: Target) -> str:
    """A clicked leg or spot in the page's words."""
    return leg_name(target.index) if target.kind == "leg" else f"spot {target.index + 1}"


def goal(kind: HandoverType, leg: int) -> str:
    """The handover's aim: the leg to the person's hand, or onto a spot on the table."""
    actions = [step.action for step in kind.steps]
    last_move = next((a for a in reversed(actions) if a in (Action.HUMAN, Action.LOCATION)), None)
    if last_move is Action.LOCATION:
        return f"Ask Robin to put {leg_name(leg)} on a spot on the table."
    via = " by way of a spot on the table" if Action.LOCATION in actions else ""
    return f"Ask Robin to give you {leg_name(leg)}{via}."


def step_text(kind: HandoverType, index: int, leg: int) -> str:
    """Step ``index`` of ``kind`` as an instruction to the participant."""
    step = kind.steps[index]
    before = [s.action for s in kind.steps[:index]]
    if step.gesture is Gesture.POINTING and step.action is Action.OBJECT:
        later = any(s.action is Action.OBJECT for s in kind.steps[index + 1 :])
        if later:
            return "Point at another leg first (click it in the image)."
        return f"Point at {leg_name(leg)}: click it in the image."
    if step.gesture is Gesture.POINTING:
        return "Point at a spot on the table: click one of the numbered rings."
    key = KEYS[step.gesture]
    what = {
        Action.CLOSE: "so that Robin grasps the leg",
        Action.HUMAN: "so that Robin brings the leg to your hand",
        Action.OPEN: "so that Robin lets go of the leg"
        + (" into your hand" if before and before[-1] is Action.HUMAN else ""),
        Action.OBJECT: "so that Robin goes to the leg",
        Action.LOCATION: "so that Robin moves to the spot",
    }[step.action]
    name = step.gesture.value.replace("give me", "give-me")
    return f"Make the {name} gesture (button or key {key}) {what}."


def guide(
    kind: HandoverType, done: int, leg: int, handover: int, legs_total: int
) -> dict[str, Any]:
    """The page's guide for handover ``handover`` of type ``kind`` with ``done`` steps let
    stand, about leg ``leg`` (0-based)."""
    steps = [{"text": step_text(kind, k, leg), "done": k < done} for k in range(len(kind.steps))]
    current = min(done, len(kind.steps) - 1)
    return {
        "goal": goal(kind, leg),
        "instruction": steps[current]["text"],
        "checklist": steps,
        "step": current,
        "handover_number": handover + 1,
        "handovers": legs_total,
        "leg": {"index": leg, "number": leg + 1, "colour": leg_colour(leg), "css": leg_rgb(leg)},
    }


def leg_now(seen: LegsSeen, delivered: set[int], legs: int) -> int:
    """The leg the guide is about: the one Robin holds or went to (as the participant saw it),
    else the first not yet delivered (0-based)."""
    for leg in (seen.holding, seen.pointed):
        if leg is not None and leg not in delivered:
            return leg
    return next((k for k in range(legs) if k not in delivered), 0)


def legend(legs: int, delivered: set[int], spots: int) -> dict[str, Any]:
    """The legend's part of the guide: the table's legs by number and colour (delivered ones
    marked) and how many spots it has."""
    return {
        "legs": [
            {
                "number": k + 1,
                "colour": leg_colour(k),
                "css": leg_rgb(k),
                "delivered": k in delivered,
            }
            for k in range(legs)
        ],
        "spots": spots,
    }


# The action a gesture means in a state the block's types do not use (for the record only).
PLAIN_MEANING = {
    Gesture.GRASP: Action.CLOSE,
    Gesture.GIVE_ME: Action.HUMAN,
    Gesture.RELEASE: Action.OPEN,
}


def meant_action(state: State, target: Target | None) -> Action:
    """What the participant means by ``state``'s gesture where the block's types have no step
    for it (for the record only): a point at a leg with an empty hand is object, another point
    location; the other gestures their plain meaning."""
    if state.gesture is Gesture.POINTING:
        leg = target is not None and target.kind == "leg"
        return Action.OBJECT if leg and state.hand is Hand.FREE else Action.LOCATION
    return PLAIN_MEANING[state.gesture]


# Why Robin could not act on a gesture (pil.validity's rule names), in the page's words.
CANNOT = {
    "grasp while occupied": "Robin already holds a leg, so it cannot grasp another one",
    "release while free": "Robin's hand is empty, so there is nothing to release",
    "give me while free": "Robin's hand is empty, so there is nothing to give you",
    "grasp away from a leg": "Robin's hand is not at a leg, so it cannot grasp now",
}


def step_for(kind: HandoverType, done: int, previous: Action, hand: Hand) -> int:
    """The step of ``kind`` the participant is at when Robin's last standing action is
    ``previous`` and its hand ``hand``: the first step from ``done`` on (then from the start)
    made in that state of the robot; else ``done``, unless its gesture is invalid there, in
    which case the first step whose gesture is valid there. The guide never asks for a gesture
    Robin cannot act on (after an approved wrong action, or a drop)."""
    steps = kind.steps
    done = min(done, len(steps) - 1)
    order = [*range(done, len(steps)), *range(done)]
    for k in order:
        state = steps[k].state
        if state.previous_action is previous and state.hand is hand:
            return k
    for k in order:
        if is_valid(State(steps[k].gesture, previous, hand)):
            return k
    return done


def cannot_act(gesture: Gesture, reason: str) -> str:
    """Why the robot handed the step back, in plain words (``reason``: the learner's)."""
    name = gesture.value.replace("give me", "give-me")
    if "invalid: " in reason:  # after the loop's own note, e.g. "re-grounded: ...; invalid: "
        rule = reason.split("invalid: ", 1)[1].split(";", 1)[0]
        why = CANNOT.get(rule, "that gesture does not fit what Robin holds and did last")
        return f"Robin could not act on your {name} gesture: {why}."
    if "since your last gesture" in reason:
        return f"Robin stopped trying ({reason})."
    if reason.startswith(("discarded", "read as")):
        return f"Robin could not read your {name} gesture clearly."
    return f"Robin could not act on your {name} gesture ({reason})."
