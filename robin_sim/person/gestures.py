"""Show the person's hand pose (the gesture or feedback being made) in renders.

The scene's person hand carries one set of visual-only geoms (contype = conaffinity = 0) per
pose, named ``human_vis_<pose>_<part>`` (:func:`robin_sim.model.names.human_vis_geom`, poses
:data:`robin_sim.model.names.HUMAN_VIS_POSES`). :class:`GestureDisplay` shows one pose by giving its
geoms their visible alpha in ``model.geom_rgba`` and every other pose's geoms alpha 0, which
MuJoCo does not draw. Only colours change, so physics is unaffected.

A model with six part geoms per pose gets each pose's shape from
:mod:`robin_sim.figure.hand_poses`, and ``show(sign, performance)`` varies one performance
(pose jitter, hand size, skin tone). The project's scene holds the articulated person instead
(``models/person/person.xml``): there the display forms each pose with the hand's joints
(:class:`robin_sim.figure.articulated.ArticulatedHand`, poses from real hands), given the
scene's ``data``; ``show(..., blend=s)`` moves the hand into the pose over ``s`` seconds, played
out by :meth:`GestureDisplay.update` at each control tick.
"""

from __future__ import annotations

import mujoco
import numpy as np

from pil.errors import InvalidChoiceError, RobinPilError
from pil.types import SIGN_OF, Feedback, Gesture
from robin_sim.figure.articulated import ArticulatedHand, has_articulated_hand
from robin_sim.figure.hand_poses import HandShaper, Performance
from robin_sim.model import names
from robin_sim.model.names import HUMAN_VIS_PREFIX  # what every pose geom's name starts with

NEUTRAL_POSE = "neutral"
POSES: tuple[str, ...] = names.HUMAN_VIS_POSES  # neutral and the six signs (pil.types)
GESTURE_POSES: dict[Gesture, str] = {gesture: SIGN_OF[gesture] for gesture in Gesture}
FEEDBACK_POSES: dict[Feedback, str] = {
    Feedback.OK: SIGN_OF[Feedback.OK],
    Feedback.NOT_OK: SIGN_OF[Feedback.NOT_OK],
    Feedback.NONE: NEUTRAL_POSE,
}


def pose_for(sign: Gesture | Feedback | str | None) -> str:
    """Hand pose showing a gesture or feedback (enum or its name), a pose name, or ``None``.

    ``None`` and no feedback show the neutral pose.
    """
    if sign is None:
        return NEUTRAL_POSE
    if isinstance(sign, Gesture):
        return GESTURE_POSES[sign]
    if isinstance(sign, Feedback):
        return FEEDBACK_POSES[sign]
    if sign in POSES:
        return sign
    for kind in (Gesture, Feedback):
        try:
            return pose_for(kind(sign))
        except ValueError:
            pass
    choices = [*POSES, *(g.value for g in Gesture), *(f.value for f in Feedback)]
    raise InvalidChoiceError("hand pose", sign, choices)


class GestureDisplay:
    """Switches which of the person's hand poses is visible in ``model``.

    The model must have ``human_vis_<pose>_*`` geoms for every pose but ``neutral`` (which may
    have its own geoms or show none). Each geom's visible alpha is its alpha in the model as
    loaded, or 1 where the model hides it (alpha 0). The pose starts as ``neutral``.
    """

    def __init__(self, model: mujoco.MjModel, data: mujoco.MjData | None = None) -> None:
        self._model = model
        self.hand: ArticulatedHand | None = None
        self.shaper: HandShaper | None = None
        self.pose = NEUTRAL_POSE
        if has_articulated_hand(model):
            if data is None:
                raise RobinPilError(
                    "the articulated person's hand poses are joint positions: "
                    "GestureDisplay(model, data) needs the scene's data"
                )
            self.hand = ArticulatedHand(model, data)
            self.show(NEUTRAL_POSE)
            return
        self._geoms: dict[str, np.ndarray] = {pose: np.zeros(0, int) for pose in POSES}
        groups: dict[str, list[int]] = {pose: [] for pose in POSES}
        for geom_id in range(model.ngeom):
            name = mujoco.mj_id2name(model, mujoco.mjtObj.mjOBJ_GEOM, geom_id) or ""
            if not name.startswith(HUMAN_VIS_PREFIX):
                continue
            pose = next((p for p in POSES if name.startswith(names.human_vis_geom(p, ""))), None)
            if pose is None:
                raise RobinPilError(
                    f"geom {name!r} names no hand pose; expected {HUMAN_VIS_PREFIX}<pose>_<part> "
                    f"with pose one of {', '.join(POSES)}"
                )
            if model.geom_contype[geom_id] or model.geom_conaffinity[geom_id]:
                raise RobinPilError(
                    f"hand pose geom {name!r} collides; make it visual-only "
                    "(contype=0 conaffinity=0)"
                )
            groups[pose].append(geom_id)
        missing = [p for p in POSES if p != NEUTRAL_POSE and not groups[p]]
        if missing:
            raise RobinPilError(
                f"the model has no {HUMAN_VIS_PREFIX}<pose>_* geoms for poses {missing}; "
                f"every pose but {NEUTRAL_POSE} ({', '.join(POSES)}) needs at least one"
            )
        self._geoms = {pose: np.array(ids, dtype=int) for pose, ids in groups.items()}
        every = np.concatenate(list(self._geoms.values()))
        loaded = model.geom_rgba[every, 3].copy()
        self._visible_alpha = dict(
            zip(every.tolist(), np.where(loaded > 0, loaded, 1.0), strict=True)
        )
        self.shaper = HandShaper(model) if HandShaper.fits(model) else None
        if self.shaper is not None:
            self.shaper.shape_all()
        self.show(NEUTRAL_POSE)

    def geoms(self, pose: str) -> tuple[int, ...]:
        """Geom ids of ``pose`` (the articulated hand: every geom of the hand)."""
        if self.hand is not None:
            pose_for(pose)
            return tuple(self.hand.hand_geoms.tolist())
        return tuple(self._geoms[pose_for(pose)].tolist())

    def update(self, now: float) -> None:
        """Play out a blend into a pose at simulated time ``now`` (articulated hand only)."""
        if self.hand is not None:
            self.hand.update(now)

    def show(
        self,
        sign: Gesture | Feedback | str | None,
        performance: Performance | None = None,
        blend: float = 0.0,
    ) -> str:
        """Show the pose for ``sign`` (see :func:`pose_for`), hide the others; return the pose.

        ``performance`` (scene models only) shapes this showing of the pose; without it the
        pose has its plain shape. ``blend`` (articulated hand): seconds to move into it.
        """
        pose = pose_for(sign)
        if self.hand is not None:
            self.hand.show(pose, performance, blend)
            self.pose = pose
            return pose
        if self.shaper is not None:
            self.shaper.shape(pose, performance)
        for other, ids in self._geoms.items():
            if other != pose:
                self._model.geom_rgba[ids, 3] = 0.0
        for geom_id in self._geoms[pose]:
            self._model.geom_rgba[geom_id, 3] = self._visible_alpha[int(geom_id)]
        self.pose = pose
        return pose
