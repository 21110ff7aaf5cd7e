"""A scenario's ``layout`` section, parsed when the scenario is loaded (typed from there on).

``legs``: a list of ``[x, y]``, ``[x, y, yaw_deg]`` or ``{x, y, yaw_deg}``; ``spots``: a list
of ``[x, y]`` or ``{x, y}``; ``handover``: ``[x, y, z]``; ``bin``: ``[x, y]`` (metres, degrees).
A missing key keeps the scene's default. Whether the robot can work there (on the table, in
reach, clear of each other) is the scene's check (``robin_sim.model.scene.SceneLayout.of``).
Nothing here imports MuJoCo.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import Any

from pil.errors import RobinPilError

LAYOUT_KEYS: tuple[str, ...] = ("legs", "spots", "handover", "bin")
LegPose = tuple[float, float, float]  # x, y (m), yaw (rad) of a leg lying on the table
Spot = tuple[float, float]


class LayoutError(RobinPilError):
    """A scene layout that is malformed, or puts a leg, spot or handover where the robot
    cannot work."""


@dataclass(frozen=True, slots=True)
class LayoutSection:
    """The parsed section; None keeps the scene's default."""

    legs: tuple[LegPose, ...] | None = None
    spots: tuple[Spot, ...] | None = None
    handover: tuple[float, float, float] | None = None
    bin: tuple[float, float] | None = None


def parse_layout(mapping: object) -> LayoutSection:
    """The section ``mapping`` (None or ``{}``: all defaults), or one :class:`LayoutError`."""
    if mapping is None:
        return LayoutSection()
    if not isinstance(mapping, Mapping):
        raise LayoutError(
            f"layout must be a mapping with keys {list(LAYOUT_KEYS)}, got {mapping!r}"
        )
    unknown = sorted(str(k) for k in set(mapping) - set(LAYOUT_KEYS))
    if unknown:
        raise LayoutError(f"unknown layout key(s) {unknown}; valid keys: {list(LAYOUT_KEYS)}")
    legs = spots = handover = bin_xy = None
    if "legs" in mapping:
        legs = tuple(_leg(i, v) for i, v in enumerate(_sequence(mapping, "legs")))
    if "spots" in mapping:
        spots = tuple(
            _point(f"spot {k}", v, ("x", "y")) for k, v in enumerate(_sequence(mapping, "spots"))
        )
    if "handover" in mapping:
        handover = _point("handover", mapping["handover"], ("x", "y", "z"))
    if "bin" in mapping:
        bin_xy = _point("bin", mapping["bin"], ("x", "y"))
    return LayoutSection(legs, spots, handover, bin_xy)  # type: ignore[arg-type]


def _sequence(mapping: Mapping[str, Any], key: str) -> Sequence[Any]:
    value = mapping[key]
    if isinstance(value, str | bytes) or not isinstance(value, Sequence):
        raise LayoutError(f"layout {key!r} must be a list, got {value!r}")
    return value


def _number(what: str, value: Any) -> float:
    if isinstance(value, bool) or not isinstance(value, int | float) or not math.isfinite(value):
        raise LayoutError(f"{what} must be a finite number, got {value!r}")
    return float(value)


def _point(what: str, value: Any, keys: tuple[str, ...]) -> tuple[float, ...]:
    if isinstance(value, Mapping):
        if set(value) != set(keys):
            raise LayoutError(f"{what} needs exactly the keys {list(keys)}, got {sorted(value)}")
        value = [value[k] for k in keys]
    if isinstance(value, str | bytes) or not isinstance(value, Sequence) or len(value) != len(keys):
        raise LayoutError(f"{what} must be [{', '.join(keys)}], got {value!r}")
    return tuple(_number(f"{what} {k}", v) for k, v in zip(keys, value, strict=True))


def _leg(index: int, value: Any) -> LegPose:
    what = f"leg {index}"
    if isinstance(value, Mapping):
        extra = sorted(set(value) - {"x", "y", "yaw_deg"})
        if extra or not {"x", "y"} <= set(value):
            raise LayoutError(f"{what} needs keys x, y and optionally yaw_deg; got {sorted(value)}")
        value = [value["x"], value["y"], value.get("yaw_deg", 0.0)]
    if isinstance(value, str | bytes) or not isinstance(value, Sequence):
        value = ()
    if len(value) not in (2, 3):
        raise LayoutError(f"{what} must be [x, y] or [x, y, yaw_deg], got {value!r}")
    x, y = _number(f"{what} x", value[0]), _number(f"{what} y", value[1])
    yaw = math.radians(_number(f"{what} yaw_deg", value[2])) if len(value) == 3 else 0.0
    return (x, y, yaw)
