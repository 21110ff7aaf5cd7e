"""Questionnaires a participant answers on the live page, read from a protocol or study file.

A ``questionnaires`` list names presets (:mod:`robin_sim.live.questionnaire_presets`) or
defines questionnaires of items (:mod:`robin_sim.live.items`)::

    questionnaires:
      - nasa-tlx                 # NASA-TLX raw: six items, 0-100 in steps of 5
      - {preset: nasa-tlx, weighted: true}   # ... with its 15 pairwise comparisons
      - godspeed                 # Godspeed: five scales of 5-point semantic differentials
      - name: trust              # a custom questionnaire
        title: Your trust in the robot
        points: 7                # 2 to 11 answer points of its scale items (default 7)
        low: strongly disagree   # the anchors of every scale item (an item may give its own)
        high: strongly agree
        items:
          - {id: reliable, text: The robot did what I meant., subscale: trust}
          - {id: wary, text: I was wary of the robot., reverse: true, subscale: trust}
          - {id: check, text: Please choose 2 here., attention: 2}
          - {id: liking, text: How much did you like it?, kind: vas, low: not at all, high: very}
          - {id: remarks, text: Anything else?, kind: text, optional: true}

:func:`load_questionnaires` checks every field and :func:`load_form` a form of the same items
(a study's demographics: choice, number and text items); :class:`QuestionnaireError` names
the problem and the valid choices. Pure Python.
"""

from __future__ import annotations

import re
from collections.abc import Mapping
from typing import Any

from pil.errors import quote
from pil.task.yaml_files import reject_unknown
from robin_sim.live.items import (
    ITEM_KINDS,
    MAX_ANSWER_CHARS,
    VAS_RANGE,
    Item,
    Questionnaire,
    QuestionnaireError,
)
from robin_sim.live.questionnaire_presets import GODSPEED_SCALES, PRESET_OPTIONS, PRESETS

__all__ = [
    "GODSPEED_SCALES",
    "PRESETS",
    "Item",
    "Questionnaire",
    "QuestionnaireError",
    "load_form",
    "load_questionnaires",
]
QUESTIONNAIRE_KEYS: tuple[str, ...] = (
    "name",
    "title",
    "instructions",
    "points",
    "low",
    "high",
    "items",
)
FORM_KEYS: tuple[str, ...] = ("title", "instructions", "items")
ITEM_KEYS: tuple[str, ...] = (
    "id",
    "text",
    "kind",
    "low",
    "high",
    "reverse",
    "subscale",
    "attention",
    "optional",
    "choices",
    "labels",
    "min",
    "max",
    "max_length",
)
KIND_KEYS: dict[str, tuple[str, ...]] = {  # the keys each item kind takes besides id and text
    "scale": ("low", "high", "reverse", "subscale", "attention", "optional"),
    "vas": ("low", "high", "reverse", "subscale", "attention", "optional"),
    "number": ("min", "max", "optional"),
    "choice": ("choices", "labels", "optional"),
    "text": ("max_length", "optional"),
}
MAX_ITEMS, MAX_TEXT, MAX_CHOICES, MAX_NUMBER = 60, 300, 20, 1_000_000
NAME = re.compile(r"[a-z][a-z0-9_-]{0,39}")


def load_questionnaires(raw: Any, where: str) -> tuple[Questionnaire, ...]:
    """The ``questionnaires`` list checked (None: none)."""
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


def load_form(raw: Any, where: str, name: str) -> Questionnaire:
    """A form (kind ``form``: answers kept, nothing scored) of items of any kind."""
    if not isinstance(raw, Mapping):
        raise QuestionnaireError(f"{where}: expected a mapping with keys " + ", ".join(FORM_KEYS))
    reject_unknown(raw, FORM_KEYS, where, QuestionnaireError, "valid keys:")
    items = _items(raw.get("items"), where, 7, "", "")
    title = _text(raw.get("title", name.capitalize()), f"{where}.title")
    instructions = _text(
        raw.get("instructions", "Please answer these questions."), f"{where}.instructions"
    )
    return Questionnaire(name, "form", title, instructions, items)


def _one(raw: Any, where: str) -> Questionnaire:
    if isinstance(raw, str) or (isinstance(raw, Mapping) and "preset" in raw):
        return _preset(raw, where)
    if not isinstance(raw, Mapping):
        raise QuestionnaireError(
            f"{where}: expected a preset name or a mapping with keys "
            + ", ".join(QUESTIONNAIRE_KEYS)
        )
    reject_unknown(raw, QUESTIONNAIRE_KEYS, where, QuestionnaireError, "valid keys:")
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
    items = _items(raw.get("items"), where, points, low, high)
    if not any(i.scored for i in items):
        raise QuestionnaireError(
            f"{where}.items: no scored item (a scale or vas item that is no attention check); "
            "a questionnaire of choices, numbers or texts only is a form"
        )
    title = _text(raw.get("title", name), f"{where}.title")
    instructions = _text(
        raw.get("instructions", "Choose one answer for each statement."), f"{where}.instructions"
    )
    return Questionnaire(name, "likert", title, instructions, items)


def _preset(raw: Any, where: str) -> Questionnaire:
    entry = {"preset": raw} if isinstance(raw, str) else dict(raw)
    name = entry.pop("preset")
    if not isinstance(name, str) or name not in PRESETS:
        raise QuestionnaireError(
            f"{where}: unknown preset {quote(name)}; valid choices: "
            + ", ".join(PRESETS)
            + " (or a mapping with items)"
        )
    options = PRESET_OPTIONS[name]
    reject_unknown(entry, options, where, QuestionnaireError, f"preset {name} takes")
    for key, value in entry.items():
        if not isinstance(value, bool):
            raise QuestionnaireError(f"{where}.{key}: expected true or false, got {quote(value)}")
    return PRESETS[name](**entry)


def _items(raw: Any, where: str, points: int, low: str, high: str) -> tuple[Item, ...]:
    if not isinstance(raw, list) or not 1 <= len(raw) <= MAX_ITEMS:
        raise QuestionnaireError(
            f"{where}.items: expected a list of 1 to {MAX_ITEMS} items, "
            "each a mapping with keys " + ", ".join(ITEM_KEYS[:4])
        )
    items = [_item(item, f"{where}.items[{k}]", points, low, high) for k, item in enumerate(raw)]
    ids = [i.id for i in items]
    repeated = next((i for i in ids if ids.count(i) > 1), None)
    if repeated is not None:
        raise QuestionnaireError(f"{where}.items: id {repeated!r} is given twice")
    kinds: dict[str, set[str]] = {}
    for item in items:
        if item.scale:
            kinds.setdefault(item.scale, set()).add(item.kind)
    mixed = next((name for name, found in kinds.items() if len(found) > 1), None)
    if mixed is not None:
        raise QuestionnaireError(
            f"{where}.items: subscale {mixed!r} mixes scale and vas items; a subscale's items "
            "share one range"
        )
    clash = next((i.scale for i in items if i.scale in (*ids, "mean")), None)
    if clash is not None:
        raise QuestionnaireError(
            f"{where}.items: subscale {clash!r} has the name of an item or of the score 'mean'; "
            "give it a name of its own"
        )
    return tuple(items)


def _item(raw: Any, here: str, points: int, low: str, high: str) -> Item:
    if not isinstance(raw, Mapping):
        keys = ", ".join(ITEM_KEYS[:4])
        raise QuestionnaireError(f"{here}: expected a mapping with keys {keys}")
    reject_unknown(raw, ITEM_KEYS, here, QuestionnaireError, "valid keys:")
    item_id = raw.get("id")
    if not isinstance(item_id, str) or not NAME.fullmatch(item_id):
        raise QuestionnaireError(
            f"{here}.id: expected an id of lower-case letters, digits, _ or -, got {quote(item_id)}"
        )
    kind = raw.get("kind", "scale")
    if kind not in ITEM_KINDS:
        raise QuestionnaireError(
            f"{here}.kind: unknown kind {quote(kind)}; valid choices: " + ", ".join(ITEM_KINDS)
        )
    wrong = [k for k in raw if k not in ("id", "text", "kind", *KIND_KEYS[kind])]
    if wrong:
        raise QuestionnaireError(
            f"{here}.{wrong[0]}: not for a {kind} item; a {kind} item takes "
            + ", ".join(KIND_KEYS[kind])
        )
    text = _text(raw.get("text"), f"{here}.text")
    optional = _flag(raw, "optional", here)
    if kind == "choice":
        choices = _choices(raw.get("choices"), f"{here}.choices")
        labels = raw.get("labels", choices)
        if labels is not choices:
            labels = _choices(labels, f"{here}.labels")
            if len(labels) != len(choices):
                raise QuestionnaireError(f"{here}.labels: give one label for each of the choices")
        return Item(item_id, text, kind=kind, choices=choices, labels=labels, optional=optional)
    if kind == "text":
        length = _whole(raw.get("max_length", 200), f"{here}.max_length", 1, MAX_ANSWER_CHARS)
        return Item(item_id, text, kind=kind, max_length=length, optional=optional)
    if kind == "number":
        least = _whole(raw.get("min", 0), f"{here}.min", -MAX_NUMBER, MAX_NUMBER)
        most = _whole(raw.get("max", 120), f"{here}.max", least + 1, MAX_NUMBER)
        return Item(item_id, text, minimum=least, maximum=most, kind=kind, optional=optional)
    least, most = VAS_RANGE if kind == "vas" else (1, points)
    attention = raw.get("attention")
    if attention is not None:
        attention = _whole(attention, f"{here}.attention", least, most)
    reverse = _flag(raw, "reverse", here)
    if reverse and attention is not None:
        raise QuestionnaireError(f"{here}: an attention check is not scored, so not reversed")
    subscale = raw.get("subscale", "")
    if subscale and (not isinstance(subscale, str) or not NAME.fullmatch(subscale)):
        raise QuestionnaireError(
            f"{here}.subscale: expected a name of lower-case letters, digits, _ or -, got "
            f"{quote(subscale)}"
        )
    return Item(
        item_id,
        text,
        _text(raw.get("low", low or "low"), f"{here}.low"),
        _text(raw.get("high", high or "high"), f"{here}.high"),
        least,
        most,
        scale=subscale,
        kind=kind,
        reverse=reverse,
        attention=attention,
        optional=optional,
    )


def _choices(value: Any, where: str) -> tuple[str, ...]:
    if (
        not isinstance(value, list)
        or not 2 <= len(value) <= MAX_CHOICES
        or not all(isinstance(v, str) and v.strip() and len(v) <= 60 for v in value)
        or len(set(value)) != len(value)
    ):
        raise QuestionnaireError(
            f"{where}: expected a list of 2 to {MAX_CHOICES} different texts of 1 to 60 "
            f"characters, got {quote(value)}"
        )
    return tuple(value)


def _flag(raw: Mapping[str, Any], key: str, where: str) -> bool:
    value = raw.get(key, False)
    if not isinstance(value, bool):
        raise QuestionnaireError(f"{where}.{key}: expected true or false, got {quote(value)}")
    return value


def _whole(value: Any, where: str, low: int, high: int) -> int:
    if isinstance(value, bool) or not isinstance(value, int) or not low <= value <= high:
        raise QuestionnaireError(
            f"{where}: expected a whole number from {low} to {high}, got {quote(value)}"
        )
    return value


def _text(value: Any, where: str) -> str:
    if not isinstance(value, str) or not value.strip() or len(value) > MAX_TEXT:
        raise QuestionnaireError(
            f"{where}: expected a text of 1 to {MAX_TEXT} characters, got {quote(value)}"
        )
    return value.strip()
