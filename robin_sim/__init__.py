"""Robin in MuJoCo: the model, mink controllers for the five actions, episodes and rendering.

Importing this package does not import MuJoCo; the names below import their module (and
MuJoCo) when first used, so a command can choose the GL backend first::

    from robin_sim import EpisodeConfig, RunSpec, assemble_physical, run_episode

    summary = run_episode(EpisodeConfig(scenario="one_handover", video=False))
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from pil.lazy_names import lazy_names

if TYPE_CHECKING:
    from pil.task.assemble import Run
    from pil.task.spec import RunSpec, parse_run_spec
    from robin_sim.episode.config import EpisodeConfig, EpisodeSpec, parse_episode
    from robin_sim.episode.physical_assembly import assemble_physical
    from robin_sim.episode.run import run_episode
    from robin_sim.robot.world import PhysicalWorld

# name -> the module that defines it (the public API; each imported on first use)
_HOMES: dict[str, str] = {
    "EpisodeConfig": "robin_sim.episode.config",
    "EpisodeSpec": "robin_sim.episode.config",
    "PhysicalWorld": "robin_sim.robot.world",
    "Run": "pil.task.assemble",
    "RunSpec": "pil.task.spec",
    "assemble_physical": "robin_sim.episode.physical_assembly",
    "parse_episode": "robin_sim.episode.config",
    "parse_run_spec": "pil.task.spec",
    "run_episode": "robin_sim.episode.run",
}
__all__ = [
    "EpisodeConfig",
    "EpisodeSpec",
    "PhysicalWorld",
    "Run",
    "RunSpec",
    "assemble_physical",
    "parse_episode",
    "parse_run_spec",
    "run_episode",
]


__getattr__, __dir__ = lazy_names("robin_sim", _HOMES, globals(), __all__)
