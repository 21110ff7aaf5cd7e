"""How the simulated person watches Robin act: recognise from the motion, react, thumb down.

:class:`PhysicalWatcher` is the :class:`pil.task.world.Watcher` of a physical episode. It is
made for one action with the person's intent and one reaction time, and it only looks at what
a person can see: where the robot's hand is and where it heads, whether the fingers close or
open, whether a leg is in the hand. It is never told which action the robot runs. At every
control tick it checks whether the motion so far contradicts what the person wants:

* wanted close or open: the arm moves (more than :data:`ARM_SEEN`); fingers that do the
  wrong thing show in the result (a close that catches nothing, an open that keeps the leg);
* wanted object, location or human: the fingertips move (a fingertip joint turns more than
  :data:`FINGERS_SEEN`; carrying a leg makes them jiggle by at most 0.05 rad, measured;
  a closing hand or the eased fingertips of a release turn them 0.2 rad and more; an empty
  hand opening on its way to the leg wanted is not a mismatch), or the hand
  heads more than
  :data:`HEADING_SEEN` away from the wanted place once it has moved :data:`ARM_SEEN`
  sideways, or it comes down away from that place. For "human" and "location" with a leg in
  the hand the person follows the leg's centre, not the hand: the robot brings the leg there,
  and a leg held off its centre (7 cm, measured after a close caught a rolled leg) puts the
  hand that far beside the palm or spot.

From the tick it recognises an unwanted action, the person needs their reaction time; then
the thumb goes down and the robot stops. An action that ran to its end is judged by its
result (the leg in the hand, the hand or the carried leg at the place and height meant); a
wrong result gets
the thumb down one reaction time later, and the robot takes the action back.
"""

from __future__ import annotations

import numpy as np

from pil.task.world import Intent
from pil.types import Action, Feedback
from robin_sim.model import names
from robin_sim.model import robot_spec as spec
from robin_sim.person.gestures import GestureDisplay
from robin_sim.robot.targets import target_point
from robin_sim.robot.world import PhysicalWorld

ARM_SEEN = 0.03  # m the hand moves before the person takes it as a motion
FINGERS_SEEN = 0.12  # rad a fingertip joint turns before the person sees it move (7 degrees)
HEADING_SEEN = np.deg2rad(40.0)  # rad between the hand's heading and the wanted place
DESCENT_SEEN = 0.03  # m the hand comes down from its highest point before it is seen
PLACE_RADIUS = 0.05  # m, hand to the wanted place (horizontally) for a result to count
LOW_ABOVE = 0.05  # m: a hand lowered to a surface holds the leg at most this high above it
FINGER_ACTIONS = (Action.CLOSE, Action.OPEN)


class PhysicalWatcher:
    """The person's eyes on one action (see the module doc)."""

    def __init__(
        self, world: PhysicalWorld, display: GestureDisplay, intent: Intent, reaction: float
    ) -> None:
        self.world, self.display, self.intent, self.reaction = world, display, intent, reaction
        hand = world.sim.hand
        self._tips = hand.joint_qadr[hand.distal]  # qpos addresses of the two fingertips
        self._site = world.data.site(names.grasp_site(names.ACTIVE_SIDE)).xpos  # a live view
        self.start_fingers = self._fingertips()
        self.start_held = world.held_leg()
        # the leg in the hand is what "human" and "location" bring to the place
        carries = intent.action in (Action.HUMAN, Action.LOCATION)
        self._carried = self.start_held if carries else None
        self.start = self._watched()
        self.highest = float(self.start[2])
        self.goal = self._goal()  # where the hand should go (xy, z of the surface), if a move
        self.recognized_at: float | None = None  # when the person saw it was unwanted
        self.stopped_at: float | None = None  # when the thumb went down
        self.why = ""

    # --- the Watcher protocol ------------------------------------------------------------------
    def stop_now(self, shown: Action | None) -> bool:
        """True from one reaction time after an unwanted motion was recognised."""
        now = self.world.time
        if self.recognized_at is None:
            why = self._mismatch()
            if why:
                self.recognized_at, self.why = now, why
        return self._thumb_down(now)

    def result_window(self, shown: Action | None, *, undone: bool = False) -> float:
        """0 when the result is what the person wants, else the time until the thumb down;
        0 for an action the robot undid by itself (the person judges it after, in
        :meth:`pil.task.person.ScriptedPerson.judge`)."""
        if undone:
            return 0.0
        now = self.world.time
        if self.recognized_at is None:
            why = self._wrong_result()
            if not why:
                return 0.0
            self.recognized_at, self.why = now, why
        due = self.recognized_at + self.reaction
        return max(0.0, due - now) + 2 * self.world.sim.control_dt

    def settled(self) -> bool:
        """False: the scripted person only opens a window for a result they will reject."""
        return False

    # --- perception ----------------------------------------------------------------------------
    def _thumb_down(self, now: float) -> bool:
        if self.recognized_at is None or now < self.recognized_at + self.reaction - 1e-9:
            return False
        if self.stopped_at is None:
            self.stopped_at = now
            self.display.show(Feedback.NOT_OK)
        return True

    def _fingertips(self) -> np.ndarray:
        return self.world.data.qpos[self._tips]

    def _watched(self) -> np.ndarray:
        """What the person follows to the place: the centre of the leg the hand carries (the
        robot brings it there, wherever the fingers hold it), else the hand's grasp site."""
        if self._carried is not None:
            return self.world.legs.position(self._carried)
        return self._site.copy()

    def _goal(self) -> np.ndarray | None:
        action, target, world = self.intent.action, self.intent.target, self.world
        if action is Action.HUMAN:
            palm = world.human.palm_centre() if world.palm_is_out() else world.layout.handover
            return np.asarray(palm, float)
        if action in (Action.OBJECT, Action.LOCATION) and target is not None:
            return target_point(target, world.layout, world.legs.position, world.legs.nearest)
        return None

    def _mismatch(self) -> str:
        """Why the motion so far is not the wanted action ("" while it may still be)."""
        here = self._watched()
        moved = here - self.start
        sideways = float(np.linalg.norm(moved[:2]))
        turned = float(np.abs(self._fingertips() - self.start_fingers).max())
        self.highest = max(self.highest, float(here[2]))
        wanted = self.intent.action
        if wanted in FINGER_ACTIONS:
            lowered = self.start[2] - here[2] > ARM_SEEN
            rose = here[2] - self.start[2] > ARM_SEEN and wanted is Action.CLOSE
            return "the arm moves" if sideways > ARM_SEEN or lowered or rose else ""
        if turned >= FINGERS_SEEN and not self._opens_to_grasp():
            return "the fingers move"
        if self.goal is None:
            return ""
        to_goal = self.goal[:2] - self.start[:2]
        if sideways > ARM_SEEN:
            far = float(np.linalg.norm(to_goal))
            cos = float(np.dot(moved[:2], to_goal)) / max(sideways * far, 1e-9)
            if far < ARM_SEEN or np.arccos(np.clip(cos, -1.0, 1.0)) > HEADING_SEEN:
                return "the hand heads elsewhere"
        away = float(np.linalg.norm(here[:2] - self.goal[:2])) > PLACE_RADIUS
        if self.highest - here[2] > DESCENT_SEEN and away:
            return "the hand comes down elsewhere"
        return ""

    def _opens_to_grasp(self) -> bool:
        """An empty hand opening on its way to a leg the person wants taken: what a person
        expects of a grasp (the robot opens a hand left closed after a drop)."""
        if self.intent.action is not Action.OBJECT or self.start_held is not None:
            return False
        hand = self.world.sim.hand
        wide = hand.targets.open[hand.distal]
        return bool(np.all(np.abs(self._fingertips() - wide) < np.abs(self.start_fingers - wide)))

    def _wrong_result(self) -> str:
        """Why the finished action's result is not the wanted one ("" when it is)."""
        world, wanted = self.world, self.intent.action
        here = self._watched()
        if wanted is Action.CLOSE:
            if float(np.linalg.norm(here - self.start)) > ARM_SEEN:
                return "the hand is not where it was"
            return "" if world.held_leg() is not None else "no leg in the hand"
        if wanted is Action.OPEN:
            return "" if world.held_leg() is None else "the leg is still in the hand"
        if world.held_leg() != self.start_held:
            return "the hand took or let go of a leg"
        if self.goal is None:
            return ""
        if float(np.linalg.norm(here[:2] - self.goal[:2])) > PLACE_RADIUS:
            return "the hand is not at the place meant"
        if wanted is Action.OBJECT:
            low = abs(here[2] - spec.GRASP_HEIGHT) <= LOW_ABOVE
        elif wanted is Action.LOCATION:
            low = here[2] - spec.GRASP_HEIGHT <= LOW_ABOVE
        else:
            low = here[2] - self.goal[2] <= LOW_ABOVE + 2 * spec.LEG_RADIUS
        return "" if low else "the hand stays too high"
