"""The right arm's seven angles in closed form: the elbow on its circle, the wrist turned.

Given the shoulder, the direction and length of the reach and a hint of where the elbow
should swing, :meth:`ArmAngles.solve` places the elbow (law of cosines), reads the shoulder's
three angles and the elbow's from the upper arm's and forearm's frames, and the forearm roll
and the wrist's two angles from the turn left to the hand's wanted frame, each clipped to its
joint's range. What the clipping leaves of that turn is the wrist's error (rad); an upper arm
or elbow out of range adds pi, so it is chosen only as a last resort.
:class:`~robin_sim.figure.posture.Posture` calls it for each candidate torso and elbow swing.
"""

from __future__ import annotations

import math

import numpy as np

from robin_sim.figure.torso import axis_rotation

_Y = np.array([0.0, 1.0, 0.0])


def clip1(value: float) -> float:
    """``value`` inside [-1, 1] (for arcsin and arccos)."""
    return min(max(float(value), -1.0), 1.0)


def unit(v: np.ndarray) -> np.ndarray:
    """``v`` scaled to length 1 (a zero vector stays near zero)."""
    return v / max(math.sqrt(float(v @ v)), 1e-12)


def cross(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """a x b of two 3-vectors (``np.cross`` costs ten times as much on one pair)."""
    return np.array(
        [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]
    )


class ArmAngles:
    """The arm's segment lengths (m), joint ranges and wrist axes; :meth:`solve` (module doc)."""

    def __init__(
        self,
        upper: float,
        fore: float,
        arm_ranges: list[tuple[float, float]],
        wrist_axes: list[np.ndarray],
    ) -> None:
        self.upper, self.fore = upper, fore
        self.arm_ranges, self.wrist_axes = arm_ranges, wrist_axes

    def solve(
        self,
        torso: np.ndarray,
        shoulder: np.ndarray,
        n: np.ndarray,
        stretch: float,
        wanted: np.ndarray,
        hint: np.ndarray,
    ) -> tuple[tuple[float, ...], float, np.ndarray]:
        """The arm's seven angles with the elbow swung towards ``hint``, the wrist's remaining
        turn (rad) from ``wanted`` after its joint limits, and the elbow (world)."""
        cos_a = (self.upper**2 + stretch**2 - self.fore**2) / (2 * self.upper * stretch)
        m = unit(hint - np.dot(hint, n) * n)
        alpha = float(np.arccos(clip1(cos_a)))
        elbow = shoulder + self.upper * (np.cos(alpha) * n + np.sin(alpha) * m)
        u = unit(elbow - shoulder)
        f = unit(shoulder + stretch * n - elbow)
        bend = f - np.dot(f, u) * u
        x = -unit(bend) if float(bend @ bend) > 1e-12 else torso[:, 0]
        z = -u
        upper = torso.T @ np.array([x, cross(z, x), z]).T
        flex = float(np.arctan2(upper[0, 2], upper[2, 2]))
        abduct = float(np.arcsin(clip1(-upper[1, 2])))
        rot = float(np.arctan2(upper[1, 0], upper[1, 1]))
        elbow_angle = float(np.arccos(clip1(np.dot(u, f))))
        fore = torso @ upper @ axis_rotation(_Y, elbow_angle)
        rest = fore.T @ wanted
        roll = float(np.arctan2(-rest[0, 1], rest[1, 1]))  # z, then -x (flex), then y (dev)
        wrist_flex = -float(np.arcsin(clip1(rest[2, 1])))
        wrist_dev = float(np.arctan2(-rest[2, 0], rest[2, 2]))
        angles = (flex, abduct, rot, elbow_angle, roll, wrist_flex, wrist_dev)
        clipped = [min(max(a, lo), hi) for a, (lo, hi) in zip(angles, self.arm_ranges, strict=True)]
        axes = self.wrist_axes
        got = (
            axis_rotation(axes[0], clipped[4])
            @ axis_rotation(axes[1], clipped[5])
            @ axis_rotation(axes[2], clipped[6])
        )
        error = float(np.arccos(clip1((float(np.sum(got * rest)) - 1) / 2)))
        if any(abs(c - a) > 1e-9 for c, a in zip(clipped[:4], angles[:4], strict=True)):
            error += np.pi  # the upper arm or elbow out of range: only a last resort
        return tuple(clipped), error, elbow
