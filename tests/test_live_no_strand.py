"""Live never strands a participant (issue 38, item 5): real sessions (physics, the learner,
the files), driven as a participant at the page.

The issue's reproduction: P01, seed 0; a click on the red leg; a thumb down on each of Robin's
tries until it moves its empty hand to the person or to a spot; that move let stand (no thumb,
or a thumb up). Before, every later gesture was handed back ("free at human or location"), the
guide kept asking to point at the leg and nothing moved on. Now the loop grounds Robin's state
in its hand and the guide takes the same grounded state (:func:`pil.task.grounding.ground`):
the participant points at the leg as the guide says, Robin acts, and the handover goes on.
"""

from __future__ import annotations

from pathlib import Path

import pytest
from live_driver import Driver, read_jsonl
from live_driver import start_session as session

from robin_sim.live.session import LiveSession

pytestmark = pytest.mark.slow
EMPTY_HAND_MOVES = ("human", "location")


def refuse_until_empty_hand_move(live: LiveSession, driver: Driver, verdict: str) -> list[str]:
    """Thumb down on each try of the gesture just made until Robin moves its empty hand to the
    person or a spot; that move gets ``verdict`` ("up", or "silence": no thumb). The tries."""
    tried: list[str] = []
    driver.wait(lambda s: s["phase"] != "waiting_for_gesture", "the gesture taken")
    while True:
        s = driver.wait(
            lambda s: (
                s["action"] is not None
                or s["phase"] == "waiting_for_thumb"
                or (s["phase"] == "waiting_for_gesture" and s["actions"] == len(tried))
            ),
            "Robin's next try",
        )
        assert s["phase"] != "waiting_for_gesture", f"handed back before a wrong move: {s}"
        tried.append(s["action"] or s["last_action"])
        if tried[-1] in EMPTY_HAND_MOVES:
            if verdict == "up":
                live.receive({"type": "thumb", "value": "up"})
            driver.wait(lambda s: s["actions"] >= len(tried), "the move logged")
            return tried
        live.receive({"type": "thumb", "value": "down"})
        driver.wait(lambda s: s["actions"] >= len(tried), "the try logged")


@pytest.mark.parametrize("verdict", ["silence", "up"])
def test_the_empty_hand_move_let_stand_is_no_dead_end(tmp_path: Path, verdict: str) -> None:
    live, driver = session(tmp_path, participant="P01", seed=0, feedback_window=1.0)
    try:
        driver.my_turn()
        driver.point_at_leg(0)
        tried = refuse_until_empty_hand_move(live, driver, verdict)
        turn = driver.my_turn()
        # the guide asks for what Robin can act on in its grounded state: the leg again
        assert turn["guide"]["instruction"].startswith("Point at the red leg"), turn["guide"]
        driver.point_at_leg(0)
        seen = driver.judge("object")  # Robin acts on the click (no hand-back) until object
        assert seen and seen[-1] == "object", seen
        turn = driver.my_turn()
        assert turn["guide"]["instruction"].startswith("Make the grasp gesture"), turn["guide"]
        driver.gesture("grasp")
        assert driver.judge("close")[-1] == "close"
        turn = driver.my_turn()
        assert turn["guide"]["step"] == 2, turn["guide"]  # on to the handover's next step
    finally:
        live.stop("ended")
    steps = read_jsonl(live.out_dir / "log.jsonl")
    stood = len(tried)
    assert steps[stood - 1]["action"] in EMPTY_HAND_MOVES
    assert steps[stood - 1]["feedback"] == ("ok" if verdict == "up" else "none")
    after = steps[stood]
    assert after["state"] == "pointing|open|free", after  # grounded: as after open
    assert after["reason"].startswith("re-grounded"), after["reason"]
    events = read_jsonl(live.out_dir / "events.jsonl")
    kinds = [e["event"] for e in events]
    assert "handed_back" not in kinds and "watchdog" not in kinds, kinds
    regrounded = [e for e in events if e["event"] == "regrounded"]  # logged as it recovers
    assert len(regrounded) == 1 and "follows no right approval" in regrounded[0]["reason"]
    assert [s["t"] for s in steps if s["action"]] == list(range(1, len(steps) + 1))


def test_gestures_handed_back_in_a_row_wake_the_watchdog_and_robin_proposes(
    tmp_path: Path,
) -> None:
    """After an approved object (the hand empty, at the leg), release and give me are invalid
    and nothing learnt corrects them: each is handed back. The third in a row wakes the
    watchdog (the page says the way on); on the fourth Robin proposes an action itself."""
    live, driver = session(tmp_path, seed=0)
    try:
        driver.my_turn()
        driver.point_at_leg(0)
        assert driver.judge("object")[-1] == "object"
        actions = driver.my_turn()["actions"]
        for k, name in enumerate(("release", "give_me", "release")):
            driver.gesture(name)
            back = driver.wait(
                lambda s, n=k + 1: s["phase"] == "waiting_for_gesture" and s["gestures"] > n,
                "the gesture handed back",
            )
        assert back["notice"].endswith(
            "That was 3 of your gestures in a row Robin could not act on. Make the gesture the "
            "guide asks for; if Robin cannot act on your next gesture either, it proposes an "
            "action for your thumb."
        ), back["notice"]
        assert back["guide"]["instruction"].startswith("Make the grasp gesture"), back["guide"]
        assert back["actions"] == actions  # nothing acted on
        driver.gesture("give_me")  # the fourth: Robin proposes an action for the thumb
        driver.wait(lambda s: s["action"] is not None, "Robin's proposal")
        live.receive({"type": "thumb", "value": "down"})
        driver.wait(lambda s: s["actions"] > actions, "the proposal logged")
    finally:
        live.stop("ended")
    events = read_jsonl(live.out_dir / "events.jsonl")
    backs = [e for e in events if e["event"] in ("handed_back", "watchdog")]
    assert [e["event"] for e in backs] == ["handed_back", "handed_back", "watchdog"], backs
    assert backs[-1]["stuck"] == "3 of your gestures in a row Robin could not act on"
    steps = read_jsonl(live.out_dir / "log.jsonl")
    repeats = [s for s in steps if s["action"] is None]
    assert [s["true_gesture"] for s in repeats] == ["release", "give me", "release"], repeats
    acted = [s for s in steps if s["action"] is not None and s["true_gesture"] == "give me"]
    assert acted and acted[0]["reason"].startswith("cannot read the gesture"), acted


def test_a_leg_pushed_out_of_reach_is_put_back_before_the_next_turn() -> None:
    """Found by the soak of wrong moves let stand: a leg left on the table out of Robin's reach
    (0.785, -0.488: the soak's) made the next point at it fail the session ("out of the arm's
    reach"). The participant's simulated hand puts such a leg back at its place (a person
    intervention) before the turn; a delivered leg, or one within reach, stays where it is."""
    import mujoco

    from robin_sim.model import names
    from robin_sim.model.robot_spec import GRASP_HEIGHT
    from robin_sim.person.body import PhysicalBody
    from robin_sim.robot.world import PhysicalWorld

    world = PhysicalWorld()
    body = PhysicalBody(world, seed=0)
    data, model = world.sim.data, world.sim.model
    for leg in (0, 1):
        adr = int(model.joint(names.leg_joint(leg)).qposadr[0])
        data.qpos[adr : adr + 3] = [0.785, -0.488 + 0.1 * leg, GRASP_HEIGHT]
    mujoco.mj_forward(model, data)
    assert world.legs.out_of_reach(0) and world.legs.out_of_reach(1)
    assert body.put_back_strays(delivered={1}) == 1  # leg 1 counts as delivered: left there
    assert not world.legs.out_of_reach(0) and world.legs.graspable(0)
    assert world.legs.out_of_reach(1)
    assert body.put_back_strays(delivered={1}) == 0
