"""The simulated person's body in a :class:`~robin_sim.robot.world.PhysicalWorld`.

:class:`PhysicalBody` is the :class:`pil.task.person.PersonBody` of a physical episode: the
scripted person (:class:`pil.task.person.ScriptedPerson`) decides, the body makes it happen in
the scene, in the order a person does it:

* :meth:`~PhysicalBody.perform` a gesture: show its hand shape; pointing moves the hand above
  the meant leg or spot, holds it there, then draws the hand back out of the robot's way and
  raises it into Robin's view (where the robot reads it);
  "give me" holds the palm out at the handover point (a little off it each time: a person never
  holds the hand at exactly the same place), but never over a leg the robot holds lower, under
  that place (after a drop there): the leg, lifted, caught on the palm and was torn from the
  fingers; the palm is shown drawn back instead, the robot brings the leg to the handover
  point, and "release" brings the palm back under a leg that the robot holds where the palm
  was (or would have been).
* :meth:`~PhysicalBody.watch` the robot act (:mod:`robin_sim.person.watcher`): recognise an
  unwanted action from the motion and stop it with a thumb down one reaction time later.
* :meth:`~PhysicalBody.show_feedback`: thumb up or down (nothing for silence), held; after an
  approval a leg that lies on the palm is carried to the bin beside the table. A thumb at the
  held-out palm is first drawn back and raised into Robin's view, as the pointing hand is:
  there Robin's own hand and the leg it holds over the palm, or a leg lying on the palm, hid
  it from Robin's eyes (a leg on the palm is carried along, slowly, and stays on it); an
  empty hand also moves aside, clear of Robin's arm reaching to the palm.
* :meth:`~PhysicalBody.recover` a leg the robot dropped: where it lies on the table within the
  robot's reach, clear of the other legs, the robot can pick it up again; anywhere else (the
  floor, the palm, on or against another leg) the person puts it back on the table at its
  place: a person intervention, the one scene change besides laying out a new table. So is
  :meth:`~PhysicalBody.put_back_off_table`: a leg about to be pointed at that lies off the
  table top (knocked to the floor by a motion) is put back at its place first.

The body sees the world as a person would (where the legs and the robot's hand are); it is never
told what the robot will do next. Only the mocap hand and visual-only geoms move.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from pil.task.world import Intent, Target
from pil.types import Feedback, Gesture
from robin_sim.control.human_hand import CARRY_SPEED, HAND_SPEED
from robin_sim.figure.hand_poses import DEFAULT_SKIN, Performance
from robin_sim.model import names
from robin_sim.model import robot_spec as spec
from robin_sim.model.robot_spec import (  # read at each pointing
    PERSON_CLEAR_X,
    POINT_RAISE,
    THUMB_ASIDE,
)
from robin_sim.person.gestures import GestureDisplay
from robin_sim.person.watcher import PhysicalWatcher
from robin_sim.robot.planning import HANDOVER_TOLERANCE, PALM_OUT_RADIUS
from robin_sim.robot.targets import axis_points, reaches_into, target_point
from robin_sim.robot.world import PhysicalWorld

GESTURE_HOLD = 0.5  # s the person holds a gesture before the robot reacts
FEEDBACK_HOLD = 0.4  # s the thumb stays up or down
# m, largest offset (per axis) of the held-out palm from the handover point: within what the
# robot counts as a palm held out there.
PALM_JITTER = PALM_OUT_RADIUS / 2
SETTLE = 0.1  # s after a hand motion before the next
# m, Robin's grasp site to the held-out palm centre within which its hand (and a leg it holds
# there) hides a thumb shown at the palm from its eyes (holding a leg over the palm: 3.5 cm)
HIDES_PALM = 0.15
FORM_TIME = (0.25, 0.45)  # s the hand takes to form a pose (drawn per sign)
SIGN_STREAM = 29  # second seed word of the random stream of how signs are made


@dataclass(frozen=True)
class Tempo:
    """How fast the body makes its signs: the free hand's peak speed (m/s), how long a
    gesture and a thumb are held (s), the pause after a hand motion (s), whether the robot
    may start while the pointing hand draws back (``overlap``), and whether a thumb at the
    held-out palm is first drawn back into Robin's view (``thumb_in_view``: the robot reads
    thumbs with its eyes)."""

    hand_speed: float = HAND_SPEED
    hold: float = GESTURE_HOLD
    feedback_hold: float = FEEDBACK_HOLD
    settle: float = SETTLE
    overlap: bool = False
    thumb_in_view: bool = True


SCRIPTED = Tempo()  # the scripted person of the study and the episodes
# A live participant has made the gesture already (a click, a key, their own hand): the body
# only shows it, quickly, so that the robot starts within a second of the input. At 2 m/s the
# hand reaches a leg from its rest in 0.6 s; it draws back while the robot starts lifting,
# which keeps the two hands apart (the robot comes down on the leg 1.5 s later or more). A
# live thumb is a click, not read by Robin's eyes: the palm stays out under a held leg.
LIVE = Tempo(
    hand_speed=2.0, hold=0.1, feedback_hold=0.2, settle=0.02, overlap=True, thumb_in_view=False
)


class PhysicalBody:
    """The person's hand in ``world``: gestures, thumbs, the palm, the bin (see module doc).

    ``seed`` seeds where the palm is held out, so the same seed gives the same trajectory;
    ``tempo`` how fast the signs are made (:data:`SCRIPTED`, or :data:`LIVE`).
    """

    def __init__(self, world: PhysicalWorld, seed: int = 0, tempo: Tempo = SCRIPTED) -> None:
        self.world = world
        self.tempo = tempo
        self.hand = world.human
        self.display = GestureDisplay(world.model, world.data)
        if world.posture is not None:  # the hand's blends into poses play out at each tick
            world.posture.hand = self.display.hand
        self._rng = np.random.default_rng(seed)
        # how each sign is made (finger variation, wrist turn, timing): its own stream, so the
        # palm's places stay those of the seed
        self._signs = np.random.default_rng([seed, SIGN_STREAM])
        self.palm_goal = np.array(world.layout.handover, float)  # where the palm was held out
        self.last_watcher: PhysicalWatcher | None = None
        self.performed_at: list[float] = []  # sim time each performance of a gesture began

    # --- the PersonBody protocol ---------------------------------------------------------------
    def start_table(self, table: int) -> None:
        """The hand goes back to rest before a new table's legs are laid out."""
        self._move(self.hand.rest(self.world.time))

    def perform(self, gesture: Gesture, target: Target | None) -> None:
        """Show ``gesture`` (see the module doc) and hold it so that it can be seen."""
        self.performed_at.append(self.world.time)
        self._show(gesture)
        if gesture is not Gesture.POINTING or target is None:
            self.world.head.attend_to("person hand")  # the robot watches the gesturing hand
        tempo, now, speed = self.tempo, self.world.time, self.tempo.hand_speed
        if gesture is Gesture.POINTING and target is not None:
            self.point_at(target)
            self.world.run(tempo.hold)
            back = self.hand.withdraw(PERSON_CLEAR_X, self.world.time, POINT_RAISE, speed)
            if not tempo.overlap:
                self._move(back)
            return
        if gesture in (Gesture.GIVE_ME, Gesture.RELEASE) and self.leg_held_over_palm_place():
            self._move(self.hand.slide_under(self.palm_goal, now, speed))
        elif gesture is Gesture.GIVE_ME and not self.world.palm_is_out():
            jitter = self._rng.uniform(-PALM_JITTER, PALM_JITTER, size=2)
            self.palm_goal = np.array(self.world.layout.handover) + np.array([*jitter, 0.0])
            if self.leg_held_below(self.palm_goal):  # shown drawn back, clear of the leg
                self._move(self.hand.withdraw(PERSON_CLEAR_X, now, POINT_RAISE, speed))
            else:
                self._move(self.hand.hold_out_palm(self.palm_goal, now, speed))
        self.world.run(tempo.hold)

    def watch(self, intent: Intent, reaction: float) -> PhysicalWatcher:
        """Eyes on the robot's next action, meaning ``intent``, reacting in ``reaction`` s."""
        self.last_watcher = PhysicalWatcher(self.world, self.display, intent, reaction)
        return self.last_watcher

    def show_feedback(self, feedback: Feedback) -> None:
        """Show the thumb and hold it (the robot reads it meanwhile).

        A thumb at the held-out palm that Robin's hand is near, or with a leg lying on the
        palm, is drawn back and raised into Robin's view first (:meth:`thumb_hidden_at_palm`),
        as the pointing hand is, and moved :data:`THUMB_ASIDE` clear of Robin's arm; a leg on
        the palm is carried straight back and up at :data:`CARRY_SPEED` (Robin's hand is home
        then).
        A thumb that already went down (the person stopped a motion or rejected its result,
        which the robot then took back) stays where it is.

        A hand with a leg lying on it cannot make a thumb sign (its fingers keep out of the leg,
        :mod:`robin_sim.figure.hand_fit`; Robin read that hand as a thumb down): a person who
        approves puts the leg into the bin first (:meth:`after_feedback`'s carry) and shows
        the thumb with the hand free, back at rest. Robin learns the verdict from the thumb
        only (taking the leg is what the person does with any leg put on the palm)."""
        stopped = self.last_watcher is not None and self.last_watcher.stopped_at is not None
        drawn = self.tempo.thumb_in_view and not stopped and feedback is not Feedback.NONE
        if drawn and feedback.approves and self.leg_on_palm() is not None:
            self._carry_to_bin()
        elif drawn and self.thumb_hidden_at_palm():
            carried = self.leg_on_palm() is not None  # moved along the leg only: it never rolls
            speed, aside = (CARRY_SPEED, 0.0) if carried else (self.tempo.hand_speed, THUMB_ASIDE)
            self._move(
                self.hand.withdraw(PERSON_CLEAR_X, self.world.time, POINT_RAISE, speed, aside)
            )
        self._show(feedback)
        self.world.run(self.tempo.feedback_hold)

    def thumb_hidden_at_palm(self) -> bool:
        """The palm is held out and Robin's hand is near it (within :data:`HIDES_PALM`), or a
        leg lies on it: there Robin's eyes see its own hand and the legs, not the thumb."""
        if not self.world.palm_is_out():
            return False
        site = self.world.sim.site_pose().translation()
        near = float(np.linalg.norm(site - self.hand.palm_centre())) <= HIDES_PALM
        return near or self.leg_on_palm() is not None

    def after_feedback(self, feedback: Feedback) -> None:
        """After an approval, carry a leg that lies on the palm to the bin."""
        if feedback.approves and self.leg_on_palm() is not None:
            self._carry_to_bin()

    def _carry_to_bin(self) -> None:
        """Carry the leg lying on the palm to the bin, tip it in, and bring the hand to rest."""
        bin_centre = np.array([*self.world.layout.bin, 0.0])
        self._move(self.hand.take_away(bin_centre, self.world.time), settle=0.2)

    def put_back_strays(self, delivered: set[int]) -> int:
        """Put back at its place every leg not ``delivered`` nor held that lies where Robin
        cannot reach it (a live participant's wrong moves let stand can push one there, and
        the next pointing at it would fail); the person interventions made."""
        world = self.world
        strays = [
            leg
            for leg in range(world.legs.count)
            if leg not in delivered and leg != world.held_leg() and world.legs.out_of_reach(leg)
        ]
        return sum(self.recover(leg) for leg in strays)

    def recover(self, leg: int) -> bool:
        """Leave a dropped leg for the robot if it can grasp it where it lies; else put it back
        on the table at its place (True: a person intervention)."""
        if self.world.legs.graspable(leg):
            return False
        self._put_back(leg)
        return True

    def put_back_off_table(self, leg: int) -> bool:
        """Before pointing at ``leg``: put it back at its place when it lies off the table top
        (e.g. knocked to the floor: the robot reaches for a leg where it lies on the table, and
        else at its layout place, where it is not) and the robot does not hold it (True: a
        person intervention)."""
        world = self.world
        if world.held_leg() == leg or world.legs.on_table(leg):
            return False
        self._put_back(leg)
        return True

    def _put_back(self, leg: int) -> None:
        self._move(self.hand.rest(self.world.time))
        self.world.put_leg_back(leg)

    # --- what the person does and sees ---------------------------------------------------------
    def point_at(self, target: Target) -> float:
        """Move the hand to point at ``target``; returns the time it took.

        A palm held out for a handover draws back and down first, clear of a held leg."""
        world = self.world
        where = target_point(target, world.layout, world.legs.position, world.legs.nearest)
        world.head.attend(where, "pointed")  # the robot looks where the person points
        speed = self.tempo.hand_speed
        return self._move(self.hand.point_at(where, world.time, world.palm_is_out(), speed))

    def rest(self) -> float:
        """The hand goes back to rest; returns the time it took."""
        return self._move(self.hand.rest(self.world.time))

    def leg_on_palm(self) -> int | None:
        """A leg that lies on the palm, free of the robot's hand (seen from positions)."""
        palm = self.hand.palm_centre()
        held = self.world.held_leg()
        for leg in range(self.world.legs.count):
            centre = self.world.legs.position(leg)
            near = np.linalg.norm(centre[:2] - palm[:2]) <= HANDOVER_TOLERANCE
            if leg != held and near and 0.0 < centre[2] - palm[2] <= 2 * spec.LEG_RADIUS:
                return leg
        return None

    def leg_held_over_palm_place(self) -> bool:
        """The robot holds a leg above where the palm was held out, and the palm is away."""
        held = self.world.held_leg()
        if held is None or self.world.palm_is_out():
            return False
        centre = self.world.legs.position(held)
        above = centre[2] > self.palm_goal[2]  # a leg held lower has no palm slid under it
        return bool(above and np.linalg.norm(centre[:2] - self.palm_goal[:2]) <= HANDOVER_TOLERANCE)

    def leg_held_below(self, palm_centre: np.ndarray) -> bool:
        """The robot holds a leg lower than a palm held out at ``palm_centre`` and under it:
        the leg's axis reaches into the palm box's footprint (:func:`reaches_into`). Lifted
        from there, the leg would catch on the palm (which collides with legs) and be torn
        from Robin's fingers."""
        held = self.world.held_leg()
        if held is None:
            return False
        centre = self.world.legs.position(held)
        if centre[2] >= palm_centre[2]:
            return False
        half = self.world.model.geom(names.HUMAN_PALM_GEOM).size[:2]  # the hand unturned
        points = axis_points(centre, self.world.legs.axis(held))
        return reaches_into(points, palm_centre, np.array([1.0, 0.0]), (half[0], half[1]))

    def _show(self, sign: Gesture | Feedback) -> None:
        """Move the hand into ``sign``'s pose: a seeded performance (the fingers, the wrist's
        turn) over a seeded time (:data:`FORM_TIME`); the skin stays the person's."""
        performance = Performance.draw(self._signs, skin_range=(DEFAULT_SKIN, DEFAULT_SKIN))
        self.display.show(sign, performance, blend=float(self._signs.uniform(*FORM_TIME)))

    def _move(self, duration: float, settle: float | None = None) -> float:
        """Let a started hand motion play out (physics runs); returns the time it took."""
        if duration <= 0.0:
            return 0.0
        settle = self.tempo.settle if settle is None else settle
        self.world.run(duration + settle)
        return duration + settle
