"""The rendered gesture data set: sampled performances, conditions and views, in chunks.

Sample ``i`` of split ``s`` draws everything from ``default_rng([seed, s, i])`` (so a sample
never depends on which worker renders it or in which order): its class (cycling through the
seven), where the hand is (a quarter each: above a leg or a table spot as when pointing, drawn
back and raised there as the person holds a pointing up to be read, at the handover point where
the palm is held out for "give me" and the release and thumbs after it are shown, or anywhere
in the person's working box) and how much higher (``lift``), where Robin's arm is (at home, or
holding a leg above the palm after a handover, the hand where the person shows each sign then:
:func:`held_leg_hand`; every sample of the ``held_leg`` split, a ninth of the training split;
``arm``), its performance (pose jitter
scaled by ``jitter``, hand size, skin tone), the aim's error and the condition (light
intensity and direction, sensor noise, blur). Both splits draw skin tones, pose jitter and hand
heights across the whole range a person shows (:data:`SPLITS`); the *held-out* split draws
light from ranges the *training* split never has, so the held-out accuracy measures light never
trained on.

A chunk of samples is one ``.npz`` (written atomically) of per-eye hand crops
(:mod:`robin_sim.vision.crops`), labels, per-sample conditions and the seed it was drawn from;
finished chunks are kept, so an interrupted run resumes. A chunk is reused only when it reads
back whole and holds the run's seed (:func:`chunk_ready`): a run with another seed, or a
damaged file, renders it anew. :func:`load_split` computes the features from the crops, so a
change of features reuses the rendered chunks (:mod:`robin_sim.vision.render_key` names the
folder that holds them by what they depend on).
"""

from __future__ import annotations

import os
import zipfile
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from pil.errors import RobinPilError
from pil.regular_files import open_bounded
from pil.types import SIGN_OF, Feedback
from robin_sim.model import names, robot_spec
from robin_sim.model.scene import DEFAULT_HANDOVER, DEFAULT_LEGS, DEFAULT_SPOTS
from robin_sim.model.scene_file import site_offset
from robin_sim.vision.classifier import CLASSES
from robin_sim.vision.crops import HandCrops
from robin_sim.vision.features import crop_features

CHUNK = 48  # samples per chunk
EYES = 2
CROP_KEYS = ("mask", "shading", "relief", "size")  # per eye row (robin_sim.vision.crops)
CHUNK_KEYS = (*CROP_KEYS, "label", "sample", "eye", "found", "iou", "condition", "seed")
# what reading a damaged .npz can raise (a truncated zip, a bad member, a missing key)
_DAMAGED = (OSError, ValueError, KeyError, EOFError, zipfile.BadZipFile)


class ChunkError(RobinPilError):
    """A chunk file of the data set that is damaged or was drawn from another seed."""


@dataclass(frozen=True, slots=True)
class Ranges:
    """Ranges a split draws its conditions from (each a tuple of (low, high) intervals)."""

    skin: tuple[tuple[float, float], ...]
    lighting: tuple[tuple[float, float], ...]
    light_tilt: tuple[tuple[float, float], ...]
    camera_noise: tuple[float, float] = (0.0, 10.0)
    blur: tuple[float, float] = (0.0, 0.8)
    jitter: tuple[float, float] = (0.0, 2.5)  # scale of the performance's pose jitter
    lift: tuple[float, float] = (-0.04, 0.16)  # m the hand is held higher than its place
    held_leg: float = 0.0  # share of samples drawn under a leg Robin holds above the palm


WHOLE_SKIN = ((0.0, 4.0),)  # every tone of the five-tone scale (hand_poses.SKIN_TONES)
SPLITS: dict[str, Ranges] = {
    # a ninth of the training samples under a leg Robin holds above the palm (issue 41)
    "train": Ranges(
        skin=WHOLE_SKIN, lighting=((0.55, 1.3),), light_tilt=((0.0, 0.5),), held_leg=1 / 9
    ),
    "heldout": Ranges(
        skin=WHOLE_SKIN, lighting=((0.35, 0.55), (1.3, 1.6)), light_tilt=((0.5, 0.8),)
    ),
    # the condition sweep (robin_sim.vision.conditions): every skin tone, the light and noise
    # set per condition, the usual pose jitter, the hand at its place
    "sweep": Ranges(
        skin=WHOLE_SKIN,
        lighting=((1.0, 1.0),),
        light_tilt=((0.0, 0.5),),
        jitter=(1.0, 1.0),
        lift=(0.0, 0.0),
    ),
    # every sample with Robin holding a leg above the palm at the handover point (issue 41), in
    # the training light, each sign where the person shows it then (held_leg_hand)
    "held_leg": Ranges(
        skin=WHOLE_SKIN, lighting=((0.55, 1.3),), light_tilt=((0.0, 0.5),), held_leg=1.0
    ),
}
SPLIT_IDS = {name: k for k, name in enumerate(SPLITS)}
# Where gestures are made: above a leg or a spot of the default layout (the pointing hand's
# place: these plus the hand's pointing offset), or anywhere in the person's working box. A leg's
# place is its centre; a spot's is drawn 1 cm lower (SPOT_PLACE_DROP), as the shipped gesture
# model's data always had it.
SPOT_PLACE_DROP = 0.01  # m
PLACES = np.array(
    [[x, y, robot_spec.GRASP_HEIGHT] for x, y, _ in DEFAULT_LEGS]
    + [[x, y, robot_spec.GRASP_HEIGHT - SPOT_PLACE_DROP] for x, y in DEFAULT_SPOTS]
)
# The hand (mocap position) with its palm held out at the handover point: the scene's
# DEFAULT_HANDOVER (palm surface centre) less the palm site's offset in the hand frame
# (models/scene.xml, human_palm_site); tests/test_vision_train.py checks it against the model.
HANDOVER_HAND = np.array(DEFAULT_HANDOVER) - site_offset(names.HUMAN_PALM_SITE)
BOX = (np.array([0.62, -0.10, 0.86]), np.array([1.25, 0.45, 1.12]))  # m, x y z
AIM_ERROR = 0.015  # m, sd of the aim point's error per axis
# Robin's arm in a sample: at home, or holding a leg above the palm at the handover point (the
# state robin_sim.vision.arm_states reaches by acting, "human"); the hand under the leg varies
# this much (m, sd across, and at most this much lower: never up into the leg). "away" (the arm
# out of the eyes' view, arm_states.away_qpos) is a what-if for benches: no split draws it.
ARMS = ("home", "held_leg", "away")
THUMB_SIGNS = (SIGN_OF[Feedback.OK], SIGN_OF[Feedback.NOT_OK])  # the thumbs' pose names
UNDER_LEG_SPREAD = 0.015
UNDER_LEG_DROP = 0.03


def drawn_back(at: np.ndarray, aside: float = 0.0) -> np.ndarray:
    """Where the person holds a sign up to be read after making it at ``at``: drawn back to
    ``PERSON_CLEAR_X``, raised ``POINT_RAISE`` and moved ``aside`` along y (as
    ``HumanHand.withdraw``)."""
    return np.array([robot_spec.PERSON_CLEAR_X, at[1] + aside, at[2] + robot_spec.POINT_RAISE])


def held_leg_hand(sign: str, rng: np.random.Generator) -> np.ndarray:
    """Where the person shows ``sign`` while Robin holds a leg above the palm (mocap position,
    m), as :class:`~robin_sim.person.body.PhysicalBody` does: a thumb drawn back, raised and
    aside into Robin's view, a pointing drawn back and raised, any other sign (release, give
    me, grasp, the relaxed hand) with the palm under the leg (never raised into it)."""
    if sign in THUMB_SIGNS or sign == "pointing":
        aside = robot_spec.THUMB_ASIDE if sign in THUMB_SIGNS else 0.0
        return drawn_back(HANDOVER_HAND, aside) + rng.normal(0, 0.02, 3)
    across = rng.normal(0, UNDER_LEG_SPREAD, 2)
    return HANDOVER_HAND + np.array([*across, -rng.uniform(0, UNDER_LEG_DROP)])


def _uniform(rng: np.random.Generator, intervals: tuple[tuple[float, float], ...]) -> float:
    widths = np.array([hi - lo for lo, hi in intervals])
    if widths.sum() <= 0:  # a fixed value (a sweep's condition, set per sample anyway)
        return float(intervals[0][0])
    k = int(rng.choice(len(intervals), p=widths / widths.sum()))
    return float(rng.uniform(*intervals[k]))


@dataclass(frozen=True, slots=True)
class SampleSpec:
    """Everything one sample shows (drawn by :func:`sample_spec`)."""

    label: int
    hand: np.ndarray  # mocap position, m
    aim_error: np.ndarray  # m
    skin: float
    lighting: float
    light_turn: float
    light_tilt: float
    camera_noise: float
    blur: float
    seed: int  # for the performance and the noise
    jitter: float = 1.0  # scale of the pose jitter (hand_poses.Performance.draw)
    lift: float = 0.0  # m the hand is held higher than ``hand``
    arm: str = "home"  # where Robin's arm is (one of ARMS)

    @property
    def held_at(self) -> np.ndarray:
        """Where the hand is held (mocap position, m): ``hand`` raised by ``lift``."""
        return self.hand + np.array([0.0, 0.0, self.lift])


def sample_spec(seed: int, split: str, index: int) -> SampleSpec:
    """Sample ``index`` of ``split``."""
    rng = np.random.default_rng([seed, SPLIT_IDS[split], index])
    ranges = SPLITS[split]
    where = rng.random()
    arm = "home"
    # drawn only where a split has held-leg samples: the others' streams stay as they were
    if ranges.held_leg > 0 and rng.random() < ranges.held_leg:
        arm = "held_leg"
        hand = held_leg_hand(CLASSES[index % len(CLASSES)], rng)
    elif where < 1 / 4:  # above a place, as while pointing
        hand = PLACES[rng.integers(len(PLACES))] + robot_spec.POINT_OFFSET + rng.normal(0, 0.02, 3)
    elif where < 2 / 4:  # drawn back from a place and raised, where a pointing is read
        place = PLACES[rng.integers(len(PLACES))] + robot_spec.POINT_OFFSET
        hand = drawn_back(place) + rng.normal(0, 0.02, 3)
    elif where < 3 / 4:  # the palm held out at the handover point (give me, release, thumbs)
        hand = HANDOVER_HAND + rng.normal(0, 0.02, 3)
    else:
        hand = rng.uniform(*BOX)
    return SampleSpec(
        label=index % len(CLASSES),
        hand=hand,
        aim_error=rng.normal(0.0, AIM_ERROR, 3),
        skin=_uniform(rng, ranges.skin),
        lighting=_uniform(rng, ranges.lighting),
        light_turn=float(rng.uniform(-np.pi, np.pi)),
        light_tilt=_uniform(rng, ranges.light_tilt),
        camera_noise=float(rng.uniform(*ranges.camera_noise)),
        blur=float(rng.uniform(*ranges.blur)),
        seed=int(rng.integers(2**31)),
        jitter=float(rng.uniform(*ranges.jitter)),
        # the last draw; under a held leg the hand is never raised into it
        lift=float(rng.uniform(*ranges.lift)) if arm == "home" else 0.0,
        arm=arm,
    )


def chunk_path(folder: Path, split: str, chunk: int) -> Path:
    """File of chunk ``chunk`` of ``split``."""
    return folder / f"{split}-{chunk:04d}.npz"


def chunks_for(samples: int) -> int:
    """Number of chunks holding ``samples`` samples."""
    return -(-samples // CHUNK)


def save_chunk(path: Path, arrays: Mapping[str, np.ndarray | np.generic]) -> None:
    """Write ``arrays`` to ``path`` atomically (a partial file never stays behind)."""
    path.parent.mkdir(parents=True, exist_ok=True)
    partial = path.with_suffix(".partial.npz")
    with partial.open("wb") as handle:
        np.savez_compressed(handle, allow_pickle=False, **arrays)
    os.replace(partial, path)


def read_chunk(path: Path, seed: int | None = None) -> dict[str, np.ndarray]:
    """Every array of a chunk file; :class:`ChunkError` when it is damaged, lacks a key or
    (``seed`` given) was drawn from another seed."""
    try:
        with open_bounded(path, "arrays") as handle, np.load(handle, allow_pickle=False) as z:
            arrays = {key: z[key] for key in CHUNK_KEYS}
    except _DAMAGED as error:
        raise ChunkError(
            f"chunk {path} is damaged or incomplete ({type(error).__name__}: {error}); run "
            "the command again: a damaged chunk is rendered anew"
        ) from None
    if seed is not None and int(arrays["seed"]) != seed:
        raise ChunkError(
            f"chunk {path} was drawn with seed {int(arrays['seed'])}, not {seed}; run the "
            "command again (its chunks are rendered anew) or give another --out"
        )
    return arrays


def chunk_ready(path: Path, seed: int) -> bool:
    """Whether ``path`` holds a whole chunk drawn from ``seed`` (so it need not be rendered)."""
    if not path.is_file():
        return False
    try:
        read_chunk(path, seed)
    except ChunkError:
        return False
    return True


def load_split(
    folder: Path,
    split: str,
    samples: int,
    seed: int | None = None,
    features: Callable[[HandCrops], np.ndarray] = crop_features,
) -> dict[str, np.ndarray]:
    """The first ``samples`` samples of ``split`` from its chunk files, concatenated (each
    checked by :func:`read_chunk`), with ``features``: one row per eye row computed by
    ``features`` from its crops (zeros where no hand was found)."""
    parts: dict[str, list[np.ndarray]] = {}
    for k in range(chunks_for(samples)):
        for key, value in read_chunk(chunk_path(folder, split, k), seed).items():
            if key != "seed":
                parts.setdefault(key, []).append(value)
    data = {key: np.concatenate(value) for key, value in parts.items()}
    keep = data["sample"] < samples
    data = {key: value[keep] for key, value in data.items()}
    crops = [
        HandCrops(*(data[key][k] for key in CROP_KEYS)) if data["found"][k] else None
        for k in range(len(data["found"]))
    ]
    data["features"] = feature_rows(crops, features)
    return data


def feature_rows(
    crops: Sequence[HandCrops | None],
    features: Callable[[HandCrops], np.ndarray] = crop_features,
) -> np.ndarray:
    """One row of ``features`` per eye row's crops (zeros where no hand was found)."""
    rows = [None if c is None else features(c) for c in crops]
    width = next((len(r) for r in rows if r is not None), 1)
    blank = np.zeros(width, np.float32)
    return np.stack([blank if r is None else r for r in rows])


def split_of_views(
    views: Sequence[tuple[int, int, Sequence[HandCrops | None]]],
) -> dict[str, np.ndarray]:
    """A split as :func:`load_split` returns it (``sample``, ``label``, ``found``,
    ``features``) of freshly rendered samples, each ``(sample, label, per-eye crops)``."""
    rows = [(sample, label, c) for sample, label, crops in views for c in crops]
    return {
        "sample": np.array([r[0] for r in rows], np.int64),
        "label": np.array([r[1] for r in rows], np.int64),
        "found": np.array([r[2] is not None for r in rows], bool),
        "features": feature_rows([r[2] for r in rows]),
    }
