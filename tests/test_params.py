"""Tests of the parameter specs: one conversion from text, one range per option, cut quotes."""

from __future__ import annotations

import pytest

from pil.errors import quote
from pil.task.params import ASSEMBLY, PARAMS, SEED, ParamError, ParamSpec, spec_for
from pil.task.runner import MAX_ACTIONS_PER_GESTURE


def test_text_and_typed_values_convert_alike() -> None:
    assert PARAMS["discard"].parse("0.3") == PARAMS["discard"].parse(0.3) == 0.3
    assert PARAMS["patience"].parse("2") == PARAMS["patience"].parse(2.0) == 2
    assert PARAMS["repeat_discarded"].parse("No") is False
    assert PARAMS["repeat_discarded"].parse(True) is True
    assert PARAMS["tables"].parse("") is None and PARAMS["tables"].parse(None) is None
    rows = PARAMS["confusion"].parse("0 .5 .5 0; .5 0 .5 0; .5 .5 0 0; 0 .5 .5 0")
    assert rows == PARAMS["confusion"].parse(str(rows)) and rows[0] == [0.0, 0.5, 0.5, 0.0]


@pytest.mark.parametrize(
    ("name", "value"),
    [
        ("discard", "nan"),
        ("discard", "inf"),
        ("discard", True),
        ("patience", "2.5"),
        ("patience", "1e400"),
        ("tables", "1001"),
        ("repeat_discarded", 2),
        ("detector", " "),
        ("confusion", "[[1, 0, 0, 0]]"),
        ("spots", 0),
    ],
)
def test_out_of_range_or_wrong_type_is_refused_naming_the_range(name: str, value: object) -> None:
    spec = PARAMS[name]
    with pytest.raises(ParamError) as caught:
        spec.parse(value)
    assert str(caught.value).startswith(f"parameter {name!r} must be {spec.valid()}")


def test_the_scenario_file_and_the_cli_share_the_assembly_ranges() -> None:
    from pil.task.scenario import ScenarioError, load_scenario

    for name, spec in ASSEMBLY.items():
        assert spec is PARAMS[name]
    with pytest.raises(ScenarioError, match=ASSEMBLY["spots"].valid()):
        load_scenario().with_changes(spots=13)


def test_defaults_are_the_loops_and_seeds_are_bounded() -> None:
    assert PARAMS["max_actions_per_gesture"].default == MAX_ACTIONS_PER_GESTURE
    assert SEED.parse("0") == 0 and SEED.parse(2**63 - 1) == 2**63 - 1
    with pytest.raises(ParamError, match="from 0 to"):
        SEED.parse(-1)


def test_specs_from_defaults_and_quotes() -> None:
    assert spec_for("n", 3).parse("4") == 4 and spec_for("x", 0.5).parse("1") == 1.0
    assert spec_for("flag", False).parse("on") is True and spec_for("s", "a").parse("b") == "b"
    assert spec_for("any", None).parse("7") == 7 and spec_for("any", None).parse("c1") == "c1"
    assert isinstance(spec_for("p", ParamSpec("p", "int", 1, "")), ParamSpec)
    assert quote("abc") == "'abc'" and len(quote("y" * 10**6)) < 120
