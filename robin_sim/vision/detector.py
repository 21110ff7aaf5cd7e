"""Robin reads gestures and thumbs with its eye cameras: :class:`VisionDetector`.

It has the step loop's detector interface (``detect(true_gesture) -> Gesture | None``, ``rate``
and the ``detected`` / ``discarded`` / ``misread`` counts) plus :meth:`read_feedback` for the
person's thumb. Each reading: the head looks at the person's palm (position actuators, the
simulator runs until the head is there), both eyes render, the hand is found and classified
(:mod:`robin_sim.vision.reader`). In context the robot only considers what it expects: one of
the four instruction gestures while waiting for an instruction, a thumb while waiting for
feedback; "no gesture" or a confidence below the model's threshold discards the reading. A
discarded thumb reads as no feedback (which the learner counts as OK); a thumb read the wrong
way round reaches the learner as the wrong feedback. Only pixels decide: the true gesture is
used to *show* the pose (when the detector is given the display) and to keep the record.

Conditions replace the detection rate: ``lighting`` (scale of the scene's light, 1 = as
built) and ``camera_noise`` (sd of pixel noise, 8-bit units). The person's looks: ``skin``
(one tone for every performance; None: each draws one) and ``pose_jitter`` (how much their
poses vary). With ``adapt`` the gesture model follows the person from the robot's feedback
(:mod:`robin_sim.vision.adapting`; :meth:`VisionDetector.verdict`).
"""

from __future__ import annotations

from collections import Counter
from collections.abc import Mapping
from dataclasses import dataclass

import mujoco
import numpy as np

from pil.errors import InvalidChoiceError, RobinPilError
from pil.types import SIGN_OF, Feedback, Gesture
from robin_sim.control.gaze import look_at
from robin_sim.control.simulator import Simulator
from robin_sim.figure.hand_poses import Performance
from robin_sim.model import names
from robin_sim.person.gestures import GestureDisplay, pose_for
from robin_sim.vision.adapting import AdaptedModel, FeedbackLabels
from robin_sim.vision.classifier import NO_GESTURE, GestureModel, ModelFileError, load_shipped
from robin_sim.vision.condition_params import CONDITION_PARAMS
from robin_sim.vision.eyes import EyeCameras, EyeCondition
from robin_sim.vision.picture import reading_picture
from robin_sim.vision.reader import EyeReading, read_views, see
from robin_sim.vision.train import DISCARDED, FEEDBACK_CLASSES, GESTURE_CLASSES

# the camera conditions' defaults, by name (a run's --param values replace them)
VISION_DEFAULTS: dict[str, float] = {name: spec.default for name, spec in CONDITION_PARAMS.items()}
GESTURE_OF = {pose_for(g): g for g in Gesture}  # pose name -> gesture
FEEDBACK_OF = {SIGN_OF[thumb]: thumb for thumb in (Feedback.OK, Feedback.NOT_OK)}
NO_HAND = "no hand"  # a discarded reading in which neither eye found a hand
ASK_AGAIN = 2  # with discarded_thumb="ask": readings asked for after a discarded thumb
READING_SHOWN = 1.0  # s (simulated) the video's eye inset shows a reading after it was made


@dataclass(frozen=True, slots=True)
class VisionRecord:
    """One reading: what was shown, what was read (class or "discarded"), and how sure."""

    kind: str  # "gesture" or "feedback"
    shown: str  # pose name shown
    read: str  # pose name read, or "discarded"
    label: str  # the best class in context before the threshold
    confidence: float
    boxes: tuple[tuple[int, int, int, int] | None, ...]  # hand box per eye (pixels)
    sim_time: float
    shipped: str | None = None  # adapting: what the shipped model reads in the same views

    @property
    def discarded(self) -> bool:
        """Whether the reading was discarded (no hand found included)."""
        return self.read == DISCARDED

    @property
    def no_hand(self) -> bool:
        """Whether neither eye found a hand (such a reading is always discarded)."""
        return all(box is None for box in self.boxes)

    @property
    def outcome(self) -> str:
        """What the reading came to: the pose read, "discarded" (a hand found but the reading
        unsure or "no gesture") or "no hand" (neither eye found one)."""
        return NO_HAND if self.no_hand else self.read

    def as_dict(self) -> dict[str, object]:
        """Plain values for the episode log."""
        return {
            "kind": self.kind,
            "shown": self.shown,
            "read": self.read,
            "label": self.label,
            "confidence": round(self.confidence, 4),
            "boxes": [None if b is None else list(map(int, b)) for b in self.boxes],
            "sim_time": round(self.sim_time, 4),
            **({} if self.shipped is None else {"shipped": self.shipped}),
        }


def _decide(reading: EyeReading, classes: tuple[str, ...]) -> tuple[str, str, float]:
    """(what is read: a class or :data:`DISCARDED`, the best class in context, its confidence)."""
    label, confidence = reading.among(classes)
    kept = label != NO_GESTURE and confidence >= reading.threshold
    return (label if kept else DISCARDED), label, confidence


class VisionDetector:
    """Reads the person's hand with Robin's eye cameras in ``sim``'s model and data."""

    def __init__(
        self,
        sim: Simulator,
        *,
        display: GestureDisplay | None = None,
        lighting: float = 1.0,
        camera_noise: float = 0.0,
        seed: int = 0,
        gesture_model: GestureModel | None = None,
        vary_performance: bool = True,
        skin: float | None = None,
        pose_jitter: float = 1.0,
        adapt: bool = False,
        discarded_thumb: str = "approve",
    ) -> None:
        self.sim = sim
        self.discarded_thumb = discarded_thumb  # checked where it enters (condition_params)
        self.thumbs_asked_again = 0
        self.condition = EyeCondition(lighting=lighting, camera_noise=camera_noise)
        self.display = display
        self.gesture_model = gesture_model or load_shipped()
        problem = self.gesture_model.problem()  # NaN weights would read every gesture wrong
        if problem:
            raise ModelFileError(f"gesture model not usable: {problem}")
        self.eyes = EyeCameras(sim.model)
        self.rng = np.random.default_rng(seed)
        self.vary_performance = vary_performance
        self.skin, self.pose_jitter = skin, pose_jitter
        self.adapted = AdaptedModel(self.gesture_model) if adapt else None
        self.labels = None if self.adapted is None else FeedbackLabels(self.adapted)
        self.records: list[VisionRecord] = []
        self.detected = self.discarded = self.misread = 0
        self.last_reading: EyeReading | None = None
        self.last_view: np.ndarray | None = None

    @classmethod
    def from_params(
        cls,
        sim: Simulator,
        params: Mapping[str, object],
        *,
        display: GestureDisplay | None = None,
        seed: int = 0,
    ) -> VisionDetector:
        """A detector from ``--param`` style values (text or numbers) of :data:`VISION_DEFAULTS`;
        an unknown name or a bad value raises one :class:`RobinPilError` naming the choices."""
        values = dict(VISION_DEFAULTS)
        for name, value in params.items():
            if name not in VISION_DEFAULTS:
                raise InvalidChoiceError("vision parameter", name, VISION_DEFAULTS)
            try:
                if not isinstance(value, str | int | float):
                    raise TypeError(name)
                values[name] = float(value)
            except (TypeError, ValueError):
                raise RobinPilError(
                    f"vision parameter {name!r} must be a number, got {value!r}"
                ) from None
        return cls(
            sim,
            display=display,
            seed=seed,
            lighting=values["lighting"],
            camera_noise=values["camera_noise"],
        )

    @property
    def rate(self) -> str:
        """What sets the detection rate here (the step loop quotes it in messages)."""
        c = self.condition
        return f"vision, lighting {c.lighting:g}, noise {c.camera_noise:g}"

    # --- reading -------------------------------------------------------------------------------
    def look(self) -> EyeReading:
        """Look at the person's palm now and read the hand (all seven classes)."""
        data = self.sim.data
        target = data.site(names.HUMAN_PALM_SITE).xpos.copy()
        look_at(self.sim, target)
        target = data.site(names.HUMAN_PALM_SITE).xpos.copy()
        self.sim.prepare_view()  # the person's arm and body follow the hand before the eyes look
        mujoco.mj_kinematics(self.sim.model, data)
        views, depths = see(self.eyes, data, target, self.condition, self.rng)
        reading = read_views(self.adapted or self.gesture_model, views, depths)
        self.last_reading, self.last_view = reading, views[0].rgb
        return reading

    def inset(self, size: tuple[int, int] | None = None) -> np.ndarray | None:
        """The left eye's last view with the hand's box and the reading, at ``size`` (width,
        height; default the eye's), for a video inset (:mod:`robin_sim.vision.picture`)."""
        if self.last_view is None or not self.records:
            return None
        record = self.records[-1]
        box = record.boxes[0] if record.boxes else None
        text = f"{record.read} {record.confidence:.2f}"
        return reading_picture(self.last_view, box, text, record.discarded, size)

    def inset_at(self, time: float, size: tuple[int, int]) -> np.ndarray | None:
        """:meth:`inset` while the last reading is at most :data:`READING_SHOWN` s old at
        simulated ``time``, else None (the video's eye inset then shows the live eye)."""
        if not self.records or not 0.0 <= time - self.records[-1].sim_time <= READING_SHOWN:
            return None
        return self.inset(size)

    def _show(self, pose: str) -> None:
        if self.display is not None:
            performance = None
            if self.vary_performance:
                skin = {} if self.skin is None else {"skin_range": (self.skin, self.skin)}
                performance = Performance.draw(self.rng, jitter=self.pose_jitter, **skin)
            self.display.show(pose, performance)

    def _read(self, kind: str, pose: str, classes: tuple[str, ...]) -> VisionRecord:
        self._show(pose)
        reading = self.look()
        read, label, confidence = _decide(reading, classes)
        shipped = None
        if self.adapted is not None:  # the shipped model on the very same views, for the record
            base, rows = self.gesture_model, reading.features
            # no hand: "no gesture" at 1 either way
            p = reading.probabilities if rows is None else base.probabilities(rows).mean(axis=0)
            shipped = _decide(EyeReading(p, reading.boxes, base.threshold), classes)[0]
        record = VisionRecord(
            kind, pose, read, label, confidence, reading.boxes, self.sim.time, shipped
        )
        self.records.append(record)
        return record

    def detect(self, gesture: Gesture) -> Gesture | None:
        """What Robin reads while the person shows ``gesture`` (None: discarded)."""
        record = self._read("gesture", pose_for(gesture), GESTURE_CLASSES)
        if self.labels is not None and self.last_reading is not None:
            self.labels.read(self.last_reading.features)
        if record.discarded:
            self.discarded += 1
            return None
        read = GESTURE_OF[record.read]
        if read is gesture:
            self.detected += 1
        else:
            self.misread += 1
        return read

    def read_feedback(self, feedback: Feedback) -> Feedback:
        """The feedback Robin perceives while the person gives ``feedback``.

        A thumb shows its pose; no feedback shows the neutral hand. A discarded reading is no
        feedback (:attr:`Feedback.NONE`, which counts as OK), or with ``discarded_thumb="ask"``
        the robot asks for the thumb again: up to :data:`ASK_AGAIN` more readings, each of a
        fresh performance of the same feedback (the robot cannot tell a discarded thumb from
        silence, so silence is asked again too; it stays silence).
        """
        record = self._read("feedback", pose_for(feedback), FEEDBACK_CLASSES)
        asks = 0
        while record.discarded and self.discarded_thumb == "ask" and asks < ASK_AGAIN:
            asks += 1
            self.thumbs_asked_again += 1
            record = self._read("feedback", pose_for(feedback), FEEDBACK_CLASSES)
        return Feedback.NONE if record.discarded else FEEDBACK_OF[record.read]

    def verdict(self, meant: Gesture | None, approved: bool) -> None:
        """The robot's verdict on its last action (:class:`pil.task.detector.LearnsFromFeedback`):
        with ``adapt``, an approval labels this instruction's readings with the gesture the
        action means (none without that evidence)."""
        if self.labels is not None:
            self.labels.verdict(None if meant is None else pose_for(meant), approved)

    # --- the summary ---------------------------------------------------------------------------
    def summary(self) -> dict[str, object]:
        """The episode summary's ``vision`` block.

        Each reading has one outcome: read right, ``misread``, ``discarded`` (a hand was found
        but the reading was unsure or "no gesture") or ``no_hand`` (neither eye found a hand);
        per kind the four add up to the readings. ``confusion`` has the same columns.
        """
        gestures = [r for r in self.records if r.kind == "gesture"]
        thumbs = [r for r in self.records if r.kind == "feedback" and r.shown in FEEDBACK_OF]
        confusion: dict[str, dict[str, int]] = {}
        for record in self.records:
            row = confusion.setdefault(record.shown, {})
            row[record.outcome] = row.get(record.outcome, 0) + 1
        right = sum(r.read == r.shown for r in gestures)
        return {
            "lighting": self.condition.lighting,
            "camera_noise": self.condition.camera_noise,
            "gestures_read": len(gestures),
            "detection_rate": right / len(gestures) if gestures else None,
            "discarded": sum(r.outcome == DISCARDED for r in gestures),
            "no_hand": sum(r.no_hand for r in gestures),
            "misread": sum(not r.discarded and r.read != r.shown for r in gestures),
            "feedback_read": len(thumbs),
            "feedback_misread": sum(not r.discarded and r.read != r.shown for r in thumbs),
            "feedback_discarded": sum(r.outcome == DISCARDED for r in thumbs),
            "feedback_no_hand": sum(r.no_hand for r in thumbs),
            "discarded_thumb": self.discarded_thumb,
            "thumbs_asked_again": self.thumbs_asked_again,
            "confusion": confusion,
            "reads": dict(Counter(r.outcome for r in self.records)),
            "skin": self.skin,
            "pose_jitter": self.pose_jitter,
            "adapt": None if self.labels is None else self.labels.summary(),
            # adapting: the share the shipped model reads right in the very same views
            "shipped_detection_rate": (
                sum(r.shipped == r.shown for r in gestures) / len(gestures)
                if gestures and self.labels is not None
                else None
            ),
        }

    def close(self) -> None:
        """Free the eye cameras' OpenGL context."""
        self.eyes.close()
