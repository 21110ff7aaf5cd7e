"""The eye cameras' gesture model adapting to one person from the robot's own feedback.

The model is the shipped one (real weights); the feature rows are drawn around the model's
own feature means, so these checks need no rendering. The loop's hook is checked with the
real step loop (pil.task.runner) and the paper's dice detector, recording what it is told.
"""

from __future__ import annotations

import numpy as np
import pytest

from pil.learner import Learner
from pil.task.detector import Detector, LearnsFromFeedback
from pil.task.runner import steps
from pil.types import Feedback, Gesture
from robin_sim.vision.adapting import MAX_PENDING, AdaptedModel, FeedbackLabels
from robin_sim.vision.classifier import CLASSES, load_shipped


@pytest.fixture(scope="module")
def rows() -> np.ndarray:
    model = load_shipped()
    rng = np.random.default_rng(0)
    return model.mean + rng.normal(0.0, 1.0, (40, model.mean.size)) * model.scale


def test_without_examples_it_reads_exactly_as_the_shipped_model(rows: np.ndarray) -> None:
    shipped = load_shipped()
    adapted = AdaptedModel(shipped)
    np.testing.assert_allclose(adapted.probabilities(rows), shipped.probabilities(rows), atol=1e-12)
    assert adapted.threshold == shipped.threshold and adapted.size == 0


def test_confirmed_readings_raise_their_class_near_the_shipped_weights(rows: np.ndarray) -> None:
    shipped = load_shipped()
    adapted = AdaptedModel(shipped)
    label = "release"
    k = CLASSES.index(label)
    taught = rows[:10]
    before = shipped.probabilities(taught)[:, k].mean()
    for row in taught:
        adapted.learn(row[None], label)
    after = adapted.probabilities(taught)[:, k].mean()
    assert adapted.size == 10 and adapted.refits == 10
    assert after > before + 0.2, (before, after)  # the person's own readings: clearly raised
    # the output layer moved, but stays near the shipped one (the L2 pull; its weights lie
    # within about +-1)
    moved = np.abs(adapted.weights - shipped.weights[-1]).max()
    assert 0.0 < moved < 1.0, moved
    assert np.abs(shipped.weights[-1]).max() > moved


def test_a_stronger_pull_moves_the_model_less(rows: np.ndarray) -> None:
    shipped = load_shipped()
    k = CLASSES.index("grasp")
    raised = []
    for pull in (1.0, 0.01):
        adapted = AdaptedModel(shipped, pull=pull)
        adapted.learn(rows[:8], "grasp")
        raised.append(adapted.probabilities(rows[:8])[:, k].mean())
    assert raised[1] > raised[0]


def test_labels_wait_for_an_approval_and_take_the_state_gesture(rows: np.ndarray) -> None:
    labels = FeedbackLabels(AdaptedModel(load_shipped()))
    labels.read(rows[0:2])  # a discarded reading (two eyes)
    labels.read(None)  # no eye found a hand: nothing to learn
    labels.read(rows[2:3])  # the reading acted on (one eye)
    labels.verdict("give_me", approved=False)  # a thumb down: nothing is labelled yet
    assert labels.model.size == 0 and len(labels.pending) == 2
    labels.verdict("give_me", approved=True)
    assert labels.model.size == 3 and labels.model.labels == [CLASSES.index("give_me")] * 3
    assert labels.pending == [] and labels.summary()["readings_confirmed"] == 2
    labels.verdict("grasp", approved=True)  # an approval with nothing read: nothing learnt
    assert labels.model.size == 3
    for k in range(MAX_PENDING + 5):
        labels.read(rows[k : k + 1])
    assert len(labels.pending) == MAX_PENDING  # the oldest go first


class RecordingDetector(Detector):
    """The paper's dice detector, recording the verdicts the loop tells it."""

    def __init__(self, *args: object, **kwargs: object) -> None:
        super().__init__(*args, **kwargs)  # type: ignore[arg-type]
        self.verdicts: list[tuple[Gesture | None, bool]] = []

    def verdict(self, meant: Gesture | None, approved: bool) -> None:
        self.verdicts.append((meant, approved))


def _run(rate: float, seed: int, tables: int) -> tuple[list, list]:
    from pil.task.assemble import assemble
    from pil.task.spec import parse_run_spec

    spec = parse_run_spec(
        system="pil", rate=rate, seed=seed, scenario=None, params={"tables": tables}
    )
    built = assemble(spec)
    detector = RecordingDetector(rate, seed=seed + 1, deck_size=64)
    assert isinstance(detector, LearnsFromFeedback)
    learner: Learner = built.learner
    records = list(steps(learner, built.person, detector, built.world, **built.options))
    acted = [r for r in records if r.action is not None and not r.proactive]
    return acted, detector.verdicts


def test_the_loop_tells_a_learning_reader_what_the_learner_received() -> None:
    acted, verdicts = _run(rate=1.0, seed=3, tables=4)
    assert [ok for _, ok in verdicts] == [r.feedback_read is not Feedback.NOT_OK for r in acted]
    assert all(meant is None for meant, ok in verdicts if not ok)  # a refusal labels nothing
    labelled = [(m, r) for (m, ok), r in zip(verdicts, acted, strict=True) if ok and m]
    approvals = sum(ok for _, ok in verdicts)
    # every gesture read right: whatever is labelled is labelled right, and once the first
    # associations are learnt most approvals carry a label
    assert all(m is r.true_gesture for m, r in labelled)
    assert len(labelled) >= 0.6 * approvals, (len(labelled), approvals)


def test_labels_come_from_what_was_learnt_not_from_a_misreading() -> None:
    acted, verdicts = _run(rate=0.6, seed=3, tables=10)
    approved = [(m, r) for (m, ok), r in zip(verdicts, acted, strict=True) if ok]
    misread = [(m, r) for m, r in approved if r.state.gesture is not r.true_gesture]
    assert len(misread) >= 10  # at 60 % misreads get approved: PIL learnt them
    labelled = [(m, r) for m, r in approved if m is not None]
    right = sum(m is r.true_gesture for m, r in labelled)
    read_right = sum(r.state.gesture is r.true_gesture for _, r in labelled)
    # the label is the person's gesture more often than the reading acted on is
    assert right > read_right and right >= 0.9 * len(labelled), (right, read_right, len(labelled))
