"""The benchmark's suite file (``pil/bench/suite.yaml``), read and checked once.

:func:`load_suite` returns a :class:`Suite`: the tracks, the seed blocks (``dev`` for tuning,
``eval`` frozen), the detector / teacher conditions, the reference agents, the tuning grids,
the metrics and the analysis declared in advance. Anything malformed raises
:class:`SuiteError` naming the entry and the valid choices. :meth:`Suite.seeds` gives a
block's run seeds; :meth:`Suite.stamp` what every results file carries (version, file hash).
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from pil.bench.declared import Focus, NonInferiority, parse_declared
from pil.bench.fingerprint import condition_files, fingerprint, staleness
from pil.bench.suite_fields import Axis, SuiteError, count, mapping, number, parse_axes
from pil.errors import RobinPilError, quote
from pil.task.params import RATE
from pil.task.yaml_files import read_small_text, read_yaml_mapping, reject_unknown

SUITE_FILE = Path(__file__).with_name("suite.yaml")
BLOCKS: tuple[str, ...] = ("dev", "eval")
TRACK_KINDS: tuple[str, ...] = ("assembly", "meaning-change", "transfer", "two-people", "physical")
GESTURE_MODELS: tuple[str, ...] = ("independent", "measured", "markov", "vision")
FEEDBACK_KEYS: tuple[str, ...] = ("silence", "misread", "missed", "late", "measured")
_TOP = ("version", "name", "seeds", "cap", "stalled", "tracks", "conditions", "agents", "tuning")
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
class Suite:
    """The whole suite file, checked (see the module docstring)."""

    version: str
    name: str
    masters: Mapping[str, int]
    counts: Mapping[str, int]
    quick_count: int
    quick_conditions: tuple[str, ...]
    cap: float
    stall_after: int  # K: a run is stalled after K gestures in a row without an action
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
    focus: Focus | None
    noninferiority: NonInferiority | None
    path: Path
    sha256: str  # the suite file and every file its conditions read (:mod:`.fingerprint`)
    inputs: Mapping[str, str]  # each condition file (as the suite names it) -> its sha256

    def seeds(self, block: str, quick: bool = False) -> list[int]:
        """The run seeds of ``block`` (``dev`` or ``eval``); ``quick``: the first few."""
        from pil.experiments.study import rep_seeds

        if block not in BLOCKS:
            raise SuiteError(f"seed block {quote(block)}; valid choices: " + ", ".join(BLOCKS))
        seeds = rep_seeds(self.masters[block], self.counts[block])
        return seeds[: self.quick_count] if quick else seeds

    def stamp(self) -> dict[str, Any]:
        """What every results file carries: the suite's version, its hash (the file and its
        conditions' files) and each condition file's own hash."""
        return {
            "suite_version": self.version,
            "suite_sha256": self.sha256,
            "suite_inputs": dict(self.inputs),
        }

    def stale(self, stamp: Mapping[str, Any]) -> str:
        """Why results stamped ``stamp`` are stale for this suite ("" if they are not)."""
        return staleness(stamp, self.sha256, self.inputs)

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


def _condition(name: str, raw: Any, base: Path) -> Condition:
    where = f"conditions.{name}"
    if not isinstance(raw, Mapping):
        raise SuiteError(f"{where}: expected a mapping with gestures (and feedback)")
    reject_unknown(raw, ("gestures", "feedback"), where, SuiteError)
    gestures = dict(mapping(raw, "gestures", where))
    model = gestures.get("model")
    if model not in GESTURE_MODELS:
        raise SuiteError(
            f"{where}.gestures.model: {quote(model)}; valid choices: " + ", ".join(GESTURE_MODELS)
        )
    if model == "independent":
        try:  # the one rate check: (0, 1], at least MIN_RATE (pil.task.params.RATE)
            gestures["rate"] = RATE.parse(gestures.get("rate"), f"{where}.gestures.rate")
        except RobinPilError as error:
            raise SuiteError(str(error)) from None
    elif model == "measured":
        gestures["file"] = str((base / str(gestures.get("file"))).resolve())
    elif model == "markov":
        for key in ("good", "bad", "enter_bad", "leave_bad"):
            gestures[key] = number(gestures.get(key), f"{where}.gestures.{key}", 0.0, 1.0)
    feedback = dict(raw.get("feedback") or {})
    reject_unknown(feedback, FEEDBACK_KEYS, f"{where}.feedback", SuiteError)
    for key in ("silence", "misread", "missed", "late"):
        if key in feedback:
            feedback[key] = number(feedback[key], f"{where}.feedback.{key}", 0.0, 1.0)
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
    quick = {k: count(v, f"{where}.quick.{k}") for k, v in (raw.get("quick") or {}).items()}
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
        None if cap is None else number(cap, f"{where}.cap", 1.0, 1000.0),
    )


def load_suite(path: str | Path = SUITE_FILE) -> Suite:
    """Read and check the suite file at ``path`` (default: the shipped one)."""
    path = Path(path)
    raw = read_yaml_mapping(path, "suite file", SuiteError, ("pil/bench/suite.yaml",))
    reject_unknown(raw, _TOP_ALL, str(path), SuiteError)
    for key in _TOP:
        if key not in raw:
            raise SuiteError(f"{path}: missing {key!r}")
    base = path.resolve().parent
    seeds = mapping(raw, "seeds", "seeds")
    masters, counts = {}, {}
    for block in BLOCKS:
        spec = seeds.get(block)
        if not isinstance(spec, Mapping):
            raise SuiteError(f"seeds.{block}: expected {{master, count}}")
        masters[block] = count(spec.get("master"), f"seeds.{block}.master", 0)
        counts[block] = count(spec.get("count"), f"seeds.{block}.count", 2)
    conditions = {n: _condition(n, c, base) for n, c in mapping(raw, "conditions", "").items()}
    tracks = {n: _track(n, t, conditions) for n, t in mapping(raw, "tracks", "").items()}
    tuning = mapping(raw, "tuning", "")
    analysis = raw.get("analysis") or {}
    equivalence = analysis.get("equivalence") or {}
    agents = tuple(str(a) for a in raw.get("agents") or ())
    anchors = tuple(str(a) for a in analysis.get("anchors") or ())
    for name in (*anchors, equivalence.get("anchor", anchors[0] if anchors else "")):
        if name not in agents:
            raise SuiteError(f"analysis: anchor {quote(name)} is not one of the agents")

    def conditions_of(track: str) -> tuple[str, ...]:
        if track not in tracks:
            raise SuiteError(f"analysis: unknown track {quote(track)}; valid: " + ", ".join(tracks))
        return tracks[track].conditions

    focus, noninferiority = parse_declared(analysis, agents, conditions_of, SuiteError)
    sha256, inputs = fingerprint(
        read_small_text(path), base, condition_files(raw["conditions"]), SuiteError
    )
    suite = Suite(
        version=str(raw["version"]),
        name=str(raw["name"]),
        masters=masters,
        counts=counts,
        quick_count=count(seeds.get("quick", 3), "seeds.quick", 2),
        quick_conditions=tuple(str(c) for c in raw.get("quick_conditions") or conditions),
        cap=number(raw["cap"], "cap", 1.0, 1000.0),
        stall_after=count(raw["stalled"], "stalled"),
        tracks=tracks,
        conditions=conditions,
        agents=agents,
        tuning_track=str(tuning.get("track")),
        tuning_conditions=tuple(str(c) for c in tuning.get("conditions") or ()),
        extend=count(tuning.get("extend", 4), "tuning.extend", 0),
        grids={
            str(a): parse_axes(str(a), g) for a, g in mapping(tuning, "grids", "tuning").items()
        },
        primary=str((raw.get("metrics") or {}).get("primary", "actions")),
        anchors=anchors,
        alpha=number(analysis.get("alpha", 0.05), "analysis.alpha", 0.0, 1.0),
        margin=number(equivalence.get("margin", 5.0), "analysis.equivalence.margin", 0.0, 1e6),
        equivalence_anchor=str(equivalence.get("anchor", anchors[0] if anchors else "")),
        focus=focus,
        noninferiority=noninferiority,
        path=path,
        sha256=sha256,
        inputs=inputs,
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
