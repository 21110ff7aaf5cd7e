"""Robin in MuJoCo: the model, mink controllers for the five actions, episodes and rendering.

Importing this package does not import MuJoCo; the names below import their module (and
MuJoCo) when first used, so a command can choose the GL backend first::

    from robin_sim import EpisodeConfig, RunSpec, assemble, run_episode

    summary = run_episode(EpisodeConfig(scenario="one_handover", video=False))
"""

from __future__ import annotations

import importlib
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    from pil.task.assemble import Run
    from pil.task.spec import RunSpec, parse_run_spec
    from robin_sim.episode.assemble import assemble
    from robin_sim.episode.config import EpisodeConfig, EpisodeSpec, parse_episode
    from robin_sim.episode.run import run_episode
    from robin_sim.robot.world import PhysicalWorld

# name -> the module that defines it (the public API; each imported on first use)
_HOMES: dict[str, str] = {
    "EpisodeConfig": "robin_sim.episode.config",
    "EpisodeSpec": "robin_sim.episode.config",
    "PhysicalWorld": "robin_sim.robot.world",
    "Run": "pil.task.assemble",
    "RunSpec": "pil.task.spec",
    "assemble": "robin_sim.episode.assemble",
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
    "assemble",
    "parse_episode",
    "parse_run_spec",
    "run_episode",
]


def __getattr__(name: str) -> Any:
    """A public name, imported from its module on first use (PEP 562)."""
    if name not in _HOMES:
        raise AttributeError(f"module 'robin_sim' has no attribute {name!r}")
    value = getattr(importlib.import_module(_HOMES[name]), name)
    globals()[name] = value
    return value


def __dir__() -> list[str]:
    return sorted({*globals(), *__all__})
