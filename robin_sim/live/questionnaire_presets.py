"""The preset questionnaires: NASA-TLX (raw, or with its pairwise weighting) and Godspeed.

* ``nasa-tlx``: mental, physical and temporal demand, performance (*perfect* to *failure*),
  effort and frustration, each 0-100 in steps of 5. With ``weighted``, the 15 pairs of the six
  dimensions follow, each a choice of the one that contributed more to the workload; a
  dimension's weight is the number of pairs it won (0-5, 15 in all).
* ``godspeed``: anthropomorphism (5 items), animacy (6), likeability (5), perceived
  intelligence (5) and perceived safety (3), each a 1-5 semantic differential.

Their scores: :meth:`robin_sim.live.items.Questionnaire.scores`. Pure Python.
"""

from __future__ import annotations

from collections.abc import Callable
from itertools import combinations

from robin_sim.live.items import TLX_PAIR, Item, Questionnaire

# id, question, low anchor, high anchor, the short name a pairwise comparison shows
TLX_DIMENSIONS: tuple[tuple[str, str, str, str, str], ...] = (
    (
        "mental",
        "Mental demand: how much thinking, deciding and remembering did the task take?",
        "very low",
        "very high",
        "Mental demand",
    ),
    (
        "physical",
        "Physical demand: how much physical activity did the task take?",
        "very low",
        "very high",
        "Physical demand",
    ),
    (
        "temporal",
        "Temporal demand: how hurried or rushed was the pace of the task?",
        "very low",
        "very high",
        "Temporal demand",
    ),
    (
        "performance",
        "Performance: how well did you do what you were asked to do?",
        "perfect",
        "failure",
        "Performance",
    ),
    (
        "effort",
        "Effort: how hard did you have to work to reach your level of performance?",
        "very low",
        "very high",
        "Effort",
    ),
    (
        "frustration",
        "Frustration: how insecure, discouraged, irritated or stressed did you feel?",
        "very low",
        "very high",
        "Frustration",
    ),
)
PAIR_QUESTION = "Which of the two contributed more to the workload of the block?"


def nasa_tlx(weighted: bool = False) -> Questionnaire:
    """The NASA-TLX: six ratings, and with ``weighted`` its 15 pairwise comparisons."""
    items = [Item(i, text, lo, hi, 0, 100, 5) for i, text, lo, hi, _ in TLX_DIMENSIONS]
    if weighted:
        short = {row[0]: row[4] for row in TLX_DIMENSIONS}
        for a, b in combinations(short, 2):
            items.append(
                Item(
                    f"pair_{a}_{b}",
                    PAIR_QUESTION,
                    scale=TLX_PAIR,
                    kind="choice",
                    choices=(a, b),
                    labels=(short[a], short[b]),
                )
            )
    instructions = "Rate the block you have just finished on each scale."
    if weighted:
        instructions += " Then, for each pair, choose the one that mattered more."
    return Questionnaire(
        "nasa-tlx", "nasa-tlx", "Workload (NASA-TLX)", instructions, tuple(items), weighted
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


def godspeed() -> Questionnaire:
    """Godspeed: five scales of 1-5 semantic differentials."""
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


# preset name -> its questionnaire (nasa-tlx takes ``weighted``)
PRESETS: dict[str, Callable[..., Questionnaire]] = {"nasa-tlx": nasa_tlx, "godspeed": godspeed}
PRESET_OPTIONS: dict[str, tuple[str, ...]] = {"nasa-tlx": ("weighted",), "godspeed": ()}
