"""One real episode with small frames, for tests that re-apply its recorded states."""

from __future__ import annotations

from pathlib import Path
from typing import Any

from robin_sim.render.gl_backend import ensure_gl_backend

ensure_gl_backend()  # before mujoco is imported (see robin_sim.render.gl_backend)

from pil.task.scenario import SCENARIOS_DIR  # noqa: E402
from robin_sim.episode.run import EpisodeConfig, run_episode  # noqa: E402
from robin_sim.render.state_log import STATES_NAME, RecordedStates, load_states  # noqa: E402


def record_episode(
    out: Path, scenario: str, seed: int, size: tuple[int, int], fps: int, **more: Any
) -> tuple[RecordedStates, dict[str, Any]]:
    """Run ``scenario`` at ``seed`` into ``out`` (no checks, no inset or policy panel) and
    return its recorded states and summary."""
    config = EpisodeConfig(
        scenario=SCENARIOS_DIR / f"{scenario}.yaml",
        seed=seed,
        out=out,
        width=size[0],
        height=size[1],
        fps=fps,
        verify=False,
        progress=False,
        eye_inset=False,
        policy_panel=False,
        **more,
    )
    summary = run_episode(config)
    return load_states(out / STATES_NAME), summary
