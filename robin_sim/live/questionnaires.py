"""Questionnaires a participant answers on the live page after each protocol block.

A protocol's ``questionnaires`` list names presets or defines Likert questionnaires::

    questionnaires:
      - nasa-tlx                 # NASA-TLX raw: six items, 0-100 in steps of 5
      - godspeed                 # Godspeed: five scales of 5-point semantic differentials
      - name: trust              # a custom questionnaire of Likert items
        title: Your trust in the robot
        points: 7                # 2 to 11 answer points, 1..points (default 7)
        low: strongly disagree   # the anchors of every item (an item may give its own)
        high: strongly agree
        items:
          - {id: reliable, text: The robot did what I meant.}

:func:`load_questionnaires` checks every field (:class:`QuestionnaireError` names the problem
and the valid choices); :meth:`Questionnaire.check_answers` checks one page submission and
:meth:`Questionnaire.scores` scores it: NASA-TLX raw = the mean of its six ratings, Godspeed
one mean per scale, a custom questionnaire one score per item and their mean. Pure Python.
"""

from __future__ import annotations

import re
import statistics
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

from pil.errors import RobinPilError, quote

QUESTIONNAIRE_KEYS: tuple[str, ...] = (
    "name",
    "title",
    "instructions",
    "points",
    "low",
    "high",
    "items",
)
ITEM_KEYS: tuple[str, ...] = ("id", "text", "low", "high", "scale")
MAX_ITEMS, MAX_TEXT = 60, 300
NAME = re.compile(r"[a-z][a-z0-9_-]{0,39}")


class QuestionnaireError(RobinPilError):
    """A questionnaire definition, or a page's answers to one, that cannot be taken."""


@dataclass(frozen=True)
class Item:
    """One rated item: answers from ``minimum`` to ``maximum`` in steps of ``step``."""

    id: str
    text: str
    low: str  # the anchor at the minimum
    high: str  # the anchor at the maximum
    minimum: int
    maximum: int
    step: int = 1
    scale: str = ""  # the scale it counts towards (Godspeed); "" for none

    def as_dict(self) -> dict[str, Any]:
        return {
            "id": self.id,
            "text": self.text,
            "low": self.low,
            "high": self.high,
            "min": self.minimum,
            "max": self.maximum,
            "step": self.step,
        }


@dataclass(frozen=True)
class Questionnaire:
    """A checked questionnaire; ``kind`` is ``nasa-tlx``, ``godspeed`` or ``likert``."""

    name: str
    kind: str
    title: str
    instructions: str
    items: tuple[Item, ...]

    def as_dict(self) -> dict[str, Any]:
        """What the page needs to show it."""
        return {
            "name": self.name,
            "kind": self.kind,
            "title": self.title,
            "instructions": self.instructions,
            "items": [item.as_dict() for item in self.items],
        }

    def check_answers(self, answers: Any) -> dict[str, int]:
        """``answers`` (item id -> number) checked: every item once, on its scale."""
        if not isinstance(answers, Mapping):
            raise QuestionnaireError(f"{self.name}: answers must be an object of item id -> number")
        ids = [item.id for item in self.items]
        unknown = [str(k) for k in answers if k not in ids]
        if unknown:
            raise QuestionnaireError(
                f"{self.name}: unknown item {quote(unknown[0])}; items: " + ", ".join(ids)
            )
        missing = [item.text for item in self.items if item.id not in answers]
        if missing:
            more = f" and {len(missing) - 1} more" if len(missing) > 1 else ""
            raise QuestionnaireError(
                f"please answer every question: {missing[0]!r}{more} not answered yet"
            )
        checked = {}
        for item in self.items:
            value = answers[item.id]
            if (
                isinstance(value, bool)
                or not isinstance(value, int)
                or not item.minimum <= value <= item.maximum
                or (value - item.minimum) % item.step
            ):
                raise QuestionnaireError(
                    f"{self.name}.{item.id}: expected a whole number from {item.minimum} to "
                    f"{item.maximum} in steps of {item.step}, got {str(value)[:20]!r}"
                )
            checked[item.id] = value
        return checked

    def scores(self, answers: Mapping[str, int]) -> dict[str, float]:
        """The questionnaire's scores of checked ``answers`` (see the module doc)."""
        if self.kind == "nasa-tlx":
            return {"raw_tlx": statistics.fmean(answers[i.id] for i in self.items)}
        if self.kind == "godspeed":
            scales: dict[str, list[int]] = {}
            for item in self.items:
                scales.setdefault(item.scale, []).append(answers[item.id])
            return {scale: statistics.fmean(values) for scale, values in scales.items()}
        scores = {item.id: float(answers[item.id]) for item in self.items}
        return {**scores, "mean": statistics.fmean(scores.values())}


def _tlx() -> Questionnaire:
    rows = (
        (
            "mental",
            "Mental demand: how much thinking, deciding and remembering did the task take?",
            "very low",
            "very high",
        ),
        (
            "physical",
            "Physical demand: how much physical activity did the task take?",
            "very low",
            "very high",
        ),
        (
            "temporal",
            "Temporal demand: how hurried or rushed was the pace of the task?",
            "very low",
            "very high",
        ),
        (
            "performance",
            "Performance: how well did you do what you were asked to do?",
            "perfect",
            "failure",
        ),
        (
            "effort",
            "Effort: how hard did you have to work to reach your level of performance?",
            "very low",
            "very high",
        ),
        (
            "frustration",
            "Frustration: how insecure, discouraged, irritated or stressed did you feel?",
            "very low",
            "very high",
        ),
    )
    items = tuple(Item(i, text, lo, hi, 0, 100, 5) for i, text, lo, hi in rows)
    return Questionnaire(
        "nasa-tlx",
        "nasa-tlx",
        "Workload (NASA-TLX)",
        "Rate the block you have just finished on each scale.",
        items,
    )


GODSPEED_SCALES: dict[str, tuple[tuple[str, str], ...]] = {
    "anthropomorphism": (
        ("fake", "natural"),
        ("machinelike", "humanlike"),
        ("unconscious", "conscious"),
        ("artificial", "lifelike"),
        ("moving rigidly", "moving elegantly"),
    ),
    "animacy": (
        ("dead", "alive"),
        ("stagnant", "lively"),
        ("mechanical", "organic"),
        ("artificial", "lifelike"),
        ("inert", "interactive"),
        ("apathetic", "responsive"),
    ),
    "likeability": (
        ("dislike", "like"),
        ("unfriendly", "friendly"),
        ("unkind", "kind"),
        ("unpleasant", "pleasant"),
        ("awful", "nice"),
    ),
    "perceived_intelligence": (
        ("incompetent", "competent"),
        ("ignorant", "knowledgeable"),
        ("irresponsible", "responsible"),
        ("unintelligent", "intelligent"),
        ("foolish", "sensible"),
    ),
    "perceived_safety": (("anxious", "relaxed"), ("agitated", "calm"), ("quiescent", "surprised")),
}


def _godspeed() -> Questionnaire:
    items = tuple(
        Item(f"{scale}_{k + 1}", f"{low} - {high}", low, high, 1, 5, 1, scale)
        for scale, pairs in GODSPEED_SCALES.items()
        for k, (low, high) in enumerate(pairs)
    )
    return Questionnaire(
        "godspeed",
        "godspeed",
        "Your impression of the robot (Godspeed)",
        "For each pair, choose where your impression of the robot lies.",
        items,
    )


PRESETS = {"nasa-tlx": _tlx, "godspeed": _godspeed}


def load_questionnaires(raw: Any, where: str) -> tuple[Questionnaire, ...]:
    """The protocol's ``questionnaires`` list checked (None: none)."""
    if raw is None:
        return ()
    if not isinstance(raw, list) or not raw:
        raise QuestionnaireError(
            f"{where}: expected a non-empty list of presets ("
            + ", ".join(PRESETS)
            + ") or questionnaire mappings with keys "
            + ", ".join(QUESTIONNAIRE_KEYS)
        )
    out = [_one(item, f"{where}[{i}]") for i, item in enumerate(raw)]
    names = [q.name for q in out]
    repeated = next((n for n in names if names.count(n) > 1), None)
    if repeated is not None:
        raise QuestionnaireError(
            f"{where}: questionnaire {repeated!r} is listed twice; give each its own name"
        )
    return tuple(out)


def _one(raw: Any, where: str) -> Questionnaire:
    if isinstance(raw, str):
        if raw not in PRESETS:
            raise QuestionnaireError(
                f"{where}: unknown preset {quote(raw)}; valid choices: "
                + ", ".join(PRESETS)
                + " (or a mapping with items)"
            )
        return PRESETS[raw]()
    if not isinstance(raw, Mapping):
        raise QuestionnaireError(
            f"{where}: expected a preset name or a mapping with keys "
            + ", ".join(QUESTIONNAIRE_KEYS)
        )
    _reject_unknown(raw, QUESTIONNAIRE_KEYS, where)
    name = raw.get("name")
    if not isinstance(name, str) or not NAME.fullmatch(name) or name in PRESETS:
        raise QuestionnaireError(
            f"{where}.name: expected a name of lower-case letters, digits, "
            f"_ or - (not a preset's: {', '.join(PRESETS)}), got "
            f"{quote(name)}"
        )
    points = raw.get("points", 7)
    if isinstance(points, bool) or not isinstance(points, int) or not 2 <= points <= 11:
        raise QuestionnaireError(
            f"{where}.points: expected a whole number from 2 to 11, got {quote(points)}"
        )
    low = _text(raw.get("low", "strongly disagree"), f"{where}.low")
    high = _text(raw.get("high", "strongly agree"), f"{where}.high")
    items_raw = raw.get("items")
    if not isinstance(items_raw, list) or not 1 <= len(items_raw) <= MAX_ITEMS:
        raise QuestionnaireError(
            f"{where}.items: expected a list of 1 to {MAX_ITEMS} items, "
            "each a mapping with keys " + ", ".join(ITEM_KEYS[:4])
        )
    items = []
    for k, item in enumerate(items_raw):
        here = f"{where}.items[{k}]"
        if not isinstance(item, Mapping):
            raise QuestionnaireError(
                f"{here}: expected a mapping with keys " + ", ".join(ITEM_KEYS[:4])
            )
        _reject_unknown(item, ITEM_KEYS[:4], here)
        item_id = item.get("id")
        if not isinstance(item_id, str) or not NAME.fullmatch(item_id):
            raise QuestionnaireError(
                f"{here}.id: expected an id of lower-case letters, digits, "
                f"_ or -, got {quote(item_id)}"
            )
        items.append(
            Item(
                item_id,
                _text(item.get("text"), f"{here}.text"),
                _text(item.get("low", low), f"{here}.low"),
                _text(item.get("high", high), f"{here}.high"),
                1,
                points,
            )
        )
    ids = [i.id for i in items]
    repeated = next((i for i in ids if ids.count(i) > 1), None)
    if repeated is not None:
        raise QuestionnaireError(f"{where}.items: id {repeated!r} is given twice")
    title = _text(raw.get("title", name), f"{where}.title")
    instructions = _text(
        raw.get("instructions", "Choose one answer for each statement."), f"{where}.instructions"
    )
    return Questionnaire(name, "likert", title, instructions, tuple(items))


def _text(value: Any, where: str) -> str:
    if not isinstance(value, str) or not value.strip() or len(value) > MAX_TEXT:
        raise QuestionnaireError(
            f"{where}: expected a text of 1 to {MAX_TEXT} characters, got {quote(value)}"
        )
    return value.strip()


def _reject_unknown(raw: Mapping[str, Any], valid: tuple[str, ...], where: str) -> None:
    unknown = [str(k) for k in raw if k not in valid]
    if unknown:
        raise QuestionnaireError(
            f"{where}: unknown key {quote(unknown[0])}; valid keys: " + ", ".join(valid)
        )
