"""The suite file's building blocks: its error, its checked fields and its tuning axes.

:class:`SuiteError` is what any unusable suite entry raises (naming the entry and the valid
choices); :func:`number`, :func:`count` and :func:`mapping` check one field;
:func:`parse_axes` reads one agent's tuning grid into :class:`Axis` objects.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import Any

from pil.errors import RobinPilError, quote
from pil.task.yaml_files import reject_unknown


class SuiteError(RobinPilError):
    """A suite file that cannot be used (or a request it does not allow)."""


@dataclass(frozen=True)
class Axis:
    """One tuned parameter: its grid, its hard bounds and how to extend it."""

    name: str
    values: tuple[float, ...]
    bounds: tuple[float, float]
    scale: str


def number(value: Any, where: str, low: float, high: float) -> float:
    """``value`` as a number in [low, high] (``where`` names the entry in the error)."""
    if isinstance(value, bool) or not isinstance(value, int | float) or not low <= value <= high:
        raise SuiteError(f"{where}: expected a number from {low:g} to {high:g}, got {quote(value)}")
    return float(value)


def count(value: Any, where: str, low: int = 1) -> int:
    """``value`` as a whole number >= ``low``."""
    if isinstance(value, bool) or not isinstance(value, int) or value < low:
        raise SuiteError(f"{where}: expected a whole number >= {low}, got {quote(value)}")
    return value


def mapping(raw: Mapping[str, Any], key: str, where: str) -> Mapping[str, Any]:
    """``raw[key]`` as a non-empty mapping."""
    value = raw.get(key)
    if not isinstance(value, Mapping) or not value:
        raise SuiteError(f"{where}: {key}: expected a mapping")
    return value


def parse_axes(agent: str, raw: Any) -> tuple[Axis, ...]:
    """``tuning.grids.<agent>``: each parameter's values, hard bounds and scale."""
    where = f"tuning.grids.{agent}"
    if not isinstance(raw, Mapping) or not raw:
        raise SuiteError(f"{where}: expected parameter: {{values, bounds, scale}}")
    axes = []
    for name, spec in raw.items():
        at = f"{where}.{name}"
        if not isinstance(spec, Mapping):
            raise SuiteError(f"{at}: expected values, bounds and scale")
        reject_unknown(spec, ("values", "bounds", "scale"), at, SuiteError)
        bounds = spec.get("bounds")
        if not isinstance(bounds, Sequence) or len(bounds) != 2:
            raise SuiteError(f"{at}.bounds: expected [low, high]")
        low, high = (number(b, f"{at}.bounds", -1e9, 1e9) for b in bounds)
        values = spec.get("values")
        if not isinstance(values, Sequence) or len(values) < 2:
            raise SuiteError(f"{at}.values: expected at least two numbers")
        grid = tuple(sorted(number(v, f"{at}.values", low, high) for v in values))
        scale = spec.get("scale")
        if scale not in ("log", "linear"):
            raise SuiteError(f"{at}.scale: {quote(scale)}; valid choices: log, linear")
        if scale == "log" and low < 0:
            raise SuiteError(f"{at}: a log axis needs bounds >= 0")
        axes.append(Axis(str(name), grid, (low, high), str(scale)))
    return tuple(axes)
