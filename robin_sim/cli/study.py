"""``robin-pil study``: the paper's learner-only study (section IV-B); never imports MuJoCo.

Writes ``runs.csv`` (one row per run), ``summary.md`` (mean ± sd, training figures next to
the paper's, Welch t-tests) and ``gestures.png``, ``actions.png``, ``training.png``.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

DEFAULT_OUT = Path("out/study")


def _rates(text: str) -> tuple[float, ...]:
    """``"0.4,0.6"`` as rates (the sweep's list rules and the rate spec); errors name the range."""
    from pil.experiments.sweep_grid import split_list
    from pil.task.params import RATE

    return tuple(RATE.parse(part, "--rates") for part in split_list(text, "--rates"))


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """The study's options (defaults: the paper's setup)."""
    parser.add_argument(
        "--rates",
        default="0.4,0.6,0.8,1.0",
        help="detection rates in [0, 1], comma separated (default: %(default)s)",
    )
    parser.add_argument(
        "--reps",
        default=20,
        help="repetitions per rate and system (default: %(default)s)",
    )
    parser.add_argument(
        "--tables",
        default=None,
        help="test tables per run (default: the scenario's, 10 in the paper's setup)",
    )
    parser.add_argument("--seed", default=0, help="master seed, >= 0 (default: %(default)s)")
    parser.add_argument(
        "--out", type=Path, default=DEFAULT_OUT, help="output folder (default: %(default)s)"
    )
    parser.add_argument(
        "--detector",
        default="exact",
        choices=("exact", "independent"),
        help="detection model (default: %(default)s)",
    )
    parser.add_argument(
        "--scenario", default=None, help="assembly scenario YAML (default: scenarios/assembly.yaml)"
    )
    parser.add_argument("--no-progress", action="store_true", help="no progress bar")  # fmt: skip


def run(args: argparse.Namespace) -> int:
    """Run the study and write its outputs; bad input raises a RobinPilError (exit code 2)."""
    from tqdm import tqdm

    from pil.experiments.study import StudyConfig, run_study, write_outputs
    from pil.experiments.systems import check_params, resolve_scenario
    from pil.outdir import check_out_dir
    from pil.task.params import ASSEMBLY, REPS, SEED

    params = {
        "tables": ASSEMBLY["tables"].parse(args.tables, "--tables"),
        "detector": args.detector,
    }
    config = StudyConfig(
        rates=_rates(args.rates),
        reps=REPS.parse(args.reps, "--reps"),
        seed=SEED.parse(args.seed, "--seed"),
        scenario=resolve_scenario(args.scenario, check_params(params)),  # a bad file: refused now
        params=params,
    )
    check_out_dir(args.out)  # before hours of computing, not after
    with tqdm(total=config.runs(), desc="study", unit="run", file=sys.stderr,
              disable=args.no_progress) as bar:  # fmt: skip
        rows = run_study(config, progress=bar.update)
    written = write_outputs(rows, config, args.out)
    print(f"{len(rows)} runs; wrote " + ", ".join(str(p) for p in written))
    return 0
