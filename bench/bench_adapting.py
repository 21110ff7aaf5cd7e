"""The cost of adapting the eye cameras' gesture model to a person (``--adapt``).

Run: ``python bench/bench_adapting.py [--repeats 20]``.
Prints the median milliseconds of: classifying one reading (two eye rows) with the shipped
model (the baseline, measured in the same run) and with the adapted one, and one refit of the
adapted output layer after an approval, for a person with 50, 200 and about 600 eye rows learnt
(the most kept). Rows are the shipped model's feature means plus noise, labelled as the shipped
model reads them but for one in five relabelled at random.
"""

from __future__ import annotations

import argparse
import statistics
import time

import numpy as np
import smoke  # bench/smoke.py: --smoke

from robin_sim.vision.adapting import MAX_EYE_ROWS, AdaptedModel
from robin_sim.vision.classifier import CLASSES, load_shipped


def _median_ms(action, repeats: int) -> float:  # type: ignore[no-untyped-def]
    times = []
    for _ in range(repeats):
        started = time.perf_counter()
        action()
        times.append((time.perf_counter() - started) * 1000)
    return statistics.median(times)


def _approval_ms(adapted: AdaptedModel, new: np.ndarray, repeats: int) -> float:
    """Median ms of learning one more approval (two eye rows), the model restored after each
    so every repeat starts from the same ``size`` rows."""
    times = []
    for k in range(repeats):
        weights, bias, size = adapted.weights.copy(), adapted.bias.copy(), adapted.size
        started = time.perf_counter()
        adapted.learn(new[2 * k : 2 * k + 2], CLASSES[k % len(CLASSES)])
        times.append((time.perf_counter() - started) * 1000)
        adapted.weights, adapted.bias = weights, bias
        del adapted.rows[size:], adapted.labels[size:]
    return statistics.median(times)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=20)
    args = smoke.parse_args(parser, repeats=2)
    model = load_shipped()
    rng = np.random.default_rng(0)
    reading = model.mean + rng.normal(0, 1, (2, model.mean.size)) * model.scale
    baseline = _median_ms(lambda: model.probabilities(reading), args.repeats * 10)
    rows = [("classify, shipped model (baseline)", baseline)]
    for size in (50, 200, MAX_EYE_ROWS - 2):
        adapted = AdaptedModel(model)
        examples = model.mean + rng.normal(0, 1, (size, model.mean.size)) * model.scale
        # a person the model mostly reads right: their confirmed labels are its own readings,
        # but for one row in five, relabelled (what adaptation is for)
        labels = model.probabilities(examples).argmax(axis=1)
        flip = rng.random(size) < 0.2
        labels[flip] = rng.integers(0, len(CLASSES), int(flip.sum()))
        for k in range(0, size, 2):  # as approvals come: two eye rows each
            adapted.learn(examples[k : k + 2], CLASSES[labels[k]])
        classify = adapted.probabilities
        rows.append(
            (
                f"classify, adapted ({size} rows)",
                _median_ms(lambda c=classify: c(reading), args.repeats * 10),
            )
        )
        new = model.mean + rng.normal(0, 1, (2 * args.repeats, model.mean.size)) * model.scale
        rows.append(
            (f"one approval learnt ({size} rows)", _approval_ms(adapted, new, args.repeats))
        )
    print(f"adapting the gesture model, medians of {args.repeats}+ repeats")
    print(f"{'what':<40}{'ms':>10}{'x baseline':>12}")
    for name, ms in rows:
        print(f"{name:<40}{ms:>10.3f}{ms / baseline:>12.1f}")


if __name__ == "__main__":
    main()
