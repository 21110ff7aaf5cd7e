"""``robin-pil train-gestures``: render the gesture data set, train the model, report.

Writes under ``--out`` (default ``out/gestures``): ``chunks/`` (the rendered data set, kept so
that an interrupted run resumes; with ``--cache DIR`` it is kept under ``DIR`` by its render
key instead, :mod:`robin_sim.vision.render_key`), ``gesture_model.npz``, ``report.md``,
``confusion.png`` and ``measured.json`` (the error model for
``robin-pil study --detector measured:FILE``).
``--install`` also copies the model, its report, figure and measured error model into the
package (``robin_sim/vision/data``: what episodes read).
"""

from __future__ import annotations

import argparse
import json
import shutil
import sys
from pathlib import Path

from pil.file_names import MEASURED_NAME
from robin_sim.cli.options import add_progress_switch, whole_number


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """The command's options."""
    from robin_sim.vision.build_config import DEFAULT_SAMPLES

    parser.add_argument(
        "--samples",
        type=whole_number,
        default=DEFAULT_SAMPLES,
        help="training samples (held-out: a third as many) (default: %(default)s)",
    )
    parser.add_argument("--seed", type=whole_number, default=0, help="seed (default: %(default)s)")
    parser.add_argument("--out", type=Path, default=Path("out/gestures"), help="output folder")
    parser.add_argument(
        "--workers",
        type=whole_number,
        default=None,
        help="render processes, at most the CPU count (default: 2, or the CPU count if less)",
    )
    parser.add_argument(
        "--cache",
        type=Path,
        default=None,
        help="render cache root: the data set is kept under its render key and reused while "
        "the scene, poses, cameras and sample spec are unchanged (default: OUT/chunks)",
    )
    parser.add_argument(
        "--install",
        action="store_true",
        help="copy the model, report and measured error model into the package",
    )
    add_progress_switch(parser)


def run(args: argparse.Namespace) -> int:
    """Render (resuming), train and report; bad input raises a RobinPilError (exit 2)."""
    from tqdm import tqdm

    from pil.outdir import claimed_out_dir
    from robin_sim.vision.build import render_all, train_and_report
    from robin_sim.vision.build_config import BuildConfig, default_build_workers
    from robin_sim.vision.classifier import shipped_path

    workers = default_build_workers() if args.workers is None else args.workers
    config = BuildConfig(
        samples=args.samples, seed=args.seed, out=args.out, workers=workers, cache=args.cache
    )
    total = config.samples + config.heldout
    with claimed_out_dir(config.out):  # unwritable, too long a name, in use: refused here
        with tqdm(
            total=total, desc="render", unit="sample", file=sys.stderr, disable=args.no_progress
        ) as bar:
            render_all(config, progress=lambda n: bar.update(min(n, total - bar.n)))
        result = train_and_report(config)
    if args.install:
        folder = shipped_path().parent
        for name in (shipped_path().name, "report.md", "confusion.png", MEASURED_NAME):
            shutil.copyfile(config.out / name, folder / name)
        result["installed"] = str(folder)
    print(json.dumps(result, indent=2))
    return 0
