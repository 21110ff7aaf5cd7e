"""The suite's declared comparisons beyond the anchors' families, read from ``analysis``.

* :class:`Focus` (``analysis.focus``): one entrant against each named opponent in each named
  (track, condition): paired t and Wilcoxon tests, one Holm family per test whose size is the
  declared number of comparisons (opponents x cells), whoever ran.
* :class:`NonInferiority` (``analysis.noninferiority``): the entrant against one anchor on one
  track in each named condition, one-sided: is the entrant no worse than the anchor by more
  than ``margin`` actions?

In both a failed run counts at the cap (the track's cap x the run's scripted gestures, the
most a run may cost) instead of dropping its pair (:mod:`pil.bench.focus`).
"""

from __future__ import annotations

from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass
from typing import Any

from pil.errors import RobinPilError, quote
from pil.task.yaml_files import reject_unknown


@dataclass(frozen=True)
class Focus:
    """One entrant against named opponents in named (track, condition) cells."""

    entrant: str
    against: tuple[str, ...]
    cells: tuple[tuple[str, str], ...]  # (track, condition)

    @property
    def size(self) -> int:
        """The declared family size per test: every opponent in every cell."""
        return len(self.against) * len(self.cells)


@dataclass(frozen=True)
class NonInferiority:
    """Entrant no worse than ``anchor`` by more than ``margin`` on ``track`` per condition."""

    entrant: str
    anchor: str
    track: str
    conditions: tuple[str, ...]
    margin: float


def _names(value: Any, where: str, error: type[RobinPilError]) -> tuple[str, ...]:
    if not isinstance(value, Sequence) or isinstance(value, str) or not value:
        raise error(f"{where}: expected a list of names")
    return tuple(str(v) for v in value)


def _agent(name: Any, agents: Sequence[str], where: str, error: type[RobinPilError]) -> str:
    if name not in agents:
        raise error(f"{where}: {quote(name)} is not one of the agents: " + ", ".join(agents))
    return str(name)


def parse_declared(
    analysis: Mapping[str, Any],
    agents: Sequence[str],
    track_conditions: Callable[[str], Sequence[str]],
    error: type[RobinPilError],
) -> tuple[Focus | None, NonInferiority | None]:
    """``analysis.focus`` and ``analysis.noninferiority`` checked against the agents and the
    tracks' conditions (``track_conditions(track)`` raises ``error`` for an unknown track)."""
    focus = None
    raw = analysis.get("focus")
    if raw is not None:
        where = "analysis.focus"
        if not isinstance(raw, Mapping):
            raise error(f"{where}: expected entrant, against and conditions")
        reject_unknown(raw, ("entrant", "against", "conditions"), where, error)
        entrant = _agent(raw.get("entrant"), agents, f"{where}.entrant", error)
        against = tuple(
            _agent(a, agents, f"{where}.against", error)
            for a in _names(raw.get("against"), f"{where}.against", error)
        )
        spec = raw.get("conditions")
        if not isinstance(spec, Mapping) or not spec:
            raise error(f"{where}.conditions: expected track: [conditions]")
        cells = []
        for track, names in spec.items():
            valid = track_conditions(str(track))
            for c in _names(names, f"{where}.conditions.{track}", error):
                if c not in valid:
                    raise error(
                        f"{where}.conditions.{track}: {quote(c)} is not one of the track's "
                        "conditions: " + ", ".join(valid)
                    )
                cells.append((str(track), c))
        focus = Focus(entrant, against, tuple(cells))
    return focus, _noninferiority(analysis, agents, track_conditions, error)


def _noninferiority(
    analysis: Mapping[str, Any],
    agents: Sequence[str],
    track_conditions: Callable[[str], Sequence[str]],
    error: type[RobinPilError],
) -> NonInferiority | None:
    raw = analysis.get("noninferiority")
    if raw is None:
        return None
    where = "analysis.noninferiority"
    if not isinstance(raw, Mapping):
        raise error(f"{where}: expected entrant, anchor, track, conditions and margin")
    reject_unknown(raw, ("entrant", "anchor", "track", "conditions", "margin"), where, error)
    track = str(raw.get("track"))
    valid = track_conditions(track)
    conditions = _names(raw.get("conditions"), f"{where}.conditions", error)
    for c in conditions:
        if c not in valid:
            raise error(f"{where}.conditions: {quote(c)}; valid: " + ", ".join(valid))
    margin = raw.get("margin")
    if isinstance(margin, bool) or not isinstance(margin, int | float) or margin < 0:
        raise error(f"{where}.margin: expected a number of actions >= 0, got {quote(margin)}")
    return NonInferiority(
        _agent(raw.get("entrant"), agents, f"{where}.entrant", error),
        _agent(raw.get("anchor"), agents, f"{where}.anchor", error),
        track,
        conditions,
        float(margin),
    )
