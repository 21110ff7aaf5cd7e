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
from pil.step_memory import STEP_MEMORY
from pil.task.detector import CAMERAS, EXACT
from pil.task.params import SEED
from pil.task.scenario import Scenario, load_scenario
from pil.task.seeds import block_seed
from pil.task.spec import PHYSICAL, RunSpec, build_run_spec
from pil.task.systems import check_system
from robin_sim.episode.config import DEFAULT_TABLES  # one table of the assembly, as the episode
from robin_sim.live.limits import BlockLimits, WatchdogLimits, from_text
from robin_sim.live.quality import LEVELS
from robin_sim.render.frame_spec import FPS, SIDE, check_size, narrowed
from robin_sim.render.worker_count import MAX_RENDER_WORKERS

NAME_PATTERN = re.compile(r"[A-Za-z0-9_-]{1,32}")
# the episode's frame checks, narrowed for a stream: at most 1920 px a side and 60 frames per
# second (and, as every frame, within the scene's off-screen buffer: check_size)
LIVE_SIDE = narrowed(SIDE, 1920)
LIVE_FPS = narrowed(FPS, 60)
SPEEDS = (0.1, 10.0)  # sim seconds per wall second
FEEDBACK_WINDOWS = (0.5, 60.0)  # s of sim time
LIVE_DETECTORS = (EXACT, CAMERAS)  # what reads the participant's gestures
EXACT_RATE = 1.0  # the detector reads every click and button as what it is
ScenarioFile = tuple[Any, Scenario]  # a scenario file as read: the name it was read by, and it
# what each block of a protocol or a study sets itself (LiveConfig.for_block); the rest is shared
BLOCK_FIELDS = frozenset(
    {"system", "scenario", "handover_types", "block", "protocol", "instructions", "session"}
    | {"seed", "practice", "block_seconds", "block_actions"}
)
BOOLEANS = (
    "eye_inset",
    "video",
    "eye_worker",
    "reflections",
    "webcam",
    "calibrate",
    "adaptive_stream",
)


@dataclass(frozen=True)
class LiveConfig:
    """Everything that defines one live session (the live page's contract)."""

    participant: str = "P01"
    system: str = "pil"  # a key of pil.task.systems
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
    # the session's own seed; None: derived from the study seed, the participant and the block
    # (pil.task.seeds.block_seed), or 0 without a study seed
    seed: int | None = None
    study_seed: int | None = None  # the study's seed (None: the session's seed is given as is)
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
    # CAMERAS: Robin reads the participant's gestures with its eye cameras from the person's
    # hand the webcam's landmarks drive (robin_sim.live.eye_watch); EXACT: as given
    detector: str = EXACT
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
    # set by checked(): what the learner side was built from, the learner side, and the
    # scenario file as read (its name, the scenario): each file is read once
    resolved: tuple[Any, RunSpec, ScenarioFile] | None = field(
        default=None, compare=False, repr=False
    )
    # True on what checked() returns (not copied by dataclasses.replace: a changed copy is
    # checked again), so that the layers below the edge take a checked config as it is
    is_checked: bool = field(default=False, init=False, compare=False, repr=False)

    def checked(self) -> LiveConfig:
        """This config with every value checked (nothing is built or written); a config
        :meth:`checked` returned is returned as it is, checked once."""
        if self.is_checked:
            return self
        return self._options_checked()._block_checked()

    def for_block(self, **changes: Any) -> LiveConfig:
        """A checked config's copy for one block of a protocol or study: only ``changes``
        (fields of :data:`BLOCK_FIELDS`) and what depends on them are checked, the options
        this config shares with its other blocks were checked once, here. With a study seed
        the block's seed is derived from it (participant and block) unless ``seed`` is given."""
        if not self.is_checked:
            raise RobinPilError("for_block is for a checked LiveConfig; call checked() first")
        unknown = sorted(set(changes) - BLOCK_FIELDS)
        if unknown:
            raise RobinPilError(
                f"for_block changes a block's fields only, not {unknown}; "
                f"valid: {', '.join(sorted(BLOCK_FIELDS))}"
            )
        if self.study_seed is not None:
            changes.setdefault("seed", None)  # derived for this block unless given
        return replace(self, **changes)._block_checked()

    def _options_checked(self) -> LiveConfig:
        """The options a study's blocks share, checked (the block's own: :meth:`_block_checked`)."""
        _name(self.participant, "participant")
        width, height = check_size(self.width, self.height, "frame", LIVE_SIDE)
        fps = LIVE_FPS.parse(self.fps, "fps")
        if not isinstance(self.out_root, str | Path) or not str(self.out_root).strip():
            raise RobinPilError(f"out_root must be a folder path, got {self.out_root!r:.60}")
        for name in BOOLEANS:
            if not isinstance(getattr(self, name), bool):
                raise RobinPilError(f"{name} must be true or false, got {getattr(self, name)!r}")
        study = self.study_seed
        study_seed = None if study is None else SEED.parse(study, "study_seed (--seed)")
        if self.step_memory not in STEP_MEMORY:
            raise InvalidChoiceError("step_memory", self.step_memory, STEP_MEMORY)
        if self.detector not in LIVE_DETECTORS:
            raise InvalidChoiceError("detector", self.detector, LIVE_DETECTORS)
        if self.detector == CAMERAS and not self.webcam:
            raise RobinPilError(
                "--detector vision reads the participant's gestures with Robin's eye cameras "
                "from the simulated hand that the webcam drives: add --webcam, or drop "
                "--detector vision (clicks and keys are read exactly)"
            )
        limits = WatchdogLimits(self.max_attempts, self.max_step_seconds).checked()
        return replace(
            self,
            width=width,
            height=height,
            fps=float(fps),
            speed=_number(self.speed, "speed", *SPEEDS),
            feedback_window=_number(self.feedback_window, "feedback_window", *FEEDBACK_WINDOWS),
            study_seed=study_seed,
            out_root=Path(self.out_root),
            render_workers=_whole(self.render_workers, "render_workers", 0, MAX_RENDER_WORKERS),
            stream_level=_whole(self.stream_level, "stream_level", 0, len(LEVELS) - 1),
            max_attempts=limits.attempts,
            max_step_seconds=limits.seconds,
        )

    def _block_checked(self) -> LiveConfig:
        """The block's own values checked (its seed derived from the study seed when not
        given), the learner side built; marked checked."""
        if self.session is not None:
            _name(self.session, "session")
        check_system(self.system)
        if self.block is not None:
            _whole(self.block, "block", 0, 10_000)
        for name in ("protocol", "instructions"):
            value = getattr(self, name)
            if value is not None and not isinstance(value, str):
                raise RobinPilError(f"{name} must be text, got {type(value).__name__}")
        if not isinstance(self.practice, bool):
            raise RobinPilError(f"practice must be true or false, got {self.practice!r}")
        if self.seed is not None:
            seed = SEED.parse(self.seed, "seed")
        elif self.study_seed is None:
            seed = 0
        else:  # derived, not given: pil.task.seeds is the one place seeds are drawn from
            seed = block_seed(self.study_seed, self.participant, self.block or 0)
        caps = self.limits.checked("LiveConfig")
        file = self._scenario_file()
        spec = self._spec(seed, file)
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
        done = replace(
            self,
            seed=seed,
            handover_types=None if types is None else tuple(str(t) for t in types),
            block_seconds=caps.seconds,
            block_actions=caps.actions,
            inactivity_seconds=caps.inactivity,
            resolved=(self._source(seed), spec, file),
        )
        object.__setattr__(done, "is_checked", True)
        return done

    def _source(self, seed: int) -> tuple[Any, ...]:
        """What the learner side is built from (a config changed since: built again)."""
        types = self.handover_types
        types = None if types is None else tuple(types)
        return (self.system, seed, self.scenario, types, self.step_memory)

    def _scenario_file(self) -> ScenarioFile:
        """The scenario file as read, with the name it was read by: the one :meth:`checked`
        read if the name is unchanged (a protocol's blocks read their file once), else read."""
        if self.resolved is not None and self.resolved[2][0] == self.scenario:
            return self.resolved[2]
        name = self.scenario
        return (name, load_scenario() if name is None else load_scenario(name))

    def _spec(self, seed: int, file: ScenarioFile | None = None) -> RunSpec:
        """The learner side: the one built by :meth:`checked` if it still fits, else built
        from the scenario ``file`` (default: :meth:`_scenario_file`)."""
        if self.resolved is not None and self.resolved[0] == self._source(seed):
            return self.resolved[1]
        values: dict[str, Any] = {"step_memory": self.step_memory}
        if self.scenario is None:
            values["tables"] = DEFAULT_TABLES
        spec = build_run_spec(  # the parameters' defaults but these: nothing parsed
            system=self.system,
            rate=EXACT_RATE,
            seed=seed,
            scenario=(file or self._scenario_file())[1],  # the values above change a copy
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
        assert self.seed is not None, "run_spec is for a checked LiveConfig"
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
    value = from_text(value, float)  # the command line's text: checked here, once
    if isinstance(value, bool) or not isinstance(value, int | float) or not math.isfinite(value):
        raise RobinPilError(f"{what} must be a number from {low} to {high}, got {value!r:.40}")
    if not low <= value <= high:
        raise RobinPilError(f"{what} must lie in [{low}, {high}], got {value}")
    return float(value)
