"""Every physical episode ends (issue 41): a leg knocked out of Robin's reach is put back
before the person points at it, and an episode stops at its simulated-time limit.

The hang this guards against (``vision_dim_episodes``, rep 8, seed 3573445666: lighting 0.15,
camera noise 40): closing on leg 2 pushed leg 3 off the table onto the floor, at
(0.4244, 0.998, 0.02). The scripted person went on pointing at leg 3 there; every reach
towards it failed and was stopped, and each thumb down misread as a thumb up started the
instruction's count of actions afresh, so no limit was ever reached (1500 simulated s, 300
steps and more). These run Robin in MuJoCo for real; they are marked slow as physics tests are.
"""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path

import mujoco
import pytest

from pil.task.person import ScriptedPerson
from pil.task.scenario import SCENARIOS_DIR
from pil.task.world import Intent, Target
from pil.types import Action, Gesture
from robin_sim.cli.episode_text import summary_text
from robin_sim.episode.config import SIM_SECONDS_PER_LEG, TIME_LIMIT, EpisodeConfig
from robin_sim.episode.log import read_step_log
from robin_sim.episode.physical_run import physical_row
from robin_sim.episode.run import run_episode
from robin_sim.model import names
from robin_sim.person.body import PhysicalBody
from robin_sim.robot.world import PhysicalWorld

pytestmark = pytest.mark.slow
ON_THE_FLOOR = (0.4244, 0.998, 0.02)  # where leg 3 lay in the hung episode


def test_a_leg_knocked_to_the_floor_is_put_back_before_it_is_pointed_at() -> None:
    world = PhysicalWorld()
    person = ScriptedPerson((), seed=0, body=PhysicalBody(world, seed=0))
    model, data = world.sim.model, world.sim.data
    adr = int(model.joint(names.leg_joint(3)).qposadr[0])
    data.qpos[adr : adr + 3] = ON_THE_FLOOR
    mujoco.mj_forward(model, data)
    world.sim.run(0.3)
    assert not world.legs.on_table(3), world.legs.position(3)
    still = world.legs.position(0)

    person.perform(Intent(Gesture.POINTING, Action.OBJECT, Target("leg", 3), 3, 0))
    assert person.interventions == 1
    assert world.legs.graspable(3), world.legs.position(3)  # on the table, within reach

    # a leg that lies on the table is left where it is, and pointed at there
    person.perform(Intent(Gesture.POINTING, Action.OBJECT, Target("leg", 0), 0, 0))
    assert person.interventions == 1
    assert abs(world.legs.position(0) - still).max() < 1e-3


def _config(out: Path) -> EpisodeConfig:
    return EpisodeConfig(
        scenario=SCENARIOS_DIR / "one_handover.yaml",
        out=out,
        video=False,
        verify=False,
        progress=False,
    )


def test_an_episode_stops_at_its_simulated_time_limit_the_same_each_time(
    tmp_path: Path,
) -> None:
    spec = _config(tmp_path / "a").spec()
    legs = spec.run.scenario.tables * spec.run.scenario.legs_per_table
    assert spec.time_limit_s == SIM_SECONDS_PER_LEG * legs
    limit = 12.0  # a few actions in: the one handover cannot be done by then
    stopped = replace(spec, time_limit_s=limit)

    summary = run_episode(stopped)
    assert summary["status"] == TIME_LIMIT and summary["error"] == ""
    assert summary["sim_time_limit_s"] == limit
    assert summary["legs_delivered"] < summary["legs_total"]
    times = [entry["sim_time"] for entry in read_step_log(tmp_path / "a" / "episode.jsonl")]
    assert times[-1] >= limit > times[-2], times  # no step after the one that reached it
    assert "stopped at its simulated-time limit, 12.0 s" in summary_text(summary, tmp_path)

    again = run_episode(replace(stopped, out=tmp_path / "b"))
    steps = [(tmp_path / name / "episode.jsonl").read_text() for name in "ab"]
    assert steps[0] == steps[1]
    assert {k: v for k, v in again.items() if "wall" not in k and k != "real_time_factor"} == {
        k: v for k, v in summary.items() if "wall" not in k and k != "real_time_factor"
    }

    row = physical_row(stopped)  # a sweep's row says how the run ended, and the limit
    assert row["ended"] == TIME_LIMIT and row["sim_time_limit_s"] == limit
    assert "status" not in row
