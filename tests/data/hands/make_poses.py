"""Make the person's hand pose library from the tracker's readings of real hands.

Run from the repository root (no footage or browser needed: it reads ``landmarks.npz``, the
vendored MediaPipe Hands tracker's readings of the Apache-2.0 footage made by
``make_data.py``):

    python tests/data/hands/make_poses.py

writes ``robin_sim/model/data/hand_poses.json``. Each frame's 21 landmarks are retargeted
onto the model's right hand (:mod:`robin_sim.figure.retarget`: closed form, refined); which side the
tracker saw is decided per frame by where the fingertips lie (curled fingers are on the palm
side: the tracker's handedness label follows the selfie convention). A pose from footage is
the per-joint median over its frames, its ``sd`` the per-joint spread over those frames
(floored at :data:`SD_FLOOR`, capped at :data:`SD_CAP`): the seeded variation a performance
draws. Poses the footage lacks are built from joints and marked so.
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np

from robin_sim.figure.retarget import Retargeter
from robin_sim.model import names
from robin_sim.model.scene import build_model

HERE = Path(__file__).resolve().parent
OUT = HERE.parents[2] / "robin_sim" / "model" / "data" / "hand_poses.json"
SD_FLOOR, SD_CAP = 0.03, 0.15  # rad
FOOTAGE = {"grasp": "fist", "give_me": "palm", "thumb_up": "thumb_up"}
CHECKS = {"thumb_down": "thumb_down", "release": "open_up"}  # flipped / turned frames


def fit_sequence(retargeter: Retargeter, data: dict[str, np.ndarray], seq: str) -> np.ndarray:
    """Joint angles (frames, 20) of every frame of ``seq`` in which a hand was found."""
    rows = []
    for i in np.flatnonzero(data["sequence"] == seq):
        points, aspect = data["landmarks"][i], float(data["aspect"][i])
        if not np.isfinite(points).all():
            continue
        mirror = retargeter.curled_toward_palm(points, aspect, False) < 0
        rows.append(retargeter.fit(points, aspect, mirror))
    return np.array(rows)


def main() -> None:
    with np.load(HERE / "landmarks.npz") as npz:
        data = {k: npz[k] for k in npz.files}
    retargeter = Retargeter(build_model())
    joints = list(retargeter.joints)
    index = {j: k for k, j in enumerate(joints)}
    poses: dict[str, dict[str, object]] = {}
    fitted = {}
    for pose, seq in FOOTAGE.items():
        angles = fit_sequence(retargeter, data, seq)
        fitted[pose] = angles
        poses[pose] = {
            "angles": np.median(angles, axis=0),
            "sd": np.clip(angles.std(axis=0), SD_FLOOR, SD_CAP),
            "source": f"footage: {seq}, {len(angles)} frames",
        }

    def built(base: str, changes: dict[str, float], source: str) -> dict[str, object]:
        angles = np.array(poses[base]["angles"], float).copy()
        for joint, value in changes.items():
            angles[index[joint]] = value
        return {"angles": angles, "sd": np.array(poses[base]["sd"]), "source": source}

    r = "human_r_"
    straight_index = {f"{r}index_spread": 0.05, f"{r}index_mcp": 0.05, f"{r}index_pip": 0.08}
    straight_index[f"{r}index_dip"] = 0.05
    poses["pointing"] = built(
        "grasp", straight_index, "built: the fist from footage with the index straight"
    )
    poses["thumb_down"] = built(
        "thumb_up", {}, "built: the thumb up's joints (the wrist turns it down)"
    )
    spread = {"index": 0.3, "middle": 0.08, "ring": -0.14, "little": -0.34}
    wide = {f"{r}{f}_spread": v for f, v in spread.items()}
    wide.update({f"{r}thumb_cmc_abduct": -0.2, f"{r}thumb_cmc_flex": 0.0})
    poses["release"] = built("give_me", wide, "built: the open palm from footage, spread wide")
    relaxed = {f"{r}{f}_{k}": v for f in spread for k, v in (("mcp", 0.45), ("pip", 0.6))}
    relaxed.update({f"{r}{f}_dip": 0.3 for f in spread})
    poses["neutral"] = built("give_me", relaxed, "built: the open palm, fingers half relaxed")
    checks = {}
    for pose, seq in CHECKS.items():
        angles = fit_sequence(retargeter, data, seq)
        base = "thumb_up" if pose == "thumb_down" else "give_me"
        diff = np.abs(np.median(angles, axis=0) - np.asarray(poses[base]["angles"]))
        checks[f"{seq} readings vs {base}"] = round(float(diff.mean()), 3)
    library = {
        "format": 1,
        "made_by": "tests/data/hands/make_poses.py",
        "source": (
            "the vendored MediaPipe Hands tracker's readings (tests/data/hands/landmarks.npz) "
            "of google-ai-edge/mediapipe-samples footage (commit ece8a1f9), Apache-2.0"
        ),
        "fit": (
            "closed form, refined by least squares on the bone directions "
            "(robin_sim.figure.retarget)"
        ),
        "joints": [j.removeprefix(r) for j in joints],
        "mean_abs_difference_rad": checks,
        "poses": {
            name: {
                "source": p["source"],
                "angles": [round(float(v), 4) for v in np.asarray(p["angles"])],
                "sd": [round(float(v), 4) for v in np.asarray(p["sd"])],
            }
            for name, p in sorted(poses.items())
        },
    }
    assert set(library["poses"]) == set(names.HUMAN_VIS_POSES)
    OUT.write_text(json.dumps(library, indent=1) + "\n")
    print(f"wrote {OUT} ({len(poses)} poses); checks: {checks}")


if __name__ == "__main__":
    main()
