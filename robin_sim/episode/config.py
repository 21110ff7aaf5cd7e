"""What defines an episode (:class:`EpisodeConfig`), its checks, and what it resolves to.

Every option is checked here, by the specs of :mod:`pil.task.params` and the few video ones
below, before an episode builds anything or writes a file; :class:`EpisodeTask` resolves the
scenario and the scene layout (and refuses a layout without the legs and spots the person
will point at).
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import TYPE_CHECKING, Any

from pil.errors import RobinPilError
from pil.experiments.systems import check_system
from pil.task.params import ASSEMBLY, RATE, SCENARIO, SEED, ParamSpec
from pil.task.parts import check_params, resolve_scenario
from pil.task.scenario import Scenario
from robin_sim.episode.reading import split_params
from robin_sim.model.names import HEAD_CAMERAS, SCENE_CAMERAS
from robin_sim.render.frame_spec import FPS, SIDE, check_even, check_size

if TYPE_CHECKING:  # the module is imported before the GL backend is chosen: no MuJoCo here
    from robin_sim.model.scene import SceneLayout

VIDEO_CAMERAS: tuple[str, ...] = (*SCENE_CAMERAS, *HEAD_CAMERAS)
CAMERA = ParamSpec("camera", "choice", "front", "the camera filmed", choices=VIDEO_CAMERAS)
RENDER_WORKERS = ParamSpec(
    "render_workers",
    "int",
    None,
    "render processes (0: in this process)",
    0,
    64,
    optional=True,
    empty="2, or 0 on one CPU",
)


class EpisodeError(RobinPilError):
    """The episode cannot go on (e.g. the learner's hand state disagrees with physics)."""


def parse_size(text: str, label: str = "--size") -> tuple[int, int]:
    """``"640x480"`` as (640, 480): two even whole numbers >= 2 (H.264 yuv420p)."""
    parts = text.lower().split("x") if isinstance(text, str) and len(text) <= 40 else []
    if len(parts) != 2:
        raise RobinPilError(f"{label} must look like 640x480 (WIDTHxHEIGHT), got {text!r:.80}")
    width, height = (
        SIDE.parse(part, f"{label} {name}")
        for part, name in zip(parts, ("width", "height"), strict=True)
    )
    return check_even(width, height, label)


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
    fps: int = 30
    shadows: bool = False  # shadows cost about 3x the render time on a CPU (llvmpipe)
    render_workers: int | None = None  # render processes; None: 2 (0 on one CPU), 0: in-process
    policy_panel: bool = True
    eye_inset: bool = True  # the robot's left-eye view as a small inset in the video
    verify: bool = True  # off-screen render checks after grasps, handovers and placements
    progress: bool = True
    params: Mapping[str, Any] = field(default_factory=dict)  # any of pil.task.parts.PARAMS

    def checked(self) -> EpisodeConfig:
        """This config with every option parsed and checked (nothing is built or written)."""
        check_system(self.system)
        scenario = self.scenario
        if scenario is not None and not isinstance(scenario, (Path, Scenario)):
            scenario = SCENARIO.parse(scenario, "--scenario")
        width, height = check_size(self.width, self.height)
        check_params(split_params(self.params)[0])
        return replace(
            self,
            tables=ASSEMBLY["tables"].parse(self.tables, "--tables"),
            rate=RATE.parse(self.rate, "--rate"),
            seed=SEED.parse(self.seed, "--seed"),
            scenario=scenario,
            camera=CAMERA.parse(self.camera, "--camera"),
            width=width,
            height=height,
            fps=FPS.parse(self.fps, "--fps"),
            render_workers=RENDER_WORKERS.parse(self.render_workers, "--render-workers"),
        )


@dataclass(frozen=True)
class EpisodeTask:
    """What an episode's config resolves to: the scenario, its parameters and the scene layout."""

    scenario: Scenario
    values: Mapping[str, Any]
    layout: SceneLayout
    vision: Mapping[str, Any] | None = None  # camera conditions when the robot reads by eye

    @property
    def legs_total(self) -> int:
        """Legs the person is to receive."""
        return self.scenario.tables * self.scenario.legs_per_table

    @classmethod
    def of(cls, config: EpisodeConfig) -> EpisodeTask:
        """Resolve ``config``: its scenario (tables default to 1 for the paper's assembly) and
        the scene layout (the scenario's ``layout`` section, else the default), checking that
        the layout has the legs and spots the person will point at."""
        from robin_sim.model.scene import SceneLayout  # imports MuJoCo

        tables = config.tables
        if tables is None and config.scenario is None:
            tables = 1  # the main job assembles one table of the paper's assembly
        params, vision = split_params(config.params)
        values = check_params({**params, "tables": tables})
        scenario = resolve_scenario(config.scenario, values)
        layout = SceneLayout.from_mapping(scenario.layout) if scenario.layout else SceneLayout()
        if scenario.spots > len(layout.spots) or scenario.legs_per_table > len(layout.legs):
            raise EpisodeError(
                f"scenario {scenario.name!r} needs {scenario.spots} table spots and "
                f"{scenario.legs_per_table} legs per table, but its layout has "
                f"{len(layout.spots)} spots and {len(layout.legs)} legs; add them to its "
                "layout section or lower spots / legs_per_table"
            )
        return cls(scenario, values, layout, vision)
