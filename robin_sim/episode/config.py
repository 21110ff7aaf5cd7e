"""What defines an episode: :class:`EpisodeConfig` as given, parsed once into
:class:`EpisodeSpec` (:func:`parse_episode`, the edge).

Every option is checked there, by the specs of :mod:`pil.task.params`, the camera conditions'
(:mod:`robin_sim.vision.condition_params`) and the few video ones below, before an episode
builds anything or writes a file; below, nothing checks a value again. The run's learner side
is a :class:`~pil.task.spec.RunSpec` of the physical world; the scene layout is resolved when
the world is built (:func:`robin_sim.episode.physical_assembly.layout_of`, which refuses a layout
without the legs and spots the person will point at). Nothing here imports MuJoCo.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from pil.errors import RobinPilError
from pil.task.detector import CAMERAS as VISION
from pil.task.params import ParamSpec
from pil.task.scenario import Scenario
from pil.task.spec import DETECTOR_SPECS, PHYSICAL, RunSpec, parse_run_spec
from robin_sim.model.names import HEAD_CAMERAS, SCENE_CAMERAS
from robin_sim.render.frame_spec import FPS, check_size
from robin_sim.render.worker_count import RENDER_WORKERS
from robin_sim.vision.condition_params import CONDITION_PARAMS, VisionSettings, parse_conditions

VIDEO_CAMERAS: tuple[str, ...] = (*SCENE_CAMERAS, *HEAD_CAMERAS)
CAMERA = ParamSpec("camera", "choice", "front", "the camera filmed", choices=VIDEO_CAMERAS)


class EpisodeError(RobinPilError):
    """The episode cannot go on (e.g. the learner's hand state disagrees with physics)."""


def parse_size(text: str, label: str = "--size") -> tuple[int, int]:
    """``"640x480"`` as (640, 480), checked by :func:`~robin_sim.render.frame_spec.check_size`
    (even whole numbers >= 2 for H.264 yuv420p, within the scene's off-screen buffer)."""
    parts = text.lower().split("x") if isinstance(text, str) and len(text) <= 40 else []
    if len(parts) != 2:
        raise RobinPilError(f"{label} must look like 640x480 (WIDTHxHEIGHT), got {text!r:.80}")
    return check_size(parts[0], parts[1], label, size_label=label)


@dataclass(frozen=True)
class EpisodeConfig:
    """Everything that defines an episode; the defaults are ``robin-pil episode``'s."""

    tables: int | None = None  # None: the scenario file's, but 1 for the default assembly
    rate: float = 1.0
    seed: int = 0
    system: str = "pil"
    scenario: str | Path | None = None  # an assembly YAML; default scenarios/assembly.yaml
    out: Path = Path("out")
    video: bool = True
    camera: str = "front"
    width: int = 640
    height: int = 480
    size: str | None = None  # "WIDTHxHEIGHT" as given (the CLI's --size); replaces width, height
    fps: int = 30
    shadows: bool = False  # shadows cost about 3x the render time on a CPU (llvmpipe)
    render_workers: int | None = None  # render processes; None: 2 (0 on one CPU), 0: in-process
    policy_panel: bool = True
    eye_inset: bool = True  # the robot's left-eye view as a small inset in the video
    verify: bool = True  # off-screen render checks after grasps, handovers and placements
    progress: bool = True
    params: Mapping[str, Any] = field(default_factory=dict)  # any of pil.task.params.PARAMS

    def spec(self) -> EpisodeSpec:
        """This config parsed (:func:`parse_episode`)."""
        return parse_episode(self)


DEFAULT_TABLES = 1  # the main job assembles one table of the paper's assembly
# s of simulated time per leg of the scenario after which an episode stops, status
# TIME_LIMIT: about twice the longest measured (10 vision episodes in a dim, noisy room: at most
# 147 s per leg), so that no run that still makes progress is cut, and a run that cannot (the
# robot's thumbs misread in a loop of re-plans that no per-gesture count catches) still ends
SIM_SECONDS_PER_LEG = 300.0
FINISHED, TIME_LIMIT = "finished", "time_limit"  # how an episode that ran to its end ended


def sim_time_limit(scenario: Scenario) -> float:
    """The simulated seconds after which an episode of ``scenario`` stops (status
    :data:`TIME_LIMIT`): :data:`SIM_SECONDS_PER_LEG` per leg of its tables."""
    return SIM_SECONDS_PER_LEG * scenario.tables * scenario.legs_per_table


_LABELS = {"rate": "--rate", "seed": "--seed", "scenario": "--scenario", "tables": "--tables"}


@dataclass(frozen=True, slots=True)
class VideoSpec:
    """The episode's video, checked (``record`` False: physics and log only)."""

    record: bool
    camera: str
    width: int
    height: int
    fps: int
    shadows: bool
    render_workers: int | None
    policy_panel: bool
    eye_inset: bool


@dataclass(frozen=True, slots=True)
class EpisodeSpec:
    """A physical episode, typed and checked: the learner side (:class:`RunSpec`, world
    ``physical``), the eye cameras' conditions (a ``vision`` run only), the video, where
    the files go and the simulated time after which it stops."""

    run: RunSpec
    conditions: VisionSettings | None
    video: VideoSpec
    verify: bool
    progress: bool
    out: Path
    time_limit_s: float  # simulated s after which it stops (:func:`sim_time_limit`)


_DEFAULT = EpisodeConfig()
# no video: a physical sweep run's (its other fields: the defaults, typed constants)
NO_VIDEO = VideoSpec(
    record=False,
    camera=_DEFAULT.camera,
    width=_DEFAULT.width,
    height=_DEFAULT.height,
    fps=_DEFAULT.fps,
    shadows=_DEFAULT.shadows,
    render_workers=_DEFAULT.render_workers,
    policy_panel=_DEFAULT.policy_panel,
    eye_inset=_DEFAULT.eye_inset,
)


def parse_episode(config: EpisodeConfig) -> EpisodeSpec:
    """``config`` with every option parsed and checked once (nothing is built or written).

    ``tables`` None: the scenario file's, but :data:`DEFAULT_TABLES` for the default assembly;
    the camera conditions (``lighting``, ``camera_noise``) need ``detector=vision``.
    """
    params = dict(config.params)
    given = {name: params.pop(name) for name in CONDITION_PARAMS if name in params}
    if config.tables is not None or (config.scenario is None and "tables" not in params):
        params["tables"] = DEFAULT_TABLES if config.tables is None else config.tables
    run = parse_run_spec(
        system=config.system,
        rate=config.rate,
        seed=config.seed,
        scenario=config.scenario,
        params=params,
        world=PHYSICAL,
        labels=_LABELS,
    )
    if run.detector.model != VISION and given:
        raise EpisodeError(
            f"{', '.join(given)} are the eye cameras' parameters and need "
            f"--detector {VISION}; the detector must be {DETECTOR_SPECS[PHYSICAL].valid()}"
        )
    if config.size is not None:
        width, height = parse_size(config.size)
    else:
        width, height = check_size(config.width, config.height)
    video = VideoSpec(
        record=bool(config.video),
        camera=CAMERA.parse(config.camera, "--camera"),
        width=width,
        height=height,
        fps=FPS.parse(config.fps, "--fps"),
        shadows=bool(config.shadows),
        render_workers=RENDER_WORKERS.parse(config.render_workers, "--render-workers"),
        policy_panel=bool(config.policy_panel),
        eye_inset=bool(config.eye_inset),
    )
    conditions = parse_conditions(given) if run.detector.model == VISION else None
    return EpisodeSpec(
        run,
        conditions,
        video,
        bool(config.verify),
        bool(config.progress),
        Path(config.out),
        sim_time_limit(run.scenario),
    )
