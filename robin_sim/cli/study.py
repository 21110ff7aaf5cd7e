"""``robin-pil study``: the paper's learner-only study (section IV-B); never imports MuJoCo.

Writes ``runs.csv`` (one row per run), ``tests.csv`` (paired tests of PIL against every other
system), ``summary.md`` (mean ± sd, training figures next to the paper's, the paper's claim,
the tests) and ``gestures.png``, ``actions.png``, ``training.png``. Each finished repetition is
kept in ``reps.jsonl`` as it ends (:mod:`pil.experiments.rep_journal`): an interrupted study
(Ctrl-C, SIGTERM) resumes from it when run again, to the same files. With ``--seeds K`` it runs
K such studies into ``OUT/seed_<n>/`` and writes their headlines over seeds
(:mod:`pil.experiments.study_seeds`).
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path
from typing import Any

from pil.errors import RobinPilError
from pil.experiments.paper import PAPER_REPS
from pil.exploration import DEFAULT_RULE, RULES
from pil.step_memory import DEFAULT_STEP_MEMORY, STEP_MEMORY
from pil.task.detector import EXACT
from robin_sim.cli.options import RATES_LABEL, add_progress_switch, systems_help, whole_number

DEFAULT_OUT = Path("out/study")


def _refuse_rates_of_measured(config: Any, given: str | None) -> None:
    """``--rates`` with ``--detector measured:FILE``: refused, the file sets the rate (the
    detector as the config parsed it, once; its file as then read)."""
    from pil.task.detector import MEASURED_PREFIX, load_measured

    model = config.base.detector.model
    if given is not None and model.startswith(MEASURED_PREFIX):
        errors = load_measured(model[len(MEASURED_PREFIX) :])
        raise RobinPilError(
            f"--rates cannot be combined with --detector {model}: the file sets the "
            f"detection rate (measured d = {errors.rate:.3f}); drop --rates"
        )


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """The study's options (defaults: the paper's setup)."""
    parser.add_argument(
        "--rates",
        default=None,
        help="detection rates in (0, 1], comma separated (default: the paper's rates; with "
        "--detector measured:FILE the file's measured rate)",
    )
    parser.add_argument(
        "--reps",
        type=whole_number,
        default=PAPER_REPS,
        help="repetitions per rate and system (default: %(default)s)",
    )
    parser.add_argument(
        "--tables",
        default=None,
        help="test tables per run (default: the scenario's, 10 in the paper's setup)",
    )
    parser.add_argument("--seed", default=0, help="master seed, >= 0 (default: %(default)s)")
    parser.add_argument(
        "--seeds",
        default="1",
        help="independent studies to run, master seeds SEED .. SEED+K-1, each in OUT/seed_<n>/, "
        "reported over seeds in OUT/summary.md and OUT/seeds.csv; a finished seed folder is "
        "reused (default: %(default)s: one study in OUT)",
    )
    parser.add_argument(
        "--out", type=Path, default=DEFAULT_OUT, help="output folder (default: %(default)s)"
    )
    parser.add_argument(
        "--detector",
        default=EXACT,
        help="detection model: exact, independent, or measured:FILE (a measured confusion "
        "matrix and discard rate, e.g. the measured.json of robin-pil train-gestures) "
        "(default: %(default)s)",
    )
    parser.add_argument(
        "--scenario", default=None, help="assembly scenario YAML (default: scenarios/assembly.yaml)"
    )
    parser.add_argument(
        "--exploration",
        default=DEFAULT_RULE,
        choices=tuple(RULES),
        help="the learner's rule after a not-OK (default: %(default)s; see pil.exploration)",
    )
    parser.add_argument(
        "--step-memory",
        default=DEFAULT_STEP_MEMORY,
        choices=tuple(STEP_MEMORY),
        help="within-step memory of every learner: on (a refused action is not tried again in "
        "the step until all five were refused), off, or per-learner (off for PIL, on for "
        "bandit and tamer) (default: %(default)s; see pil.step_memory)",
    )
    parser.add_argument(
        "--discarded",
        default="repeated",
        choices=("repeated", "corrected"),
        help="a discarded gesture: the person repeats it, or the learner corrects it as an "
        "invalid one (default: %(default)s)",
    )
    parser.add_argument(
        "--systems",
        default=None,
        help=systems_help("the paper's pil,c1,c2,c3,c4"),
    )
    add_progress_switch(parser)


def run(args: argparse.Namespace) -> int:
    """Run the study and write its outputs; bad input raises a RobinPilError (exit code 2)."""
    from tqdm import tqdm

    from pil.experiments.rep_journal import RepJournal, report_journal
    from pil.experiments.study import (
        DETECTOR_RATES,
        StudyConfig,
        journal_settings,
        run_study,
        write_outputs,
    )
    from pil.outdir import claimed_out_dir
    from pil.task.systems import PAPER_SYSTEMS

    params = {
        "tables": args.tables,
        "detector": args.detector,
        "exploration": args.exploration,
        "repeat_discarded": args.discarded == "repeated",
        "step_memory": args.step_memory,
    }
    # as given: parsed once, by the study's config
    given = None if args.systems is None else args.systems.split(",")
    systems = PAPER_SYSTEMS if given is None else tuple(name.strip() for name in given)
    config = StudyConfig(
        systems=systems,
        # as given: parsed once, by the study's config (the RATE spec; none given: the
        # paper's rates, or a measured detector's own)
        rates=DETECTOR_RATES if args.rates is None else tuple(args.rates.split(",")),
        reps=args.reps,
        seed=args.seed,
        scenario=args.scenario,  # a bad file: refused now, by the config (parsed once)
        params=params,
        labels={
            "tables": "--tables",
            "scenario": "--scenario",
            "rate": RATES_LABEL,
            "detector": "--detector",
            "reps": "--reps",
            "seed": "--seed",
            "system": "--systems: system",
        },
    )
    _refuse_rates_of_measured(config, args.rates)
    count = _seed_count(args.seeds)
    # before the computation; the folder stays locked until the files are written
    with claimed_out_dir(args.out):
        if count > 1:
            from pil.experiments.study_seeds import check_seeds, run_study_seeds

            check_seeds(config, count, args.out)
            with tqdm(
                total=config.runs() * count,
                desc="study",
                unit="run",
                file=sys.stderr,
                disable=args.no_progress,
            ) as bar:
                written = run_study_seeds(config, count, args.out, progress=bar.update)
            print(
                f"{count} studies of {config.runs()} runs; wrote "
                + ", ".join(str(p) for p in written)
            )
            return 0
        journal = RepJournal(args.out, journal_settings(config))  # finished reps: kept
        report_journal("study", journal)
        with tqdm(
            total=config.runs(), desc="study", unit="run", file=sys.stderr, disable=args.no_progress
        ) as bar:
            rows = run_study(config, progress=bar.update, journal=journal)
        written = write_outputs(rows, config, args.out)
    print(f"{len(rows)} runs; wrote " + ", ".join(str(p) for p in written))
    return 0


def _seed_count(text: str) -> int:
    """``--seeds`` as a whole number of studies."""
    from pil.experiments.over_seeds import MAX_SEEDS, check_seed_count

    try:
        count = int(str(text).strip())
    except ValueError:
        raise RobinPilError(
            f"--seeds must be a whole number from 1 to {MAX_SEEDS}, got {text!r}"
        ) from None
    return check_seed_count(count)
