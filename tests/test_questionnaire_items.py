"""Questionnaire items of every kind: their checks, reverse scoring, subscales, attention
checks, the NASA-TLX's pairwise weights, forms, and the refusals at load."""

from __future__ import annotations

import pytest

from robin_sim.live.questionnaires import QuestionnaireError, load_form, load_questionnaires

EASE = {
    "name": "ease",
    "points": 5,
    "items": [
        {"id": "clear", "text": "Robin understood me.", "subscale": "fluency"},
        {"id": "slow", "text": "I waited.", "reverse": True, "subscale": "fluency"},
        {"id": "check", "text": "Choose 4.", "attention": 4},
        {"id": "liking", "text": "Liking", "kind": "vas"},
        {"id": "remarks", "text": "Remarks", "kind": "text", "optional": True, "max_length": 20},
    ],
}


def test_scores_reverse_items_make_subscales_and_keep_attention_apart() -> None:
    (ease,) = load_questionnaires([EASE], "here")
    answers = ease.check_answers({"clear": 4, "slow": 1, "check": 3, "liking": 70})
    assert answers["remarks"] == ""  # an optional item left open
    assert ease.scores(answers) == {
        "clear": 4.0,
        "slow": 5.0,  # 1 + 5 - 1
        "liking": 70.0,
        "fluency": 4.5,
        "mean": 4.5,  # the scale items only: the slider's 0-100 is never mixed in
    }
    assert ease.attention(answers) == {"check": False}
    shown = {i["id"]: i for i in ease.as_dict()["items"]}
    assert (shown["liking"]["kind"], shown["liking"]["min"], shown["liking"]["max"]) == (
        "vas",
        0,
        100,
    )
    assert "reverse" not in shown["slow"]  # the page is not told which items are reversed


@pytest.mark.parametrize(
    ("answers", "expected"),
    [
        ({"clear": 4, "slow": 1, "check": 3}, "please answer every question: 'Liking'"),
        (
            {"clear": 4, "slow": 1, "check": 3, "liking": 101},
            "ease.liking: expected a whole number from 0 to 100",
        ),
        (
            {"clear": 4, "slow": 1, "check": 3, "liking": 5, "remarks": "x" * 21},
            "at most 20 characters, got 21",
        ),
        (
            {"clear": 4, "slow": 1, "check": 3, "liking": 5, "remarks": 7},
            "at most 20 characters, got 7",
        ),
    ],
)
def test_the_server_checks_every_answer_of_every_kind(answers, expected) -> None:
    (ease,) = load_questionnaires([EASE], "here")
    with pytest.raises(QuestionnaireError, match=expected):
        ease.check_answers(answers)


def test_a_demographics_form_keeps_answers_and_scores_nothing() -> None:
    form = load_form(
        {
            "items": [
                {"id": "age", "text": "Age", "kind": "number", "min": 18, "max": 99},
                {"id": "hand", "text": "Hand", "kind": "choice", "choices": ["l", "r"],
                 "labels": ["left", "right"]},
            ]
        },
        "study.yaml: demographics",
        "demographics",
    )  # fmt: skip
    answers = form.check_answers({"age": 44, "hand": "r"})
    assert form.scores(answers) == {} and form.kind == "form"
    with pytest.raises(
        QuestionnaireError, match=r"demographics\.age: expected a whole number from 18"
    ):
        form.check_answers({"age": 7, "hand": "r"})
    with pytest.raises(QuestionnaireError, match="unknown choice 'right'; valid choices: l, r"):
        form.check_answers({"age": 30, "hand": "right"})


def test_the_weighted_nasa_tlx_weighs_each_rating_by_the_pairs_it_won() -> None:
    (tlx,) = load_questionnaires([{"preset": "nasa-tlx", "weighted": True}], "here")
    pairs = [i for i in tlx.items if i.kind == "choice"]
    assert len(tlx.items) == 21 and len(pairs) == 15
    ratings = {"mental": 80, "physical": 10, "temporal": 50, "performance": 40, "effort": 70,
               "frustration": 20}  # fmt: skip
    order = ["mental", "effort", "temporal", "performance", "frustration", "physical"]
    # the dimension ranked higher wins each pair: weights 5, 4, 3, 2, 1, 0
    won = {p.id: min(p.choices, key=order.index) for p in pairs}
    scores = tlx.scores(tlx.check_answers({**ratings, **won}))
    weights = {d: 5 - order.index(d) for d in ratings}
    assert {d: scores[f"weight_{d}"] for d in ratings} == weights
    assert scores["weighted_tlx"] == pytest.approx(
        sum(weights[d] * ratings[d] for d in ratings) / 15
    )
    assert scores["raw_tlx"] == pytest.approx(sum(ratings.values()) / 6)


@pytest.mark.parametrize(
    ("item", "expected"),
    [
        (
            {"id": "a", "text": "A", "kind": "slider"},
            "unknown kind 'slider'; valid choices: scale, vas",
        ),
        ({"id": "a", "text": "A", "min": 2}, "min: not for a scale item"),
        (
            {"id": "a", "text": "A", "attention": 9},
            "attention: expected a whole number from 1 to 5",
        ),
        ({"id": "a", "text": "A", "attention": 2, "reverse": True}, "not scored, so not reversed"),
        ({"id": "a", "text": "A", "kind": "choice", "choices": ["x"]}, "2 to 20 different texts"),
        (
            {
                "id": "a",
                "text": "A",
                "kind": "choice",
                "choices": ["x", "y"],
                "labels": ["X", "Y", "Z"],
            },
            "one label for each",
        ),
        ({"id": "a", "text": "A", "subscale": "b"}, None),  # fine alone
    ],
)
def test_item_mistakes_are_refused_at_load(item, expected) -> None:
    raw = [{"name": "q", "points": 5, "items": [item, {"id": "z", "text": "Z"}]}]
    if expected is None:
        load_questionnaires(raw, "here")
        return
    with pytest.raises(QuestionnaireError, match=expected):
        load_questionnaires(raw, "here")


def test_questionnaire_level_refusals() -> None:
    mixed = [
        {"id": "a", "text": "A", "subscale": "s"},
        {"id": "b", "text": "B", "kind": "vas", "subscale": "s"},
    ]
    with pytest.raises(QuestionnaireError, match="subscale 's' mixes scale and vas items"):
        load_questionnaires([{"name": "q", "items": mixed}], "here")
    with pytest.raises(QuestionnaireError, match="subscale 'a' has the name of an item"):
        load_questionnaires(
            [{"name": "q", "items": [{"id": "a", "text": "A", "subscale": "a"}]}], "here"
        )
    with pytest.raises(QuestionnaireError, match="no scored item"):
        load_questionnaires(
            [{"name": "q", "items": [{"id": "a", "text": "A", "kind": "text"}]}], "here"
        )
    with pytest.raises(
        QuestionnaireError, match="unknown key 'pairs'; preset nasa-tlx takes weighted"
    ):
        load_questionnaires([{"preset": "nasa-tlx", "pairs": True}], "here")
