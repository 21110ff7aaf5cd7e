"""The sweep's physical kind: its parameters (a physical run's row: tests/test_spine.py)."""

from __future__ import annotations

import pytest

from pil.errors import InvalidChoiceError
from pil.experiments.sweep_grid import parse_param
from robin_sim.episode.physical_run import PHYSICAL_RUNS


def test_an_unknown_parameter_lists_the_valid_ones() -> None:
    with pytest.raises(InvalidChoiceError, match="discard"):
        parse_param("discrad=0.3", PHYSICAL_RUNS)
