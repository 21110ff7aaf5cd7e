"""Physics speed: the raw ``mj_step`` ceiling against the controlled robot, IK rate, action times.

Run: ``python bench/bench_physics.py [--repeats 5]``. The process is pinned to one CPU core.
Prints three tables (medians of ``--repeats`` runs):

1. raw ``mj_step`` steps/s of the scene (at home, legs on the table; and with a leg held in
   the hand), the ceiling; the controlled loop's steps/s and real-time factor over a whole
   type-A handover (IK planning, fingers, the person's hand, contacts) and its ratio to it;
2. mink IK solves/s on the arm-only kinematic model and on the full model with frozen DoFs;
3. simulated seconds per action of a handover (object, close, human, open).
"""

from __future__ import annotations

import argparse
import os
import statistics
import time
from collections.abc import Callable

import mujoco
import numpy as np
import smoke  # bench/smoke.py: --smoke

from pil.task.world import Target
from pil.types import Action, Feedback, Gesture
from robin_sim.control.ik import ArmIK, arm_kinematic_model, home_arm_q
from robin_sim.control.trajectory import pose, through
from robin_sim.model import names
from robin_sim.model import robot_spec as spec
from robin_sim.person.body import PhysicalBody
from robin_sim.robot.world import PhysicalWorld

HANDOVER = (Action.OBJECT, Action.CLOSE, Action.HUMAN, Action.OPEN)


def _median(runs: int, measure: Callable[[], float]) -> float:
    """Median of ``runs`` calls of ``measure``."""
    return statistics.median(measure() for _ in range(runs))


def raw_steps_per_second(model: mujoco.MjModel, data: mujoco.MjData, steps: int) -> float:
    """``mj_step`` rate from a copy of ``data`` (controls held)."""
    work = mujoco.MjData(model)
    mujoco.mj_copyData(work, model, data)
    start = time.perf_counter()
    for _ in range(steps):
        mujoco.mj_step(model, work)
    return steps / (time.perf_counter() - start)


GESTURE_OF = {
    Action.OBJECT: Gesture.POINTING,
    Action.CLOSE: Gesture.GRASP,
    Action.HUMAN: Gesture.GIVE_ME,
    Action.OPEN: Gesture.RELEASE,
}


def handover(world: PhysicalWorld) -> dict[Action, float]:
    """One type-A handover of leg 0; simulated seconds per step (gesture, action, thumb).

    The person's body performs each gesture (holding out the palm for "give me") and gives the
    thumb; after "open" it carries the leg to the bin.
    """
    body = PhysicalBody(world, seed=0)
    target = Target("leg", 0)
    spent = {}
    for action in HANDOVER:
        before = world.time
        body.perform(GESTURE_OF[action], target if action is Action.OBJECT else None)
        world.execute(action, target if action is Action.OBJECT else None, None)
        assert world.last_result is not None and world.last_result.succeeded, action
        body.show_feedback(Feedback.OK)
        body.after_feedback(Feedback.OK)
        spent[action] = world.time - before
    return spent


def without_sleep(world: PhysicalWorld) -> PhysicalWorld:
    """``world`` with MuJoCo's island sleeping switched off (the default; see build_spec)."""
    world.model.opt.enableflags &= ~int(mujoco.mjtEnableBit.mjENBL_SLEEP)
    return world


def controlled_run(
    sleep: bool = True,
) -> tuple[float, float, float, int, float, dict[Action, float], np.ndarray]:
    """Steps/s, real-time factor, wall s, IK solves, share of wall time in ``mj_step``, the
    action times of one handover and where the legs ended (``sleep`` off: the old settings)."""
    world = PhysicalWorld(sleep=True) if sleep else without_sleep(PhysicalWorld())
    ticks, sim_start, solves = world.sim.ticks, world.time, world.sim.ik.solves
    physics = world.sim.physics_seconds
    start = time.perf_counter()
    spent = handover(world)
    wall = time.perf_counter() - start
    steps = (world.sim.ticks - ticks) * world.sim.substeps
    share = (world.sim.physics_seconds - physics) / wall
    rtf = (world.time - sim_start) / wall
    legs = np.array(world.legs.positions())
    return steps / wall, rtf, wall, world.sim.ik.solves - solves, share, spent, legs


def held_leg_state() -> tuple[mujoco.MjModel, mujoco.MjData]:
    """The scene with leg 0 grasped and lifted (a contact-rich state for the raw ceiling)."""
    world = PhysicalWorld()
    world.execute(Action.OBJECT, Target("leg", 0), None)
    world.execute(Action.CLOSE, None, None)
    here = world.sim.commanded_site_pose()
    up = pose(here.translation() + np.array([0.0, 0.0, 0.15]), here.rotation().wxyz)
    world.sim.execute(world.sim.plan(through([here, up])))
    return world.model, world.data


def ik_solves_per_second(ik: ArmIK, solves: int) -> float:
    """Rate of ``ArmIK.step`` towards a target 10 cm away (re-started every 50 solves)."""
    start_q = ik.q
    here = ik.site_pose()
    goal = pose(here.translation() + np.array([0.05, 0.05, -0.07]), here.rotation().wxyz)
    begin = time.perf_counter()
    for i in range(solves):
        if i % 50 == 0:
            ik.reset(start_q)
        ik.step(goal, 0.02)
    return solves / (time.perf_counter() - begin)


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--repeats", type=int, default=5, help="runs per figure (median)")
    parser.add_argument("--steps", type=int, default=5000, help="mj_step calls per raw run")
    args = smoke.parse_args(parser, argv, repeats=1, steps=200)
    if hasattr(os, "sched_setaffinity"):
        os.sched_setaffinity(0, {min(os.sched_getaffinity(0))})

    world = PhysicalWorld()
    home_model, home_data = world.model, world.data
    held_model, held_data = held_leg_state()
    rows: list[tuple[float, float, float, float, float, float, float, dict[Action, float]]] = []
    before: list[tuple[float, float]] = []  # (steps/s, wall s) with sleeping off
    ends: list[float] = []  # legs' end positions, sleep on vs off (m, largest difference)
    for _ in range(args.repeats):  # interleaved, so that load from other processes hits all
        raw_home = raw_steps_per_second(home_model, home_data, args.steps)
        raw_held = raw_steps_per_second(held_model, held_data, args.steps)
        rate, rtf, wall, solves, share, spent, legs = controlled_run()
        rows.append((raw_home, raw_held, rate, rtf, wall, solves, share, spent))
        old_rate, _, old_wall, _, _, _, old_legs = controlled_run(sleep=False)
        before.append((old_rate, old_wall))
        ends.append(float(np.abs(legs - old_legs).max()))

    def med(i: int) -> float:
        return statistics.median(float(row[i]) for row in rows)  # type: ignore[arg-type]

    ratio = statistics.median(row[2] / min(row[0], row[1]) for row in rows)
    timestep = home_model.opt.timestep
    print(
        f"\nPhysics speed, one core, timestep {timestep * 1e3:.0f} ms, control "
        f"{1 / world.sim.control_dt:.0f} Hz (median of {args.repeats}, interleaved)"
    )
    print(f"| {'measure':<44} | {'steps/s':>9} | {'x real time':>11} |")
    print(f"|{'-' * 46}|{'-' * 11}|{'-' * 13}|")
    for label, value in (
        ("raw mj_step, at home (legs on the table)", med(0)),
        ("raw mj_step, leg held in the hand", med(1)),
        ("controlled: full handover (IK, hand, person)", med(2)),
    ):
        print(f"| {label:<44} | {value:>9.0f} | {value * timestep:>11.1f} |")
    print(
        f"controlled / ceiling (lower raw figure of the same repeat): {ratio:.0%}; one handover "
        f"takes {med(4):.2f} s wall with {med(5):.0f} IK solves (real-time factor {med(3):.1f})"
    )
    print(
        f"share of the controlled run's wall time spent in mj_step (same states, no load "
        f"difference): {med(6):.0%}"
    )
    gains = sorted(b[1] / r[4] for b, r in zip(before, rows, strict=True))
    old = statistics.median(b[0] for b in before)
    print(
        f"\nIsland sleeping (legs at rest sleep), the controlled handover in the same run: "
        f"{old:.0f} steps/s without, {med(2):.0f} with (medians); gain per interleaved pair "
        f"(wall without / wall with): median {statistics.median(gains):.2f}x, all "
        + ", ".join(f"{g:.2f}" for g in gains)
        + f"; legs' end positions differ by at most {1000 * max(ends):.2f} mm"
    )
    runs = [row[7] for row in rows]

    spec_model = world.spec
    side = names.ACTIVE_SIDE
    limits = dict(zip(names.arm_joints(side), spec.ARM_VELOCITY_LIMITS, strict=True))
    home = home_arm_q(home_model, side)
    reduced = ArmIK(arm_kinematic_model(spec_model, side), side, limits, posture_q=home)
    full = ArmIK(home_model, side, limits, posture_q=home)
    print(f"\nmink IK (daqp), solves/s (median of {args.repeats})")
    print(f"| {'IK model':<40} | {'DoF':>4} | {'solves/s':>9} | {'µs/solve':>9} |")
    print(f"|{'-' * 42}|{'-' * 6}|{'-' * 11}|{'-' * 11}|")
    for label, ik in (
        ("arm-only kinematic copy (used)", reduced),
        ("full scene, other DoFs frozen", full),
    ):
        per_s = _median(args.repeats, lambda ik=ik: ik_solves_per_second(ik, 500))
        print(f"| {label:<40} | {ik.model.nv:>4} | {per_s:>9.0f} | {1e6 / per_s:>9.0f} |")

    print(f"\nSimulated seconds per action of a handover (median of {args.repeats})")
    print(f"| {'action':<10} | {'sim s':>6} |")
    print(f"|{'-' * 12}|{'-' * 8}|")
    for action in HANDOVER:
        print(f"| {action.value:<10} | {statistics.median(r[action] for r in runs):>6.2f} |")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
