"""Questionnaire items and questionnaires: what the page shows, the checks of an answer, scores.

An :class:`Item` is one question of a kind (:data:`ITEM_KINDS`):

* ``scale``: a whole number from ``minimum`` to ``maximum`` in steps of ``step`` (Likert points,
  the NASA-TLX 0-100 in fives, a Godspeed differential), shown as radio buttons;
* ``vas``: a visual analogue scale, a slider from 0 to 100 (whole numbers);
* ``number``: a whole number typed in (an age), from ``minimum`` to ``maximum``;
* ``choice``: one of ``choices`` (the page shows ``labels``);
* ``text``: free text of at most ``max_length`` characters.

A ``scale`` or ``vas`` item may be *reverse-scored* (its score is ``minimum + maximum -
answer``), count towards a *subscale*, or be an *attention check* (``attention``: the one answer
a reader gives; it is checked, kept apart and never scored). Any item may be ``optional``.

:meth:`Questionnaire.check_answers` checks one page submission (every required item once, each
on its scale) and :meth:`Questionnaire.scores` scores it (see :meth:`Questionnaire.scores`).
Pure Python.
"""

from __future__ import annotations

import statistics
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import Any

from pil.errors import RobinPilError, quote

ITEM_KINDS: tuple[str, ...] = ("scale", "vas", "number", "choice", "text")
TLX_PAIR = "tlx_pair"  # the subscale of the NASA-TLX's pairwise comparisons (choice items)
RATED: tuple[str, ...] = ("scale", "vas")  # the kinds that are scored
VAS_RANGE = (0, 100)
MAX_ANSWER_CHARS = 2000  # the longest free text an item may allow
Answer = int | str


class QuestionnaireError(RobinPilError):
    """A questionnaire definition, or a page's answers to one, that cannot be taken."""


@dataclass(frozen=True)
class Item:
    """One question (see the module doc); ``scale`` is the subscale it counts towards."""

    id: str
    text: str
    low: str = ""  # the anchor at the minimum (scale, vas)
    high: str = ""  # the anchor at the maximum
    minimum: int = 1
    maximum: int = 7
    step: int = 1
    scale: str = ""  # the subscale (Godspeed's scales, a custom subscale); "" for none
    kind: str = "scale"  # one of ITEM_KINDS
    reverse: bool = False
    attention: int | None = None  # an attention check's expected answer
    optional: bool = False
    choices: tuple[str, ...] = ()  # choice: the values sent
    labels: tuple[str, ...] = ()  # choice: what the page shows for each value
    max_length: int = 200  # text: characters at most

    @property
    def scored(self) -> bool:
        """Whether the item has a score (a rated item that is no attention check)."""
        return self.kind in RATED and self.attention is None

    def score(self, value: int) -> float:
        """The item's score of a checked answer (reversed when the item is)."""
        return float(self.minimum + self.maximum - value if self.reverse else value)

    def as_dict(self) -> dict[str, Any]:
        """What the page needs to show the item."""
        shown: dict[str, Any] = {"id": self.id, "kind": self.kind, "text": self.text}
        shown["optional"] = self.optional
        if self.kind in ("scale", "vas", "number"):
            shown.update(min=self.minimum, max=self.maximum, step=self.step)
        if self.kind in RATED:
            shown.update(low=self.low, high=self.high)
        if self.kind == "choice":
            shown.update(choices=list(self.choices), labels=list(self.labels or self.choices))
        if self.kind == "text":
            shown["max_length"] = self.max_length
        return shown

    def check(self, value: Any, where: str) -> Answer:
        """``value`` as this item's answer, or a :class:`QuestionnaireError` naming the item
        and what it takes."""
        if self.kind == "choice":
            if not isinstance(value, str) or value not in self.choices:
                raise QuestionnaireError(
                    f"{where}: unknown choice {quote(value)}; valid choices: "
                    + ", ".join(self.choices)
                )
            return value
        if self.kind == "text":
            if not isinstance(value, str) or len(value) > self.max_length:
                raise QuestionnaireError(
                    f"{where}: expected a text of at most {self.max_length} characters, got "
                    + (f"{len(value)} characters" if isinstance(value, str) else quote(value))
                )
            return value.strip()
        if (
            isinstance(value, bool)
            or not isinstance(value, int)
            or not self.minimum <= value <= self.maximum
            or (value - self.minimum) % self.step
        ):
            raise QuestionnaireError(
                f"{where}: expected a whole number from {self.minimum} to "
                f"{self.maximum} in steps of {self.step}, got {str(value)[:20]!r}"
            )
        return value


@dataclass(frozen=True)
class Questionnaire:
    """A checked questionnaire; ``kind`` is ``nasa-tlx``, ``godspeed``, ``likert`` (a custom
    one, of any item kinds) or ``form`` (demographics: answers, no scores). ``weighted``: the
    NASA-TLX with its pairwise weighting (:mod:`robin_sim.live.questionnaire_presets`)."""

    name: str
    kind: str
    title: str
    instructions: str
    items: tuple[Item, ...]
    weighted: bool = False

    def as_dict(self) -> dict[str, Any]:
        """What the page needs to show it."""
        return {
            "name": self.name,
            "kind": self.kind,
            "title": self.title,
            "instructions": self.instructions,
            "items": [item.as_dict() for item in self.items],
        }

    def check_answers(self, answers: Any) -> dict[str, Answer]:
        """``answers`` (item id -> answer) checked: every required item once, on its scale;
        an optional item left out is kept as ``""``."""
        if not isinstance(answers, Mapping):
            raise QuestionnaireError(f"{self.name}: answers must be an object of item id -> number")
        ids = [item.id for item in self.items]
        unknown = [str(k) for k in answers if k not in ids]
        if unknown:
            raise QuestionnaireError(
                f"{self.name}: unknown item {quote(unknown[0])}; items: " + ", ".join(ids)
            )
        missing = [
            item.text
            for item in self.items
            if not item.optional and (item.id not in answers or answers[item.id] == "")
        ]
        if missing:
            more = f" and {len(missing) - 1} more" if len(missing) > 1 else ""
            raise QuestionnaireError(
                f"please answer every question: {missing[0]!r}{more} not answered yet"
            )
        checked: dict[str, Answer] = {}
        for item in self.items:
            value = answers.get(item.id, "")
            if item.optional and value in ("", None):
                checked[item.id] = ""
                continue
            checked[item.id] = item.check(value, f"{self.name}.{item.id}")
        return checked

    def attention(self, answers: Mapping[str, Answer]) -> dict[str, bool]:
        """Each attention check's item id -> whether the answer was the one asked for."""
        checks = [i for i in self.items if i.attention is not None]
        return {i.id: answers.get(i.id) == i.attention for i in checks}

    def scores(self, answers: Mapping[str, Answer]) -> dict[str, float]:
        """The scores of checked ``answers``. NASA-TLX: ``raw_tlx`` (the mean of the six
        ratings) and, weighted, ``weighted_tlx`` (each rating times the number of its 15 pairs
        it won, summed, over 15) with each ``weight_<dimension>``. Godspeed: one mean per
        scale. A custom questionnaire: each scored item's score (reversed where marked), each
        subscale's mean and ``mean`` over its scored scale items (over its VAS items when it has
        no scale item: the two ranges are never mixed; attention checks, texts, choices and
        numbers are not scored); a form: none."""
        if self.kind == "nasa-tlx":
            return self._tlx(answers)
        rated = [i for i in self.items if i.scored and answers.get(i.id, "") != ""]
        scales: dict[str, list[float]] = {}
        for item in rated:
            if item.scale:
                scales.setdefault(item.scale, []).append(item.score(int(answers[item.id])))
        if self.kind == "godspeed":
            return {scale: statistics.fmean(values) for scale, values in scales.items()}
        if self.kind == "form" or not rated:
            return {}
        scores = {i.id: i.score(int(answers[i.id])) for i in rated}
        subscales = {name: statistics.fmean(values) for name, values in scales.items()}
        points = [scores[i.id] for i in rated if i.kind == "scale"] or list(scores.values())
        return {**scores, **subscales, "mean": statistics.fmean(points)}

    def score_ranges(self) -> dict[str, list[float]]:
        """Each score of :meth:`scores` -> ``[lowest, highest]``: the span of its items (a
        NASA-TLX weight: 0 to the number of pairs). Saved with the scores, so that a report
        can refuse a score off its scale."""

        def span(items: Sequence[Item]) -> list[float]:
            return [float(min(i.minimum for i in items)), float(max(i.maximum for i in items))]

        if self.kind == "nasa-tlx":
            ratings = [i for i in self.items if i.kind == "scale"]
            out = {"raw_tlx": span(ratings)}
            pairs = sum(1 for i in self.items if i.scale == TLX_PAIR)
            if pairs:
                out["weighted_tlx"] = span(ratings)
                out.update({f"weight_{i.id}": [0.0, float(pairs)] for i in ratings})
            return out
        rated = [i for i in self.items if i.scored]
        scales: dict[str, list[Item]] = {}
        for item in rated:
            if item.scale:
                scales.setdefault(item.scale, []).append(item)
        subscales = {name: span(items) for name, items in scales.items()}
        if self.kind == "godspeed":
            return subscales
        if self.kind == "form" or not rated:
            return {}
        points = [i for i in rated if i.kind == "scale"] or rated
        return {**{i.id: span([i]) for i in rated}, **subscales, "mean": span(points)}

    def _tlx(self, answers: Mapping[str, Answer]) -> dict[str, float]:
        ratings = {i.id: int(answers[i.id]) for i in self.items if i.kind == "scale"}
        scores = {"raw_tlx": statistics.fmean(ratings.values())}
        pairs = [str(answers[i.id]) for i in self.items if i.scale == TLX_PAIR]
        if pairs:
            weights = {name: pairs.count(name) for name in ratings}
            total = sum(weights[n] * ratings[n] for n in ratings) / len(pairs)
            scores["weighted_tlx"] = total
            scores.update({f"weight_{n}": float(w) for n, w in weights.items()})
        return scores
