"""Over whole episodes, the person passes through nothing: legs, table, bin and robot.

Real episodes (MuJoCo physics, the scripted person, small EGL renders and their states file):
``one_handover`` at three seeds and ``table_one`` (three handovers) at one. Every recorded state
is re-applied as a render applies it (the person's joints as the view hook solved them, the
recorded userdata; :func:`robin_sim.render.worker.apply_state`), and the deepest reach of every
person geom into the handed-over legs, the table, the bin and the robot
(:mod:`robin_sim.person.clearance`) must be at most :data:`BOUND`. A failure lists each pair
that went deeper: category, person geom, other geom, the time of its deepest reach and depth.
"""

from __future__ import annotations

import mujoco
import numpy as np
import pytest
from recorded_episode import record_episode

from robin_sim.render.gl_backend import ensure_gl_backend

ensure_gl_backend()

from robin_sim.model import names  # noqa: E402
from robin_sim.model.scene import build_model  # noqa: E402
from robin_sim.person.clearance import CATEGORIES, Clearance  # noqa: E402
from robin_sim.render.state_log import RecordedStates  # noqa: E402
from robin_sim.render.worker import apply_state  # noqa: E402

BOUND = 0.002  # m
EPISODES = (("one_handover", 0), ("one_handover", 1), ("one_handover", 2), ("table_one", 0))
# m: the recorded arm's wrist meets the hand's wrist point (the posture was solved for the
# render; it may trail a moving hand by one view period)
POSED = 0.03


@pytest.fixture(scope="module", params=EPISODES, ids=[f"{s}-{n}" for s, n in EPISODES])
def episode(
    request: pytest.FixtureRequest, tmp_path_factory: pytest.TempPathFactory
) -> tuple[str, RecordedStates, dict]:
    scenario, seed = request.param
    folder = tmp_path_factory.mktemp(f"{scenario}{seed}")
    recorded, summary = record_episode(folder, scenario, seed, (96, 72), 10)
    return f"{scenario} seed {seed}", recorded, summary


def deepest_reaches(recorded: RecordedStates) -> tuple[dict, float]:
    """Per (category, person geom, other geom): the deepest reach (m) and its time; and the
    share of states whose arm's wrist meets the hand (the posture was solved)."""
    model = build_model(recorded.layout)
    data = mujoco.MjData(model)
    clearance = Clearance(model)
    wrist = model.site(names.person_wrist_site("r")).id
    point = model.site(names.person_wrist_point("r")).id
    worst: dict[tuple[str, str, str], tuple[float, float]] = {}
    posed = 0
    for state in recorded.states:
        apply_state(model, data, state)
        posed += float(np.linalg.norm(data.site_xpos[wrist] - data.site_xpos[point])) <= POSED
        for reach in clearance.measure(data):
            key = (reach.category, reach.person, reach.other)
            if reach.depth > worst.get(key, (0.0, 0.0))[0]:
                worst[key] = (reach.depth, state.time)
    return worst, posed / len(recorded.states)


@pytest.mark.slow
def test_no_person_geom_reaches_into_legs_table_bin_or_robot(
    episode: tuple[str, RecordedStates, dict],
) -> None:
    label, recorded, summary = episode
    assert summary["status"] == "finished" and summary["legs_to_person"] >= 1, summary
    worst, posed = deepest_reaches(recorded)
    assert posed >= 0.9, f"{label}: the arm meets the hand in only {posed:.0%} of the states"
    deepest = {
        c: max((d for (k, *_), (d, _) in worst.items() if k == c), default=0.0) for c in CATEGORIES
    }
    failures = [
        f"{category}: {person} into {other} at t = {time:.1f} s: {depth * 1000:.1f} mm"
        for (category, person, other), (depth, time) in sorted(
            worst.items(), key=lambda kv: -kv[1][0]
        )
        if depth > BOUND
    ]
    per_category = ", ".join(f"{c} {d * 1000:.1f} mm" for c, d in deepest.items())
    assert not failures, f"{label}: deepest {per_category}\n" + "\n".join(failures)
