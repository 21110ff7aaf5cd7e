"""What ``train-gestures`` builds: the data set size, seed, output folder and workers."""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

from pil.cpus import cpu_count
from pil.errors import RobinPilError
from pil.task.params import SEED
from robin_sim.vision.dataset import CHUNK

DEFAULT_SAMPLES = 18144  # 2592 per class, a ninth under a held leg (issue 41; 16128 before)
MIN_SAMPLES = 7 * 4
MAX_SAMPLES = 100_000  # about 6x the shipped model's set; hours of rendering on 2 cores


def default_build_workers() -> int:
    """Processes rendering the gesture samples by default: 2, or 1 on a machine with one CPU."""
    return min(2, cpu_count())


@dataclass(frozen=True, slots=True)
class BuildConfig:
    """What ``train-gestures`` builds."""

    samples: int = DEFAULT_SAMPLES
    seed: int = 0
    out: Path = Path("out/gestures")
    workers: int = field(default_factory=lambda: default_build_workers())
    cache: Path | None = None  # a render cache root (robin_sim.vision.render_key); None: OUT

    def __post_init__(self) -> None:
        SEED.parse(self.seed, "--seed")  # a negative or huge seed: refused here
        samples_ok = isinstance(self.samples, int) and not isinstance(self.samples, bool)
        if not samples_ok or not MIN_SAMPLES <= self.samples <= MAX_SAMPLES:
            raise RobinPilError(
                f"--samples must be a whole number from {MIN_SAMPLES} (4 of each of the 7 "
                f"classes) to {MAX_SAMPLES}, got {self.samples!r}"
            )
        cpus = cpu_count()
        workers_ok = isinstance(self.workers, int) and not isinstance(self.workers, bool)
        if not workers_ok or not 1 <= self.workers <= cpus:
            raise RobinPilError(
                f"--workers must be a whole number from 1 to {cpus} (the CPUs here: each "
                f"worker renders with its own OpenGL context), got {self.workers!r}"
            )

    @property
    def heldout(self) -> int:
        """Samples in the held-out split."""
        return max(CHUNK, self.samples // 3)

    @property
    def chunks(self) -> Path:
        """Folder of the chunk files: ``OUT/chunks``, or with a cache root the folder of this
        checkout's render key and the seed under it (reused while what the pictures depend
        on is unchanged)."""
        if self.cache is None:
            return self.out / "chunks"
        from robin_sim.vision.render_key import cache_folder

        return cache_folder(self.cache, self.seed)


__all__ = ["DEFAULT_SAMPLES", "MAX_SAMPLES", "MIN_SAMPLES", "BuildConfig", "default_build_workers"]
