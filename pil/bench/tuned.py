"""A ``tuned.json`` (of ``robin-pil bench --tune``) read back and checked before any agent is built.

The file maps each tuned reference agent to its chosen ``params`` (and the tuning's ``score``,
``optimum`` and ``grid``). It is read through the guarded reader (a device, a FIFO or a folder
is refused before a byte is read; no NaN or infinities) and every entry is checked against the
suite: the agent is one of the suite's reference agents, its parameters are exactly the axes of
its tuning grid (``tuning.grids``; an agent without a grid takes none), each a finite number
within the axis's hard bounds. Anything else is one :class:`TunedFileError` naming the file,
the agent and the valid parameters, so no value ever reaches an agent's constructor unchecked.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from pathlib import Path
from typing import Any

from pil.bench.suite import Suite
from pil.errors import RobinPilError, quote
from pil.regular_files import read_json_file

WHERE_OPTIMUM = ("inside", "at bound", "at edge")  # pil.bench.tuning.where_optimum's answers


class TunedFileError(RobinPilError):
    """A tuned.json that cannot be used: the message names the file and the agent."""


def valid_params(suite: Suite, agent: str) -> str:
    """The parameters ``agent`` takes, with their ranges ("no parameters" for none)."""
    axes = suite.grids.get(agent, ())
    if not axes:
        return "takes no parameters"
    return "takes " + ", ".join(f"{a.name} ({a.bounds[0]:g}-{a.bounds[1]:g})" for a in axes)


def _number(value: Any) -> bool:
    return type(value) in (int, float) and math.isfinite(value)


def _entry_problem(suite: Suite, agent: str, entry: Any) -> str:
    """What is wrong with ``entry`` as ``agent``'s tuned parameters ("" if nothing)."""
    if not isinstance(entry, Mapping) or not isinstance(entry.get("params"), Mapping):
        return f"expected {{'params': {{name: number}}}}, got {quote(entry)}"
    params, axes = entry["params"], {a.name: a for a in suite.grids.get(agent, ())}
    if set(params) != set(axes):
        return f"parameters {quote(sorted(params))}"
    for name, value in params.items():
        low, high = axes[name].bounds
        if not _number(value) or not low <= value <= high:
            return f"{name} = {quote(value)}, not a number from {low:g} to {high:g}"
    optimum = entry.get("optimum", {})
    if not isinstance(optimum, Mapping) or any(
        k not in axes or v not in WHERE_OPTIMUM for k, v in optimum.items()
    ):
        return f"optimum {quote(optimum)}: each parameter " + " / ".join(WHERE_OPTIMUM)
    if "score" in entry and not _number(entry["score"]):
        return f"score {quote(entry['score'])}, not a finite number"
    return ""


def read_tuned(path: Path, suite: Suite) -> dict[str, dict[str, Any]]:
    """The checked tuned parameters of ``path`` (module docstring): agent -> its entry."""
    data = read_json_file(path, "settings", "the tuned parameters", finite=True)
    if not isinstance(data, dict):
        raise TunedFileError(
            f"{path}: expected a mapping of agent -> {{'params': ...}} (a tuned.json of robin-pil "
            f"bench --tune), got {type(data).__name__}"
        )
    for agent, entry in data.items():
        if agent not in suite.agents:
            raise TunedFileError(
                f"{path}: unknown agent {quote(agent)}; valid choices: " + ", ".join(suite.agents)
            )
        problem = _entry_problem(suite, agent, entry)
        if problem:
            raise TunedFileError(
                f"{path}: {agent}: {problem}; {agent} {valid_params(suite, agent)}"
            )
    return data
