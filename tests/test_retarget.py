"""Retargeting tracked landmarks onto the hand (robin_sim.figure.retarget): closed form, refined."""

from __future__ import annotations

import mujoco
import numpy as np
import pytest
from hand_data import footage

from robin_sim.figure.retarget import FINGER_POINTS, Retargeter, metric, steady_palm_frame
from robin_sim.model import names, person_joints
from robin_sim.model.pose_library import load_library
from robin_sim.model.scene import build_model

# degrees: median over the footage's frames and a finger's three bones of the angle between a
# bone's direction (palm frame) in the landmarks and in the model posed with the fitted angles
MEDIAN_BOUND = 12.0  # measured refined: thumb 1.7, index 9.3, middle 9.4, ring 7.1, little 7.4
GUESS_WORSE = 15.0  # the guess alone: thumb 1.5, index 21, middle 21, ring 20, little 26


@pytest.fixture(scope="module")
def fitted() -> dict[str, list[float]]:
    return bone_errors(refine=True)


def bone_errors(refine: bool) -> dict[str, list[float]]:
    model = build_model()
    data = mujoco.MjData(model)
    retargeter = Retargeter(model)
    qadr = person_joints.figure().adr(retargeter.joints)  # the person's joints live in userdata
    hand = model.body(names.person_hand_body("r")).id
    reads = footage()
    errors: dict[str, list[float]] = {}
    for i in np.flatnonzero(np.isin(reads["sequence"], ["fist", "palm", "thumb_up"])):
        points, aspect = reads["landmarks"][i], float(reads["aspect"][i])
        if not np.isfinite(points).all():
            continue
        mirror = retargeter.curled_toward_palm(points, aspect, False) < 0
        data.userdata[qadr] = retargeter.fit(points, aspect, mirror, refine=refine)
        person_joints.pose(model, data)
        mujoco.mj_kinematics(model, data)
        p = metric(points, aspect, mirror)
        frame = steady_palm_frame(p)
        rotation = data.xmat[hand].reshape(3, 3)
        for finger, marks in FINGER_POINTS.items():
            bodies = [data.xpos[model.body(b).id] for b in names.person_finger_bodies("r", finger)]
            joints = [*bodies, data.site(names.person_fingertip_site("r", finger)).xpos]
            for k in range(3):  # each bone: knuckle to knuckle, the last to the tip
                got = rotation.T @ (joints[k + 1] - joints[k])
                want = frame.T @ (p[marks[k + 1]] - p[marks[k]])
                cos = np.dot(got, want) / np.linalg.norm(got) / np.linalg.norm(want)
                angle = float(np.degrees(np.arccos(np.clip(cos, -1, 1))))
                errors.setdefault(finger, []).append(angle)
    return errors


def test_fitted_fingers_point_where_the_tracked_ones_do(fitted: dict[str, list[float]]) -> None:
    medians = {finger: float(np.median(e)) for finger, e in fitted.items()}
    assert len(fitted["index"]) >= 3 * 60  # fist, palm and thumb up frames with a hand
    assert all(m < MEDIAN_BOUND for m in medians.values()), medians


def test_the_refinement_brings_the_curled_fingers_nearer() -> None:
    """Without the least-squares step the four fingers lie further off (the bound fails)."""
    guess = {finger: float(np.median(e)) for finger, e in bone_errors(refine=False).items()}
    assert all(guess[f] > GUESS_WORSE for f in ("index", "middle", "ring", "little")), guess


def test_the_library_is_the_footage_fit_and_names_its_sources() -> None:
    library = load_library()
    model_joints = names.person_hand_joints("r")
    assert library.joints == tuple(j.removeprefix("human_r_") for j in model_joints)
    for pose in ("grasp", "give_me", "thumb_up"):
        assert library.sources[pose].startswith("footage:")
    for pose in ("pointing", "release", "thumb_down", "neutral"):
        assert library.sources[pose].startswith("built:")
    fist, palm = library.pose("grasp"), library.pose("give_me")
    mcp = [4 + 4 * k + 1 for k in range(4)]  # index .. little MCP flexion
    assert np.all(fist[mcp] > palm[mcp] + 0.6)  # the fist's knuckles bent, the palm's flat
