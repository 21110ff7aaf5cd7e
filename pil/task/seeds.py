"""A run's sub-seeds: the one place they are derived from the run seed.

Every random part of a run draws from its own sub-seed (numpy ``SeedSequence`` of the run
seed), so its draws do not depend on anything else in the run: per phase (``train``, ``test``)
the handover order (``draw``), the detector (the dice, or the eye cameras' noise), the learner
and the scripted person's mind. The person's physical body (where the palm is held out) is
seeded with the run seed itself (:attr:`RunSeeds.body`): the main job's seeded log is pinned
to it.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from pil.errors import InvalidChoiceError
from pil.task.params import MAX_SEED, SEED

PHASES: tuple[str, ...] = ("train", "test")
SEED_PARTS: tuple[str, ...] = ("draw", "detector", "learner", "person")
SEED_NAMES: tuple[str, ...] = tuple(f"{phase}_{part}" for part in SEED_PARTS for phase in PHASES)


@dataclass(frozen=True, slots=True)
class PhaseSeeds:
    """The sub-seeds of one phase of a run."""

    draw: int
    detector: int
    learner: int
    person: int


@dataclass(frozen=True, slots=True)
class RunSeeds:
    """All sub-seeds of one run seed (:func:`sub_seeds`)."""

    seed: int
    words: tuple[int, ...]  # one per name of SEED_NAMES

    @property
    def body(self) -> int:
        """The person's physical body: the run seed itself."""
        return self.seed

    def phase(self, phase: str) -> PhaseSeeds:
        """The sub-seeds of ``phase`` ("train" or "test")."""
        if phase not in PHASES:
            raise InvalidChoiceError("phase", phase, PHASES)
        named = self.as_dict()
        return PhaseSeeds(*(named[f"{phase}_{part}"] for part in SEED_PARTS))

    def as_dict(self) -> dict[str, int]:
        """Sub-seed name (:data:`SEED_NAMES`) -> seed."""
        return dict(zip(SEED_NAMES, self.words, strict=True))


def sub_seeds(seed: int) -> RunSeeds:
    """The sub-seeds of an already parsed run seed (no checks: the edge parsed it)."""
    words = np.random.SeedSequence(int(seed)).generate_state(len(SEED_NAMES), np.uint64)
    return RunSeeds(int(seed), tuple(int(w) for w in words))


def derive_seeds(seed: int) -> dict[str, int]:
    """Independent sub-seeds of one run or repetition, ``seed`` checked first (a Python call
    is an edge): name (:data:`SEED_NAMES`) -> seed."""
    return sub_seeds(SEED.parse(seed, "seed")).as_dict()


def person_seed(run_seed: int, person: int) -> int:
    """The run seed of person ``person`` (0-based) among the people taking turns in a run
    seeded ``run_seed`` (both parsed already): a numpy ``SeedSequence`` of the two."""
    return int(np.random.SeedSequence([int(run_seed), int(person)]).generate_state(1)[0] >> 1)


def block_seed(study_seed: int, participant: str, block: int) -> int:
    """The seed of ``participant``'s block ``block`` (0-based) in a study seeded ``study_seed``
    (all parsed already): a numpy ``SeedSequence`` of the three, the participant id by its
    UTF-8 bytes, so every participant and block of a study gets a sequence of its own and the
    same three give the same seed on any machine."""
    entropy = [int(study_seed), int(block), *participant.encode("utf-8")]
    word = np.random.SeedSequence(entropy).generate_state(1, np.uint64)[0]
    return int(word) % (MAX_SEED + 1)
