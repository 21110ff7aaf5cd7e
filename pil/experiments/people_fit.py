"""A simulated person fitted to a participant's recorded sessions, and its file.

From every consented session of one participant (:mod:`pil.experiments.people_sources`,
read by :mod:`pil.experiments.people_observed`):

* **latencies** (simulated s), each a lognormal fitted by maximum likelihood
  (``scipy.stats.lognorm.fit`` with the location fixed at 0): the gesture latency after Robin
  gives the turn back, the thumb down's and the thumb up's latency from the action's
  beginning. Kept: the median (the lognormal's scale), sigma (its shape), n, and a 95 % interval
  of the median (Student's t on the logs). One observation: a fixed latency (sigma 0).
* **rates**, each k of n with its exact (Clopper-Pearson) 95 % interval (the beta quantiles,
  ``scipy.stats.beta``): a thumb down on a wrong arm move and on a wrong finger motion (close,
  open), a thumb down on a right action (a slip), a thumb up on a right action (the rest is
  silence, which approves). A thumb that came after the feedback window counts as given: its
  latency says it was late, and the simulated person is late as often.
* **hand examples**: the webcam's landmarks per gesture label, as recorded (none without a
  webcam), for a hand model to retarget.

The file (JSON, ``format`` :data:`PERSON_FORMAT`) names every source session with its files'
SHA-256, and the settings each was run with, so the simulated sessions repeat them. The
simulation uses the fitted values (the MLE); the intervals say how well the sessions pin them.
:meth:`FittedPerson.verdict` draws the person's thumb on one robot action from them (the
simulated player, :mod:`robin_sim.fitted.player`, sends it).
"""

from __future__ import annotations

import json
import math
from collections.abc import Mapping, Sequence
from dataclasses import asdict, dataclass, field
from pathlib import Path
from typing import Any

import numpy as np
from scipy import stats

from pil.errors import RobinPilError
from pil.experiments.people_observed import FINGER_MOTIONS, Observed
from pil.types import Feedback

PERSON_FORMAT = 1
KIND = "robin-pil fitted person"


class FittedPersonError(RobinPilError):
    """A fitted-person file that cannot be used."""


@dataclass(frozen=True)
class Latency:
    """A lognormal latency (s): ``median`` (scale) and ``sigma`` (shape) fitted to ``n``
    observations, with a 95 % interval of the median."""

    median: float
    sigma: float
    n: int
    median_low: float
    median_high: float

    @classmethod
    def fit(cls, values: Sequence[float]) -> Latency | None:
        """The lognormal MLE of ``values`` (each > 0); None without any."""
        data = np.array([max(float(v), 1e-3) for v in values])
        if data.size == 0:
            return None
        if data.size == 1:
            value = float(data[0])
            return cls(round(value, 4), 0.0, 1, round(value, 4), round(value, 4))
        sigma, _, scale = stats.lognorm.fit(data, floc=0)
        logs = np.log(data)
        half = stats.t.ppf(0.975, data.size - 1) * logs.std(ddof=1) / math.sqrt(data.size)
        centre = logs.mean()
        return cls(
            round(float(scale), 4),
            round(float(sigma), 4),
            int(data.size),
            round(float(math.exp(centre - half)), 4),
            round(float(math.exp(centre + half)), 4),
        )

    def draw(self, rng: np.random.Generator) -> float:
        """One latency."""
        if self.sigma == 0.0:
            return self.median
        return float(self.median * math.exp(rng.normal(0.0, self.sigma)))


@dataclass(frozen=True)
class Rate:
    """``k`` of ``n`` with its exact 95 % interval (``p`` None when ``n`` is 0)."""

    k: int
    n: int
    p: float | None
    low: float | None
    high: float | None

    @classmethod
    def of(cls, k: int, n: int) -> Rate:
        if n == 0:
            return cls(0, 0, None, None, None)
        # Clopper-Pearson: the beta quantiles (scipy's binomtest(...).proportion_ci's default)
        low = float(stats.beta.ppf(0.025, k, n - k + 1)) if k > 0 else 0.0
        high = float(stats.beta.ppf(0.975, k + 1, n - k)) if k < n else 1.0
        return cls(k, n, round(k / n, 4), round(low, 4), round(high, 4))

    def value(self, fallback: float) -> float:
        """The fitted share, or ``fallback`` when nothing was observed."""
        return fallback if self.p is None else self.p


@dataclass(frozen=True)
class FittedPerson:
    """A participant's fitted behaviour (see the module doc)."""

    participant: str
    gesture_latency: Latency
    down_latency: Latency | None
    up_latency: Latency | None
    down_on_wrong_move: Rate
    down_on_wrong_fingers: Rate
    down_on_right: Rate
    up_on_right: Rate
    late_thumbs: int
    hand_examples: dict[str, list[list[list[float]]]] = field(default_factory=dict)
    sources: list[dict[str, Any]] = field(default_factory=list)  # name, participant, sha256
    settings: list[dict[str, Any]] = field(default_factory=list)  # one per source session

    @property
    def down_on_wrong(self) -> Rate:
        """Thumbs down on every wrong action, arm and fingers together."""
        moves, fingers = self.down_on_wrong_move, self.down_on_wrong_fingers
        return Rate.of(moves.k + fingers.k, moves.n + fingers.n)

    def verdict(
        self, action: str | None, meant: str | None, rng: np.random.Generator
    ) -> tuple[Feedback, float] | None:
        """The thumb this person gives when the robot begins ``action`` meaning ``meant``,
        and its latency from that beginning (None: no thumb, silence). A share fitted from
        nothing falls back on the wrong actions' pooled share (a wrong action), else 1 for a
        wrong action and 0 for a right one."""
        wrong = action != meant
        moves, fingers = self.down_on_wrong_move, self.down_on_wrong_fingers
        pooled = (moves.k + fingers.k) / (moves.n + fingers.n) if moves.n + fingers.n else 1.0
        if wrong and action in FINGER_MOTIONS:
            down = fingers.value(pooled)
        elif wrong:
            down = moves.value(pooled)
        else:
            down = self.down_on_right.value(0.0)
        up = 0.0 if wrong else self.up_on_right.value(0.0)
        roll = float(rng.random())
        if roll < down and self.down_latency is not None:
            return Feedback.NOT_OK, self.down_latency.draw(rng)
        if roll < down + up and self.up_latency is not None:
            return Feedback.OK, self.up_latency.draw(rng)
        return None

    def as_json(self) -> dict[str, Any]:
        return {"kind": KIND, "format": PERSON_FORMAT, **asdict(self)}


def fit_person(
    participant: str,
    observed: Sequence[Observed],
    sources: Sequence[Mapping[str, Any]],
    settings: Sequence[Mapping[str, Any]],
) -> FittedPerson:
    """The fitted person of ``participant`` from their sessions' observations."""
    gestures = [v for o in observed for v in o.gesture_latencies]
    judged = [j for o in observed for j in o.judgements]
    if not gestures:
        raise FittedPersonError(
            f"participant {participant}: no instruction gesture in their sessions; nothing to fit"
        )
    downs = [j.latency for j in judged if j.thumb == "down" and j.latency is not None]
    ups = [j.latency for j in judged if j.thumb == "up" and j.latency is not None]
    wrong_moves = [j for j in judged if j.wrong and not j.fingers]
    wrong_fingers = [j for j in judged if j.wrong and j.fingers]
    right = [j for j in judged if not j.wrong]
    examples: dict[str, list[list[list[float]]]] = {}
    for o in observed:
        for label, marks in o.hand_examples.items():
            examples.setdefault(label, []).extend(marks)
    latency = Latency.fit(gestures)
    assert latency is not None  # there are gestures
    return FittedPerson(
        participant=participant,
        gesture_latency=latency,
        down_latency=Latency.fit(downs),
        up_latency=Latency.fit(ups),
        down_on_wrong_move=Rate.of(sum(j.thumb == "down" for j in wrong_moves), len(wrong_moves)),
        down_on_wrong_fingers=Rate.of(
            sum(j.thumb == "down" for j in wrong_fingers), len(wrong_fingers)
        ),
        down_on_right=Rate.of(sum(j.thumb == "down" for j in right), len(right)),
        up_on_right=Rate.of(sum(j.thumb == "up" for j in right), len(right)),
        late_thumbs=sum(j.late for j in judged),
        hand_examples=examples,
        sources=[dict(s) for s in sources],
        settings=[dict(s) for s in settings],
    )


def write_person(person: FittedPerson, path: Path) -> None:
    """The fitted person as JSON (atomically)."""
    from pil.atomic import write_text_atomic

    write_text_atomic(path, json.dumps(person.as_json(), indent=1, sort_keys=False) + "\n")


def read_person(data: Mapping[str, Any], where: str) -> FittedPerson:
    """A fitted person from its JSON; :class:`FittedPersonError` naming ``where``."""
    if data.get("kind") != KIND or data.get("format") != PERSON_FORMAT:
        raise FittedPersonError(
            f"{where}: not a fitted person of format {PERSON_FORMAT} (kind {data.get('kind')!r}, "
            f"format {data.get('format')!r})"
        )
    try:

        def latency(value: Any) -> Latency | None:
            return None if value is None else Latency(**value)

        return FittedPerson(
            participant=str(data["participant"]),
            gesture_latency=Latency(**data["gesture_latency"]),
            down_latency=latency(data["down_latency"]),
            up_latency=latency(data["up_latency"]),
            down_on_wrong_move=Rate(**data["down_on_wrong_move"]),
            down_on_wrong_fingers=Rate(**data["down_on_wrong_fingers"]),
            down_on_right=Rate(**data["down_on_right"]),
            up_on_right=Rate(**data["up_on_right"]),
            late_thumbs=int(data["late_thumbs"]),
            hand_examples=dict(data.get("hand_examples", {})),
            sources=list(data.get("sources", [])),
            settings=list(data.get("settings", [])),
        )
    except (KeyError, TypeError, ValueError) as error:
        raise FittedPersonError(f"{where}: a field is missing or wrong ({error})") from None
