"""What defines a live session (:class:`LiveConfig`) and its checks, before anything is built.

Every value is checked by :meth:`LiveConfig.checked`: one :class:`~pil.errors.RobinPilError`
naming the value and the valid choices. The scenario (a shipped name or a YAML path) and the
block's handover types are loaded and checked there too, so a bad protocol block fails before
its session starts.
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import Any

from pil.errors import InvalidChoiceError, RobinPilError
from pil.experiments.systems import check_system
from pil.step_memory import STEP_MEMORY
from pil.task.params import SEED
from pil.task.scenario import Scenario
from pil.task.spec import PHYSICAL, RunSpec, build_run_spec
from robin_sim.episode.config import DEFAULT_TABLES  # one table of the assembly, as the episode
from robin_sim.live.limits import BlockLimits, WatchdogLimits
from robin_sim.live.quality import LEVELS
from robin_sim.render.frame_spec import FPS, SIDE, check_size, narrowed

NAME_PATTERN = re.compile(r"[A-Za-z0-9_-]{1,32}")
# the episode's frame checks, narrowed for a stream: at most 1920 px a side (the scene's
# off-screen buffer is checked when the scene is built) and 60 frames per second
LIVE_SIDE = narrowed(SIDE, 1920)
LIVE_FPS = narrowed(FPS, 60)
SPEEDS = (0.1, 10.0)  # sim seconds per wall second
FEEDBACK_WINDOWS = (0.5, 60.0)  # s of sim time
LIVE_DETECTORS = ("exact", "vision")  # what reads the participant's gestures
EXACT_RATE = 1.0  # the detector reads every click and button as what it is


@dataclass(frozen=True)
class LiveConfig:
    """Everything that defines one live session (the live page's contract)."""

    participant: str = "P01"
    system: str = "pil"  # a key of pil.experiments.systems
    scenario: str | Path | None = None  # a shipped scenario name or a YAML path
    handover_types: tuple[str, ...] | None = None  # the block's types (None: the scenario's)
    out_root: Path = Path("out/live")
    session: str | None = None  # folder under out_root/participant (None: from the UTC time)
    width: int = 640
    height: int = 480
    fps: float = 15.0
    eye_inset: bool = True
    video: bool = True
    speed: float = 1.0  # sim seconds per wall second
    feedback_window: float = 4.0  # s of sim time to wait for a thumb after an action
    seed: int = 0  # the session's own seed (from the CLI: pil.task.seeds.block_seed)
    study_seed: int | None = None  # the study seed it was derived from (None: given as is)
    block: int | None = None
    protocol: str | None = None
    instructions: str = ""
    render_workers: int = 0  # scene render processes; 0: in the physics thread (see README)
    eye_worker: bool = False  # the eye inset rendered in a process of its own, meanwhile
    reflections: bool = False  # the floor's reflection (an extra render pass)
    # a busy machine lowers the stream (robin_sim.live.quality) before physics falls behind;
    # stream_level is where it starts (0: all frames with the eye inset), or stays unadaptive
    adaptive_stream: bool = True
    stream_level: int = 0
    webcam: bool = False  # the participant's hand read from the page's camera (docs/webcam.md)
    calibrate: bool = True  # with the webcam: ask for each gesture once at the start
    # "vision": Robin reads the participant's gestures with its eye cameras from the person's
    # hand the webcam's landmarks drive (robin_sim.live.eye_watch); "exact": as given
    detector: str = "exact"
    # The within-step memory (pil.step_memory): on, an action the participant refused in a
    # step is not tried again in it until all five were (a person should not refuse twice).
    step_memory: str = "on"
    # The step's watchdog (robin_sim.live.watchdog): robot attempts and sim seconds per gesture.
    max_attempts: int = WatchdogLimits.attempts
    max_step_seconds: float = WatchdogLimits.seconds
    # A study's block (robin_sim.lab): a practice block (its data marked so, never analysed)
    # and the block's caps (robin_sim.live.limits.BlockLimits; None: none).
    practice: bool = False
    block_seconds: float | None = None
    block_actions: int | None = None
    inactivity_seconds: float | None = None
    # set by checked(): the learner side (its scenario loaded once) and what it was built from
    resolved: tuple[Any, RunSpec] | None = field(default=None, compare=False, repr=False)

    def checked(self) -> LiveConfig:
        """This config with every value checked (nothing is built or written)."""
        _name(self.participant, "participant")
        if self.session is not None:
            _name(self.session, "session")
        check_system(self.system)
        width, height = check_size(self.width, self.height, "frame", LIVE_SIDE)
        fps = LIVE_FPS.parse(self.fps, "fps")
        if not isinstance(self.out_root, str | Path) or not str(self.out_root).strip():
            raise RobinPilError(f"out_root must be a folder path, got {self.out_root!r:.60}")
        if self.block is not None:
            _whole(self.block, "block", 0, 10_000)
        for name in ("protocol", "instructions"):
            value = getattr(self, name)
            if value is not None and not isinstance(value, str):
                raise RobinPilError(f"{name} must be text, got {type(value).__name__}")
        for name in (
            "eye_inset",
            "video",
            "eye_worker",
            "reflections",
            "webcam",
            "calibrate",
            "adaptive_stream",
            "practice",
        ):
            if not isinstance(getattr(self, name), bool):
                raise RobinPilError(f"{name} must be true or false, got {getattr(self, name)!r}")
        if self.detector not in LIVE_DETECTORS:
            raise InvalidChoiceError("detector", self.detector, LIVE_DETECTORS)
        if self.detector == "vision" and not self.webcam:
            raise RobinPilError(
                "--detector vision reads the participant's gestures with Robin's eye cameras "
                "from the simulated hand that the webcam drives: add --webcam, or drop "
                "--detector vision (clicks and keys are read exactly)"
            )
        seed = SEED.parse(self.seed, "seed")
        if self.study_seed is not None:
            SEED.parse(self.study_seed, "study_seed")
        if self.step_memory not in STEP_MEMORY:
            raise InvalidChoiceError("step_memory", self.step_memory, STEP_MEMORY)
        limits = WatchdogLimits(self.max_attempts, self.max_step_seconds).checked()
        caps = self.limits.checked("LiveConfig")
        spec = self._spec(seed)
        scenario = spec.scenario
        types = self.handover_types
        if types is not None:
            if isinstance(types, str) or not types:
                valid = ", ".join(t.name for t in scenario.types)
                raise RobinPilError(
                    f"handover_types must be a non-empty list of type names; valid: {valid}"
                )
            for name in types:
                scenario.type_named(str(name))  # names the valid types
        return replace(
            self,
            width=width,
            height=height,
            fps=float(fps),
            speed=_number(self.speed, "speed", *SPEEDS),
            feedback_window=_number(self.feedback_window, "feedback_window", *FEEDBACK_WINDOWS),
            seed=seed,
            out_root=Path(self.out_root),
            handover_types=None if types is None else tuple(str(t) for t in types),
            render_workers=_whole(self.render_workers, "render_workers", 0, 8),
            stream_level=_whole(self.stream_level, "stream_level", 0, len(LEVELS) - 1),
            max_attempts=limits.attempts,
            max_step_seconds=limits.seconds,
            block_seconds=caps.seconds,
            block_actions=caps.actions,
            inactivity_seconds=caps.inactivity,
            resolved=(self._source(seed), spec),
        )

    def _source(self, seed: int) -> tuple[Any, ...]:
        """What the learner side is built from (a config changed since: built again)."""
        types = self.handover_types
        types = None if types is None else tuple(types)
        return (self.system, seed, self.scenario, types, self.step_memory)

    def _spec(self, seed: int) -> RunSpec:
        """The learner side: the one built by :meth:`checked` if it still fits, else built
        (the scenario file loaded here, once per config)."""
        if self.resolved is not None and self.resolved[0] == self._source(seed):
            return self.resolved[1]
        values: dict[str, Any] = {"step_memory": self.step_memory}
        if self.scenario is None:
            values["tables"] = DEFAULT_TABLES
        spec = build_run_spec(  # the parameters' defaults but these: nothing parsed
            system=self.system,
            rate=EXACT_RATE,
            seed=seed,
            scenario=self.scenario,
            values=values,
            world=PHYSICAL,
        )
        types = self.handover_types
        if types and not isinstance(types, str):
            sequence = tuple(str(t) for t in types)
            spec = replace(spec, scenario=replace(spec.scenario, sequence=sequence))
        return spec

    def run_spec(self) -> RunSpec:
        """The session's learner side (of a :meth:`checked` config: built there, its scenario
        loaded once): its system and seed, the block's scenario, the exact detector at rate 1,
        the parameters' defaults, in the physical world."""
        return self._spec(self.seed)

    @property
    def watchdog(self) -> WatchdogLimits:
        """The step watchdog's limits (of a :meth:`checked` config)."""
        return WatchdogLimits(self.max_attempts, self.max_step_seconds)

    @property
    def limits(self) -> BlockLimits:
        """The block's caps on time and actions, and the inactivity timeout."""
        return BlockLimits(self.block_seconds, self.block_actions, self.inactivity_seconds)

    def scenario_of(self) -> Scenario:
        """The session's scenario: the block's handover types drawn in the scenario's way."""
        return self.run_spec().scenario


def _name(value: object, what: str) -> str:
    if not isinstance(value, str) or not NAME_PATTERN.fullmatch(value):
        raise RobinPilError(
            f"{what} {value!r:.60} is not a valid name; use 1-32 letters, digits, '_' or '-'"
        )
    return value


def _whole(value: object, what: str, low: int, high: int) -> int:
    if isinstance(value, bool) or not isinstance(value, int) or not low <= value <= high:
        raise RobinPilError(
            f"{what} must be a whole number from {low} to {high}, got {value!r:.40}"
        )
    return value


def _number(value: object, what: str, low: float, high: float) -> float:
    if isinstance(value, bool) or not isinstance(value, int | float) or not math.isfinite(value):
        raise RobinPilError(f"{what} must be a number from {low} to {high}, got {value!r:.40}")
    if not low <= value <= high:
        raise RobinPilError(f"{what} must lie in [{low}, {high}], got {value}")
    return float(value)
