"""What ``train-gestures`` builds: the data set size, seed, output folder and workers."""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

from pil.errors import RobinPilError
from robin_sim.vision.dataset import CHUNK

DEFAULT_SAMPLES = 2016  # 288 per class; the shipped model's
MIN_SAMPLES = 7 * 4


@dataclass(frozen=True, slots=True)
class BuildConfig:
    """What ``train-gestures`` builds."""

    samples: int = DEFAULT_SAMPLES
    seed: int = 0
    out: Path = Path("out/gestures")
    workers: int = 2

    def __post_init__(self) -> None:
        if isinstance(self.samples, bool) or self.samples < MIN_SAMPLES:
            raise RobinPilError(
                f"--samples must be a whole number >= {MIN_SAMPLES} (4 of each of the 7 "
                f"classes), got {self.samples!r}"
            )
        if self.workers < 1:
            raise RobinPilError(f"--workers must be >= 1, got {self.workers}")

    @property
    def heldout(self) -> int:
        """Samples in the held-out split."""
        return max(CHUNK, self.samples // 3)

    @property
    def chunks(self) -> Path:
        """Folder of the chunk files."""
        return self.out / "chunks"


__all__ = ["DEFAULT_SAMPLES", "MIN_SAMPLES", "BuildConfig"]
