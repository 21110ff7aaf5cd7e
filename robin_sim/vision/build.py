"""``train-gestures`` end to end: render the data set in parallel (resumable), train, report.

Chunks are rendered by a ``spawn`` process pool (each worker builds its own scene and OpenGL
context); a whole chunk file of the same seed already in ``OUT/chunks`` is not rendered
again, so an interrupted run (Ctrl-C or SIGTERM) resumes where it stopped; a damaged chunk or
one of another seed is rendered anew. The held-out split has a third of the training
split's samples (at least one chunk).
"""

from __future__ import annotations

import os
from collections.abc import Callable
from concurrent.futures import FIRST_COMPLETED, Future, wait
from dataclasses import dataclass
from pathlib import Path

from pil.worker_pool import SpawnPool
from robin_sim.vision.build_config import BuildConfig
from robin_sim.vision.dataset import CHUNK, chunk_path, chunk_ready, chunks_for, load_split


def _jobs(config: BuildConfig) -> list[tuple[str, int]]:
    jobs = [("train", k) for k in range(chunks_for(config.samples))]
    jobs += [("heldout", k) for k in range(chunks_for(config.heldout))]
    return jobs


def pending(config: BuildConfig) -> list[tuple[str, int]]:
    """Chunks not rendered yet (or damaged, or drawn from another seed)."""
    return [
        job
        for job in _jobs(config)
        if not chunk_ready(chunk_path(config.chunks, *job), config.seed)
    ]


def render_all(config: BuildConfig, progress: Callable[[int], None] = lambda n: None) -> int:
    """Render every pending chunk; ``progress(samples)`` after each. Returns chunks rendered."""
    jobs = pending(config)
    progress(CHUNK * (len(_jobs(config)) - len(jobs)))
    work = [Job(split, k) for split, k in jobs]
    return run_jobs(work, config.chunks, config.seed, config.workers, progress)


@dataclass(frozen=True, slots=True)
class Job:
    """One chunk to render: split, chunk index, spec overrides, file name (default: split)."""

    split: str
    chunk: int
    overrides: tuple[tuple[str, float], ...] = ()
    name: str | None = None


def run_jobs(
    jobs: list[Job],
    folder: Path,
    seed: int,
    workers: int,
    progress: Callable[[int], None] = lambda n: None,
) -> int:
    """Render ``jobs`` in a :class:`~pil.worker_pool.SpawnPool` (Ctrl-C / SIGTERM stop it at
    once; finished chunk files stay); ``progress(samples)`` after each. Returns the chunks
    rendered."""
    if not jobs:
        return 0
    os.environ.setdefault("MUJOCO_GL", "egl")
    pool = SpawnPool(min(workers, len(jobs)))
    from robin_sim.vision.render_set import render_chunk

    done = 0
    try:
        futures: set[Future[int]] = {
            pool.submit(
                render_chunk, folder, seed, job.split, job.chunk, dict(job.overrides), job.name
            )
            for job in jobs
        }
        while futures:
            finished, futures = wait(futures, return_when=FIRST_COMPLETED)
            for future in finished:
                progress(future.result())
                done += 1
    except BaseException:  # an interrupt, a failed chunk: the chunks in flight are not waited for
        pool.stop()
        for partial in folder.glob("*.partial.npz"):  # a chunk killed while being written
            partial.unlink(missing_ok=True)
        raise
    pool.shutdown(wait=True)
    return done


def train_and_report(config: BuildConfig) -> dict[str, object]:
    """Train on the rendered training split, evaluate on the held-out one, write the outputs.

    Writes ``OUT/gesture_model.npz``, ``OUT/report.md``, ``OUT/confusion.png`` and
    ``OUT/measured.json``; returns the headline figures.
    """
    from robin_sim.vision.report import write_report
    from robin_sim.vision.train import evaluate, fit

    train = load_split(config.chunks, "train", config.samples, config.seed)
    heldout = load_split(config.chunks, "heldout", config.heldout, config.seed)
    model = fit(train, seed=config.seed)
    model_path = model.save(config.out / "gesture_model.npz")
    evaluation = evaluate(model, heldout)
    training = evaluate(model, train)
    written = write_report(
        config, model_path, model.threshold, evaluation, training, heldout, train
    )
    return {
        "model": str(model_path),
        "heldout_accuracy": evaluation.accuracy,
        "heldout_discarded": evaluation.discard_rate,
        "heldout_detection_rate": evaluation.detection_rate(),
        "training_accuracy": training.accuracy,
        "written": [str(p) for p in written],
    }
