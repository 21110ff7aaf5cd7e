"""A learner-only run's row from values given as text or typed, for the tests (not collected).

:func:`learner_row` parses its arguments once (:func:`pil.task.spec.parse_run_spec`) and
runs the spec (:func:`pil.experiments.run_row.spec_row`), as a study or a sweep's learner kind
does with values it parsed.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

from pil.experiments.run_row import spec_row
from pil.task.scenario import Scenario
from pil.task.spec import parse_run_spec


def learner_row(
    system: str,
    rate: Any,
    seed: Any,
    *,
    scenario: Scenario | str | Path | None = None,
    **params: Any,
) -> dict[str, Any]:
    """The row of one learner-only run of ``system`` at ``rate`` with ``seed`` and ``params``."""
    spec = parse_run_spec(system=system, rate=rate, seed=seed, scenario=scenario, params=params)
    return spec_row(spec)
