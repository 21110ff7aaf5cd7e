"""The eye cameras' gesture model adapted to one person, on the fly, from the robot's feedback.

The shipped model (:mod:`robin_sim.vision.classifier`) was trained on a crowd; a given person
(their skin, how much their poses vary, the light of the room) may sit where it is unsure.
:class:`AdaptedModel` keeps the model's hidden layer as it is and refits its output layer on
this person's confirmed readings, pulled towards the shipped weights (an L2 penalty on the
difference, the "L2-SP" prior of transfer learning) so that a few examples move it a little
and classes the person never showed keep their shipped weights; each gesture the person showed
weighs the same in total (class-balanced), so the most frequent one does not pull the rest
towards it. The refit is a small smooth convex problem (the examples' weighted softmax
cross-entropy, summed, plus the pull), solved by
SciPy's L-BFGS from the current weights (on one BLAS thread: a few milliseconds).

Where the labels come from (:class:`FeedbackLabels`): only what the robot itself perceives and
has learnt. The eye readings made for one instruction (every performance of it: the discarded
ones, the one acted on, the ones after a thumb down) wait until the robot takes an action for
it as approved (its own reading of the thumb, or silence); then each is labelled with the
gesture that action means by the learner's table (:func:`pil.gesture_evidence.meant_gesture`),
and the model is refitted. Not with the gesture the robot read: PIL learns the action of a
gesture misread the same way again and again for the misread state, so the misread action is
approved, and labelling by the reading would teach the model its own mistakes (tried: a person
in dim light read right 0.91 with the shipped model fell to 0.85). Without evidence (early
on, or a context where two gestures lead to the same action) the readings are dropped
unlabelled. The person's true gesture is never used.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
from scipy.optimize import minimize
from threadpoolctl import threadpool_limits

from robin_sim.vision.classifier import CLASSES, GestureModel

PULL = 5.0  # weight of the squared distance to the shipped output layer (the examples' losses
# are summed: a few examples move the layer a little, a few hundred decide)
MAX_EYE_ROWS = 600  # eye rows kept (the oldest go first)
MAX_PENDING = 12  # eye rows of one instruction awaiting its verdict (the oldest go first)
REFIT_ITERATIONS = 60  # L-BFGS iterations per refit (from the last weights: few are needed)


def _softmax(logits: np.ndarray) -> np.ndarray:
    z = logits - logits.max(axis=-1, keepdims=True)
    p = np.exp(z)
    return p / p.sum(axis=-1, keepdims=True)


@dataclass
class AdaptedModel:
    """A :class:`GestureModel` whose output layer follows one person (see the module doc);
    it reads like the shipped model (``probabilities``, ``threshold``) until it has examples."""

    base: GestureModel
    pull: float = PULL
    rows: list[np.ndarray] = field(default_factory=list)  # hidden-layer rows of the examples
    labels: list[int] = field(default_factory=list)  # their class indices (CLASSES)
    refits: int = 0

    def __post_init__(self) -> None:
        self.weights = self.base.weights[-1].copy()
        self.bias = self.base.biases[-1].copy()

    @property
    def threshold(self) -> float:
        return self.base.threshold

    @property
    def size(self) -> int:
        """Examples learnt from (eye rows)."""
        return len(self.rows)

    def hidden(self, features: np.ndarray) -> np.ndarray:
        """The shipped model's last hidden layer for feature rows (N, F) -> (N, H)."""
        h = (np.atleast_2d(np.asarray(features, np.float64)) - self.base.mean) / self.base.scale
        for w, b in zip(self.base.weights[:-1], self.base.biases[:-1], strict=True):
            h = np.maximum(h @ w + b, 0.0)
        return h

    def probabilities(self, features: np.ndarray) -> np.ndarray:
        """Class probabilities (N, 7) of feature rows (N, F), with the adapted output layer."""
        return _softmax(self.hidden(features) @ self.weights + self.bias)

    def learn(self, features: np.ndarray, label: str) -> None:
        """Take eye rows (N, F) of a reading confirmed as ``label`` and refit."""
        for row in self.hidden(features):
            self.rows.append(row)
            self.labels.append(CLASSES.index(label))
        del self.rows[:-MAX_EYE_ROWS], self.labels[:-MAX_EYE_ROWS]
        self._refit()

    def _refit(self) -> None:
        h, y = np.array(self.rows), np.array(self.labels)
        target = np.eye(len(CLASSES))[y]
        # each gesture the person showed weighs the same in total, however often they made it
        # (pointing is most of a task's gestures: unweighted, the layer leant towards it and
        # read "give me" and release as pointing; tried, 3 people x 5 seeds)
        seen = np.bincount(y, minlength=len(CLASSES))
        weight = (len(y) / (np.count_nonzero(seen) * seen[y]))[:, None]
        w0, b0 = self.base.weights[-1], self.base.biases[-1]
        shape = w0.shape

        def loss(v: np.ndarray) -> tuple[float, np.ndarray]:
            w, b = v[: w0.size].reshape(shape), v[w0.size :]
            p = _softmax(h @ w + b)
            dw, db = w - w0, b - b0
            value = -float((weight * target * np.log(p + 1e-12)).sum())
            value += self.pull * float((dw**2).sum() + (db**2).sum())
            g = weight * (p - target)
            grad_w = h.T @ g + 2 * self.pull * dw
            grad_b = g.sum(axis=0) + 2 * self.pull * db
            return value, np.concatenate([grad_w.ravel(), grad_b])

        start = np.concatenate([self.weights.ravel(), self.bias])
        # products this small run best on one thread: OpenBLAS's threads, spun up for each
        # one, cost 25x more on a busy machine (bench/bench_adapting.py)
        with threadpool_limits(limits=1, user_api="blas"):
            result = minimize(
                loss, start, jac=True, method="L-BFGS-B", options={"maxiter": REFIT_ITERATIONS}
            )
        self.weights = result.x[: w0.size].reshape(shape)
        self.bias = result.x[w0.size :]
        self.refits += 1


@dataclass
class FeedbackLabels:
    """The readings of the instruction in hand, labelled when an action for it is approved."""

    model: AdaptedModel
    pending: list[np.ndarray] = field(default_factory=list)  # feature rows per reading
    confirmed: int = 0  # readings labelled
    steps: int = 0  # approved actions that labelled readings
    unlabelled: int = 0  # readings dropped at an approval without evidence of the gesture

    def read(self, features: np.ndarray | None) -> None:
        """A gesture reading was made (None: no eye found a hand: nothing to learn from)."""
        if features is not None and len(features):
            self.pending.append(np.asarray(features))
            del self.pending[:-MAX_PENDING]

    def verdict(self, pose: str | None, approved: bool) -> None:
        """The robot took its last action as ``approved`` or not; an approval ends the
        instruction: its readings are labelled ``pose`` (the class name of the gesture the
        action means) or, without one, dropped."""
        if not approved or not self.pending:
            return
        if pose is None:
            self.unlabelled += len(self.pending)
        else:
            self.model.learn(np.concatenate(self.pending), pose)
            self.confirmed += len(self.pending)
            self.steps += 1
        self.pending.clear()

    def summary(self) -> dict[str, int]:
        """The summary's ``adapt`` figures."""
        return {
            "readings_confirmed": self.confirmed,
            "readings_unlabelled": self.unlabelled,
            "approvals_learnt_from": self.steps,
            "examples": self.model.size,
            "refits": self.model.refits,
        }
