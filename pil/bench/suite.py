"""The benchmark's suite file (``pil/bench/suite.yaml``), read and checked once.

:func:`load_suite` returns a :class:`Suite`: the tracks, the seed blocks (``dev`` for tuning,
``eval`` frozen), the detector / teacher conditions, the reference agents, the tuning grids,
the metrics and the analysis declared in advance. Anything malformed raises
:class:`SuiteError` naming the entry and the valid choices. :meth:`Suite.seeds` gives a
block's run seeds; :meth:`Suite.stamp` what every results file carries (version, file hash).
"""

from __future__ import annotations

import hashlib
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from pil.errors import RobinPilError, quote
from pil.task.yaml_files import read_small_text, read_yaml_mapping, reject_unknown

SUITE_FILE = Path(__file__).with_name("suite.yaml")
BLOCKS: tuple[str, ...] = ("dev", "eval")
TRACK_KINDS: tuple[str, ...] = ("assembly", "meaning-change", "transfer", "two-people", "physical")
GESTURE_MODELS: tuple[str, ...] = ("independent", "measured", "markov", "vision")
FEEDBACK_KEYS: tuple[str, ...] = ("silence", "misread", "missed", "late", "measured")
_TOP = ("version", "name", "seeds", "cap", "tracks", "conditions", "agents", "tuning")
_TOP_ALL = (*_TOP, "metrics", "analysis", "quick_conditions")
_TRACK_KEYS = (
    "description",
    "kind",
    "scenario",
    "change",
    "criterion",
    "second",
    "people",
    "quick",
    "slow",
    "conditions",
    "cap",
)


class SuiteError(RobinPilError):
    """A suite file that cannot be used (or a request it does not allow)."""


@dataclass(frozen=True)
class Track:
    """One track: its kind, options (scenario, change, ...), quick overrides, conditions."""

    name: str
    kind: str
    description: str
    options: Mapping[str, Any]
    quick: Mapping[str, int]
    conditions: tuple[str, ...]
    slow: bool = False
    cap: float | None = None  # this track's cap (None: the suite's)


@dataclass(frozen=True)
class Condition:
    """How gestures are read (``gestures``) and what happens to the thumbs (``feedback``)."""

    name: str
    gestures: Mapping[str, Any]
    feedback: Mapping[str, Any] = field(default_factory=dict)


@dataclass(frozen=True)
class Axis:
    """One tuned parameter: its grid, its hard bounds and how to extend it."""

    name: str
    values: tuple[float, ...]
    bounds: tuple[float, float]
    scale: str


@dataclass(frozen=True)
class Suite:
    """The whole suite file, checked (see the module docstring)."""

    version: str
    name: str
    masters: Mapping[str, int]
    counts: Mapping[str, int]
    quick_count: int
    quick_conditions: tuple[str, ...]
    cap: float
    tracks: Mapping[str, Track]
    conditions: Mapping[str, Condition]
    agents: tuple[str, ...]
    tuning_track: str
    tuning_conditions: tuple[str, ...]
    extend: int
    grids: Mapping[str, tuple[Axis, ...]]
    primary: str
    anchors: tuple[str, ...]
    alpha: float
    margin: float
    equivalence_anchor: str
    path: Path
    sha256: str

    def seeds(self, block: str, quick: bool = False) -> list[int]:
        """The run seeds of ``block`` (``dev`` or ``eval``); ``quick``: the first few."""
        from pil.experiments.study import rep_seeds

        if block not in BLOCKS:
            raise SuiteError(f"seed block {quote(block)}; valid choices: " + ", ".join(BLOCKS))
        seeds = rep_seeds(self.masters[block], self.counts[block])
        return seeds[: self.quick_count] if quick else seeds

    def stamp(self) -> dict[str, str]:
        """What every results file carries: the suite's version and its file's hash."""
        return {"suite_version": self.version, "suite_sha256": self.sha256}

    def track(self, name: str) -> Track:
        """The track ``name`` (an unknown one names the valid choices)."""
        if name not in self.tracks:
            raise SuiteError(
                f"unknown track {quote(name)}; valid choices: " + ", ".join(self.tracks)
            )
        return self.tracks[name]

    def track_conditions(self, name: str, quick: bool = False) -> tuple[str, ...]:
        """The conditions track ``name`` runs under (``quick``: those of ``quick_conditions``,
        or all of its own when it has none of them, as the physical track)."""
        found = self.track(name).conditions
        chosen = tuple(c for c in found if c in self.quick_conditions)
        return (chosen or found) if quick else found

    def cap_of(self, name: str) -> float:
        """Track ``name``'s cap: its own, else the suite's (x the scripted instructions)."""
        own = self.track(name).cap
        return self.cap if own is None else own

    def quick_tracks(self) -> tuple[str, ...]:
        """The tracks that run without MuJoCo (all but the slow ones)."""
        return tuple(n for n, t in self.tracks.items() if not t.slow)


def _number(value: Any, where: str, low: float, high: float) -> float:
    if isinstance(value, bool) or not isinstance(value, int | float) or not low <= value <= high:
        raise SuiteError(f"{where}: expected a number from {low:g} to {high:g}, got {quote(value)}")
    return float(value)


def _count(value: Any, where: str, low: int = 1) -> int:
    if isinstance(value, bool) or not isinstance(value, int) or value < low:
        raise SuiteError(f"{where}: expected a whole number >= {low}, got {quote(value)}")
    return value


def _mapping(raw: Mapping[str, Any], key: str, where: str) -> Mapping[str, Any]:
    value = raw.get(key)
    if not isinstance(value, Mapping) or not value:
        raise SuiteError(f"{where}: {key}: expected a mapping")
    return value


def _condition(name: str, raw: Any, base: Path) -> Condition:
    where = f"conditions.{name}"
    if not isinstance(raw, Mapping):
        raise SuiteError(f"{where}: expected a mapping with gestures (and feedback)")
    reject_unknown(raw, ("gestures", "feedback"), where, SuiteError)
    gestures = dict(_mapping(raw, "gestures", where))
    model = gestures.get("model")
    if model not in GESTURE_MODELS:
        raise SuiteError(
            f"{where}.gestures.model: {quote(model)}; valid choices: " + ", ".join(GESTURE_MODELS)
        )
    if model == "independent":
        gestures["rate"] = _number(gestures.get("rate"), f"{where}.gestures.rate", 0.0, 1.0)
    elif model == "measured":
        gestures["file"] = str((base / str(gestures.get("file"))).resolve())
    elif model == "markov":
        for key in ("good", "bad", "enter_bad", "leave_bad"):
            gestures[key] = _number(gestures.get(key), f"{where}.gestures.{key}", 0.0, 1.0)
    feedback = dict(raw.get("feedback") or {})
    reject_unknown(feedback, FEEDBACK_KEYS, f"{where}.feedback", SuiteError)
    for key in ("silence", "misread", "missed", "late"):
        if key in feedback:
            feedback[key] = _number(feedback[key], f"{where}.feedback.{key}", 0.0, 1.0)
    if "measured" in feedback:
        feedback["measured"] = str((base / str(feedback["measured"])).resolve())
    return Condition(name, gestures, feedback)


def _track(name: str, raw: Any, conditions: Mapping[str, Condition]) -> Track:
    """One track entry, checked (its own ``cap`` or None for the suite's)."""
    where = f"tracks.{name}"
    if not isinstance(raw, Mapping):
        raise SuiteError(f"{where}: expected a mapping")
    reject_unknown(raw, _TRACK_KEYS, where, SuiteError)
    kind = raw.get("kind")
    if kind not in TRACK_KINDS:
        raise SuiteError(f"{where}.kind: {quote(kind)}; valid choices: " + ", ".join(TRACK_KINDS))
    quick = {k: _count(v, f"{where}.quick.{k}") for k, v in (raw.get("quick") or {}).items()}
    learner_only = tuple(c for c, v in conditions.items() if v.gestures["model"] != "vision")
    chosen = tuple(raw.get("conditions") or learner_only)
    for c in chosen:
        if c not in conditions:
            raise SuiteError(f"{where}.conditions: {quote(c)}; valid: " + ", ".join(conditions))
    options = {k: v for k, v in raw.items() if k not in ("description", "kind", "quick", "slow")}
    options.pop("conditions", None)
    cap = options.pop("cap", None)
    return Track(
        name,
        kind,
        str(raw.get("description", "")),
        options,
        quick,
        chosen,
        bool(raw.get("slow")),
        None if cap is None else _number(cap, f"{where}.cap", 1.0, 1000.0),
    )


def _axes(agent: str, raw: Any) -> tuple[Axis, ...]:
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
        low, high = (_number(b, f"{at}.bounds", -1e9, 1e9) for b in bounds)
        values = spec.get("values")
        if not isinstance(values, Sequence) or len(values) < 2:
            raise SuiteError(f"{at}.values: expected at least two numbers")
        grid = tuple(sorted(_number(v, f"{at}.values", low, high) for v in values))
        scale = spec.get("scale")
        if scale not in ("log", "linear"):
            raise SuiteError(f"{at}.scale: {quote(scale)}; valid choices: log, linear")
        if scale == "log" and low < 0:
            raise SuiteError(f"{at}: a log axis needs bounds >= 0")
        axes.append(Axis(str(name), grid, (low, high), str(scale)))
    return tuple(axes)


def load_suite(path: str | Path = SUITE_FILE) -> Suite:
    """Read and check the suite file at ``path`` (default: the shipped one)."""
    path = Path(path)
    raw = read_yaml_mapping(path, "suite file", SuiteError, ("pil/bench/suite.yaml",))
    reject_unknown(raw, _TOP_ALL, str(path), SuiteError)
    for key in _TOP:
        if key not in raw:
            raise SuiteError(f"{path}: missing {key!r}")
    base = path.resolve().parent
    seeds = _mapping(raw, "seeds", "seeds")
    masters, counts = {}, {}
    for block in BLOCKS:
        spec = seeds.get(block)
        if not isinstance(spec, Mapping):
            raise SuiteError(f"seeds.{block}: expected {{master, count}}")
        masters[block] = _count(spec.get("master"), f"seeds.{block}.master", 0)
        counts[block] = _count(spec.get("count"), f"seeds.{block}.count", 2)
    conditions = {n: _condition(n, c, base) for n, c in _mapping(raw, "conditions", "").items()}
    tracks = {n: _track(n, t, conditions) for n, t in _mapping(raw, "tracks", "").items()}
    tuning = _mapping(raw, "tuning", "")
    analysis = raw.get("analysis") or {}
    equivalence = analysis.get("equivalence") or {}
    agents = tuple(str(a) for a in raw.get("agents") or ())
    anchors = tuple(str(a) for a in analysis.get("anchors") or ())
    for name in (*anchors, equivalence.get("anchor", anchors[0] if anchors else "")):
        if name not in agents:
            raise SuiteError(f"analysis: anchor {quote(name)} is not one of the agents")
    suite = Suite(
        version=str(raw["version"]),
        name=str(raw["name"]),
        masters=masters,
        counts=counts,
        quick_count=_count(seeds.get("quick", 3), "seeds.quick", 2),
        quick_conditions=tuple(str(c) for c in raw.get("quick_conditions") or conditions),
        cap=_number(raw["cap"], "cap", 1.0, 1000.0),
        tracks=tracks,
        conditions=conditions,
        agents=agents,
        tuning_track=str(tuning.get("track")),
        tuning_conditions=tuple(str(c) for c in tuning.get("conditions") or ()),
        extend=_count(tuning.get("extend", 4), "tuning.extend", 0),
        grids={str(a): _axes(str(a), g) for a, g in _mapping(tuning, "grids", "tuning").items()},
        primary=str((raw.get("metrics") or {}).get("primary", "actions")),
        anchors=anchors,
        alpha=_number(analysis.get("alpha", 0.05), "analysis.alpha", 0.0, 1.0),
        margin=_number(equivalence.get("margin", 5.0), "analysis.equivalence.margin", 0.0, 1e6),
        equivalence_anchor=str(equivalence.get("anchor", anchors[0] if anchors else "")),
        path=path,
        sha256=hashlib.sha256(read_small_text(path).encode("utf-8")).hexdigest(),
    )
    for c in suite.quick_conditions:
        if c not in conditions:
            raise SuiteError(f"quick_conditions: {quote(c)} is not a condition")
    if suite.tuning_track not in tracks:
        raise SuiteError(f"tuning.track: {quote(suite.tuning_track)} is not a track")
    for c in suite.tuning_conditions:
        if c not in conditions:
            raise SuiteError(f"tuning.conditions: {quote(c)} is not a condition")
    dev, evaluation = set(suite.seeds("dev")), set(suite.seeds("eval"))
    if dev & evaluation:
        raise SuiteError(f"the dev and eval seed blocks share seeds: {sorted(dev & evaluation)}")
    return suite
