"""The gesture model: standardised features -> a small MLP -> softmax over the seven classes.

Trained by :mod:`robin_sim.vision.train` (scikit-learn's ``MLPClassifier``: one hidden layer of
ReLU units) and stored as a small ``.npz`` of plain arrays (no pickle), so reading needs only
numpy. The
shipped model is ``robin_sim/vision/data/gesture_model.npz`` (:func:`load_shipped`).
"""

from __future__ import annotations

import zipfile
from dataclasses import dataclass
from importlib import resources
from pathlib import Path

import numpy as np

from pil.errors import RobinPilError
from pil.regular_files import open_bounded
from robin_sim.model.names import HUMAN_VIS_POSES
from robin_sim.vision.features import FEATURE_COUNT

NO_GESTURE = "no_gesture"
# The hand's signs as the model names them (every pose but the relaxed one), then "no gesture".
CLASSES: tuple[str, ...] = (*(p for p in HUMAN_VIS_POSES if p != "neutral"), NO_GESTURE)
# 4: features of robin_sim.vision.features as of issue 41 (silhouette and relief HOG at two
# scales); a model of format 3 (one scale) or 2 (the shading HOG) is refused by name
FORMAT = 4
SHIPPED = "gesture_model.npz"
MAX_LAYERS = 16


class ModelFileError(RobinPilError):
    """A gesture model file that cannot be read."""


@dataclass(frozen=True)
class GestureModel:
    """A feed-forward softmax classifier over standardised features."""

    mean: np.ndarray  # (F,)
    scale: np.ndarray  # (F,)
    weights: tuple[np.ndarray, ...]  # layer k: (inputs, outputs); the last has 7 outputs
    biases: tuple[np.ndarray, ...]  # layer k: (outputs,)
    threshold: float  # confidence below which a reading is discarded
    seed: int = 0
    samples: int = 0

    def probabilities(self, features: np.ndarray) -> np.ndarray:
        """Class probabilities (N, 7) of feature rows (N, F) (or (7,) for one row)."""
        h = (np.asarray(features, np.float64) - self.mean) / self.scale
        for k, (w, b) in enumerate(zip(self.weights, self.biases, strict=True)):
            h = h @ w + b
            if k < len(self.weights) - 1:
                h = np.maximum(h, 0.0)  # ReLU
        logits = h - h.max(axis=-1, keepdims=True)
        p = np.exp(logits)
        return p / p.sum(axis=-1, keepdims=True)

    def save(self, path: Path) -> Path:
        """Write the model as ``.npz`` (float32 weights)."""
        path.parent.mkdir(parents=True, exist_ok=True)
        with path.open("wb") as handle:
            np.savez_compressed(
                handle,
                allow_pickle=False,  # numeric arrays only; also no array may take this name
                format=np.int64(FORMAT),
                classes=np.array(CLASSES),
                mean=self.mean.astype(np.float32),
                scale=self.scale.astype(np.float32),
                layers=np.int64(len(self.weights)),
                **{f"w{k}": w.astype(np.float32) for k, w in enumerate(self.weights)},
                **{f"b{k}": b.astype(np.float32) for k, b in enumerate(self.biases)},
                threshold=np.float64(self.threshold),
                seed=np.int64(self.seed),
                samples=np.int64(self.samples),
            )
        return path

    @classmethod
    def load(cls, path: Path | str) -> GestureModel:
        """Read a model written by :meth:`save`; a bad file raises :class:`ModelFileError`."""
        try:
            with open_bounded(path, "arrays") as handle, np.load(handle, allow_pickle=False) as z:
                if int(z["format"]) != FORMAT or tuple(z["classes"].tolist()) != CLASSES:
                    raise ModelFileError(
                        f"gesture model {path}: format {int(z['format'])} or classes "
                        f"{z['classes'].tolist()} do not match this version ({FORMAT}, "
                        f"{CLASSES}); a model of format 3 or older was trained on other "
                        "features: retrain it with 'robin-pil train-gestures'"
                    )
                layers = int(z["layers"])
                if not 1 <= layers <= MAX_LAYERS:
                    raise ModelFileError(
                        f"gesture model {path}: {layers} layers, not 1 to {MAX_LAYERS}"
                    )
                model = cls(
                    mean=z["mean"].astype(np.float64),
                    scale=z["scale"].astype(np.float64),
                    weights=tuple(z[f"w{k}"].astype(np.float64) for k in range(layers)),
                    biases=tuple(z[f"b{k}"].astype(np.float64) for k in range(layers)),
                    threshold=float(z["threshold"]),
                    seed=int(z["seed"]),
                    samples=int(z["samples"]),
                )
        except (OSError, KeyError, ValueError, TypeError, EOFError, zipfile.BadZipFile) as error:
            raise ModelFileError(
                f"cannot read gesture model {path} ({type(error).__name__}: {error}); it is "
                "damaged or not a model file: rebuild it with 'robin-pil train-gestures'"
            ) from None
        problem = model.problem()
        if problem:
            raise ModelFileError(
                f"gesture model {path} is not usable: {problem}; rebuild it with "
                "'robin-pil train-gestures'"
            )
        return model

    def problem(self) -> str:
        """What makes the model unusable (shapes that do not chain, values that are not
        finite, a threshold outside [0, 1]), or an empty text when it is sound."""
        features = self.mean.shape
        if self.mean.ndim != 1 or self.scale.shape != features or not features[0]:
            return f"mean {self.mean.shape} and scale {self.scale.shape} differ or are empty"
        if features[0] != FEATURE_COUNT:
            return f"it takes {features[0]} features, not the {FEATURE_COUNT} the reader gives"
        inputs = features[0]
        for k, (w, b) in enumerate(zip(self.weights, self.biases, strict=True)):
            if w.ndim != 2 or w.shape[0] != inputs or b.shape != (w.shape[1],):
                return (
                    f"layer {k}: weights {w.shape} and biases {b.shape} do not take "
                    f"{inputs} inputs (transposed or cut?)"
                )
            inputs = w.shape[1]
        if inputs != len(CLASSES):
            return f"the last layer has {inputs} outputs, not one per class ({len(CLASSES)})"
        arrays = [self.mean, self.scale, *self.weights, *self.biases]
        if not all(np.isfinite(a).all() for a in arrays):
            return "some weights are NaN or infinite"
        if not (self.scale > 0).all():
            return "a feature scale is zero or negative"
        if not 0.0 <= self.threshold <= 1.0:
            return f"threshold {self.threshold} is not in [0, 1]"
        return ""


def shipped_path() -> Path:
    """Path of the model shipped in the package."""
    return Path(str(resources.files("robin_sim.vision") / "data" / SHIPPED))


def load_shipped() -> GestureModel:
    """The shipped gesture model (trained by ``robin-pil train-gestures``)."""
    return GestureModel.load(shipped_path())
