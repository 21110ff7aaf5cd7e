"""What the articulated person costs the physics: ``mj_step`` with and without its bodies.

Run: ``python bench/bench_person_physics.py [--repeats 5] [--steps 3000]``. Pinned to one
core; steps per second of CPU time (the process's own, so that other work on a shared core
counts less). Prints the median steps/s of raw ``mj_step`` (the robot at home, legs on the
table) of:

1. the scene as shipped: the articulated person without DoFs (its joints' values live in
   ``data.userdata`` and pose its bodies' frames, :mod:`robin_sim.model.person_joints`), idle;
2. the same scene with the person's articulated bodies removed (the body, arms and both
   hands; the mocap hand and the welded collision palm stay): the baseline, measured in the
   same run, which the capsule person of before matched (no person DoFs);
3. the shipped scene with the person's pose solved and written at every control tick (50 Hz,
   :class:`robin_sim.figure.posture.Posture`, the hand moving so every tick solves); in an
   episode it is solved only when a frame is rendered (a view hook), at most at video rate;
4. the same at video rate (30 Hz: every 17th step), the hand moving every control tick;
5. the shipped scene posed once as the person reaches (give me, the hand 0.3 m towards the
   table, solved once) and stepped without solving: the person's geoms move MuJoCo's
   broad phase frame (it is fitted to every non-world geom, collidable or not), so a pose
   changes the cost a little;
6. the scene as ``scene.xml`` is written, the person with its 63 joint DoFs (as it was
   shipped before), idle.

Every case steps its own compiled model (a solve writes the person's frames into the
model), and the ratios are to the baseline.
"""

from __future__ import annotations

import argparse
import os
import statistics
import time

import mujoco
import numpy as np
import smoke  # bench/smoke.py: --smoke

from robin_sim.figure.articulated import ArticulatedHand
from robin_sim.figure.posture import Posture
from robin_sim.model import names
from robin_sim.model.scene import build_spec

CONTROL_EVERY = 10  # steps of 2 ms per control tick (50 Hz)
VIDEO_EVERY = 17  # steps of 2 ms per video frame (30 fps)


def without_person() -> mujoco.MjModel:
    """The scene less the articulated person's bodies (see the module doc)."""
    spec = build_spec()
    for name in (names.PERSON_BODY, names.person_hand_body("r")):
        spec.delete(spec.body(name))
    return spec.compile()


def with_person_joints() -> mujoco.MjModel:
    """The scene as ``scene.xml`` is written: the person with its 63 joint DoFs (case 5)."""
    return mujoco.MjModel.from_xml_path(str(names.SCENE_XML))


REACH = np.array([-0.3, 0.0, 0.0])  # m: the hand's way towards the table in cases 3-5


def posed_reaching() -> mujoco.MjModel:
    """The shipped scene with the person posed once as it reaches (case 5)."""
    model = build_spec().compile()
    data = mujoco.MjData(model)
    mujoco.mj_resetDataKeyframe(model, data, model.key(names.HOME_KEY).id)
    ArticulatedHand(model, data).show("give_me")
    data.mocap_pos[int(model.body(names.HUMAN_MOCAP_BODY).mocapid[0])] += REACH
    Posture(model, data).update()  # writes the person's body frames into the model
    return model


def steps_per_second(model: mujoco.MjModel, steps: int, solve_every: int = 0) -> float:
    """``mj_step`` rate from the home keyframe; ``solve_every`` > 0: the hand moves every
    control tick and the person is solved every ``solve_every`` steps."""
    data = mujoco.MjData(model)
    mujoco.mj_resetDataKeyframe(model, data, model.key(names.HOME_KEY).id)
    person = None
    if solve_every:
        ArticulatedHand(model, data).show("give_me")
        person = Posture(model, data)
    mocap = int(model.body(names.HUMAN_MOCAP_BODY).mocapid[0])
    start_pos = data.mocap_pos[mocap].copy()
    start = time.process_time()  # CPU time: what the other work on a shared core takes is not ours
    for k in range(steps):
        if person is not None and k % CONTROL_EVERY == 0:
            data.mocap_pos[mocap] = start_pos + REACH * k / steps
        if person is not None and k % solve_every == 0:
            person.update()
        mujoco.mj_step(model, data)
    return steps / (time.process_time() - start)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=5)
    parser.add_argument("--steps", type=int, default=3000)
    args = smoke.parse_args(parser, repeats=1, steps=100)
    if hasattr(os, "sched_setaffinity"):
        os.sched_setaffinity(0, {sorted(os.sched_getaffinity(0))[0]})
    shipped, baseline = build_spec().compile(), without_person()
    cases = {
        "scene as shipped (the person posed from userdata, no DoFs)": (shipped, 0),
        "without the person's articulated bodies (baseline)": (baseline, 0),
        "as shipped, the person solved every control tick": (
            build_spec().compile(),
            CONTROL_EVERY,
        ),
        "as shipped, the person solved at video rate": (build_spec().compile(), VIDEO_EVERY),
        "as shipped, posed once reaching (not solved)": (posed_reaching(), 0),
        "the person with its 63 joint DoFs (before)": (with_person_joints(), 0),
    }
    rates: dict[str, list[float]] = {name: [] for name in cases}
    for _ in range(args.repeats):  # interleaved: a load change hits every case alike
        for name, (model, solve_every) in cases.items():
            rates[name].append(steps_per_second(model, args.steps, solve_every))
    base = statistics.median(rates["without the person's articulated bodies (baseline)"])
    print(f"nv: shipped {shipped.nv}, baseline {baseline.nv}; {args.repeats} runs of {args.steps}")
    print("| case | steps/s (median) | ratio to baseline |")
    print("|---|---|---|")
    for name, values in rates.items():
        rate = statistics.median(values)
        print(f"| {name} | {rate:.0f} | {rate / base:.2f} |")


if __name__ == "__main__":
    main()
