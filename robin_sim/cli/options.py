"""Options shared by the learner-only study commands (adapt, transfer, people), and the
parsing of ``--rates`` and ``--systems`` lists; each check raises before anything runs."""

from __future__ import annotations

import argparse
from collections.abc import Callable, Sequence
from pathlib import Path
from typing import Any

from pil.errors import RobinPilError, quote
from pil.experiments.paper import PAPER_REPS
from pil.numbers import parse_decimal, parse_whole

RATES_LABEL = "--rates: each detection rate (comma separated)"  # names a bad one


def whole_number(text: str) -> int:
    """An option's whole number in ASCII digits (argparse's ``type``: ``"1_0"`` or ``"٣"``
    are refused with exit code 2, not read as 10 and 3)."""
    try:
        return parse_whole(text)
    except ValueError as error:
        raise argparse.ArgumentTypeError(str(error)) from None


def decimal_number(text: str) -> float:
    """An option's number in ASCII (argparse's ``type``; see :mod:`pil.numbers`)."""
    try:
        return parse_decimal(text)
    except ValueError as error:
        raise argparse.ArgumentTypeError(str(error)) from None


def parse_rates(text: str) -> tuple[float, ...]:
    """``"0.4,0.6"`` as rates, each checked by the one rate spec (:data:`pil.task.params.RATE`);
    a bad one raises naming the valid range and the value given."""
    from pil.task.params import RATE

    rates: list[float] = []
    for part in text.split(","):
        rate = RATE.parse(part, RATES_LABEL)
        if rate in rates:
            raise RobinPilError(
                f"--rates: rate {rate:g} is given twice; give each rate once, e.g. 0.4,0.6,0.8,1.0"
            )
        rates.append(rate)
    return tuple(rates)


def parse_systems(text: str) -> tuple[str, ...]:
    """``"pil,bandit"`` as system names; an unknown or repeated one raises listing them."""
    from pil.errors import InvalidChoiceError
    from pil.task.systems import SYSTEMS

    names = tuple(part.strip() for part in text.split(","))
    for name in names:
        if name not in SYSTEMS:
            raise InvalidChoiceError("--systems: system", name, SYSTEMS)
        if names.count(name) > 1:
            raise RobinPilError(f"--systems: system {name!r} is given twice; give each once")
    return names


def systems_help(default: str, accepts: Sequence[str] | None = None) -> str:
    """The help of a ``--systems`` option: ``default`` and every system it accepts (``accepts``;
    by default every system of the registry)."""
    from pil.task.systems import SYSTEMS

    names = ", ".join(SYSTEMS if accepts is None else accepts)
    return f"comma-separated systems (default: {default}); any of {names}"


def add_run_options(
    parser: argparse.ArgumentParser,
    *,
    rates: str,
    out: Path,
    systems: Sequence[str],
    accepts: Sequence[str] | None = None,
    reps_help: str | None = None,
) -> None:
    """``--systems`` (``systems`` by default, ``accepts`` the valid choices: every system if
    None), ``--rates``, ``--reps``, ``--seed``, ``--seeds``, ``--out`` and ``--no-progress``;
    with ``reps_help`` ``--reps`` defaults to None (the command picks it) and says so."""
    parser.add_argument("--systems", default=None, help=systems_help(",".join(systems), accepts))
    parser.add_argument("--rates", default=rates, help="detection rates (default: %(default)s)")
    parser.add_argument(
        "--reps",
        type=whole_number,
        default=None if reps_help else PAPER_REPS,
        help=reps_help or "repetitions (default: %(default)s)",
    )
    parser.add_argument(
        "--seed", type=whole_number, default=0, help="master seed (default: %(default)s)"
    )
    parser.add_argument(
        "--seeds",
        type=whole_number,
        default=1,
        help="independent studies, master seeds SEED .. SEED+K-1, each in OUT/seed_<n>/, their "
        "comparisons over seeds in OUT/seeds.md and OUT/seeds_tests.csv; a finished seed "
        "folder is reused (default: %(default)s: one study in OUT)",
    )
    parser.add_argument(
        "--out", type=Path, default=out, help="output folder (default: %(default)s)"
    )
    add_progress_switch(parser)


def add_progress_switch(parser: argparse._ActionsContainer) -> None:
    """``--no-progress`` (every command's name for it), and ``--quiet``, its old name in some
    commands, kept as a hidden alias; ``parser`` is a parser or one of its argument groups."""
    parser.add_argument(
        "--no-progress", dest="no_progress", action="store_true", help="no progress bar"
    )
    parser.add_argument("--quiet", dest="no_progress", action="store_true", help=argparse.SUPPRESS)


def run_options(
    args: argparse.Namespace, systems: Sequence[str], *, only: Sequence[str] | None = None
) -> tuple[tuple[float, ...], tuple[str, ...]]:
    """The checked rates and systems (``systems`` by default; ``only`` limits the choice)."""
    if args.seed < 0:
        raise RobinPilError(f"--seed must be a whole number >= 0, got {args.seed}")
    if args.reps < 1:
        raise RobinPilError(f"--reps must be >= 1, got {args.reps}")
    from pil.experiments.over_seeds import check_seed_count

    check_seed_count(args.seeds)
    rates = parse_rates(args.rates)
    chosen = tuple(systems) if args.systems is None else parse_systems(args.systems)
    for system in chosen:
        if only is not None and system not in only:
            valid = ", ".join(repr(s) for s in only)
            raise RobinPilError(
                f"--systems: this study runs PIL learners; {system!r} is not "
                f"one (valid choices: {valid})"
            )
    return rates, chosen


def progress_bar(total: int, desc: str, args: argparse.Namespace) -> Any:
    """A tqdm bar on stderr (off with ``--no-progress``)."""
    import sys

    from tqdm import tqdm

    return tqdm(total=total, desc=desc, unit="run", file=sys.stderr, disable=args.no_progress)


def run_seed_studies(
    args: argparse.Namespace,
    name: str,
    settings: dict[str, Any],
    run_one: Callable[[int, Callable[[int], object]], list[dict[str, Any]]],
    write_one: Callable[[int, list[dict[str, Any]], Path], object],
    *,
    within: Sequence[str],
    title: str,
    runs_per_seed: int,
) -> int:
    """``--seeds K`` of a small study: K studies in ``OUT/seed_<n>/`` (``run_one(seed,
    progress)`` then ``write_one(seed, rows, folder)``; a finished folder is reused) and their
    comparisons over seeds; the settings of an existing folder are checked before anything
    runs."""
    from pil.experiments.over_seeds import check_seed_folders, run_seeds, write_tests_over_seeds

    seeds = list(range(args.seed, args.seed + args.seeds))
    check_seed_folders(args.out, seeds, settings)
    with progress_bar(runs_per_seed * len(seeds), name, args) as bar:
        run_seeds(
            args.out,
            seeds,
            settings,
            f"{name}.csv",
            lambda seed: run_one(seed, bar.update),
            write_one,
            skipped=lambda _seed: bar.update(runs_per_seed),
        )
    written = write_tests_over_seeds(args.out, seeds, within, title)
    print(f"{len(seeds)} studies; wrote " + ", ".join(str(p) for p in written))
    return 0


def parse_port(text: str) -> int:
    """``--port`` as a whole number in [0, 65535]."""
    try:
        port = int(str(text).strip())
    except ValueError:
        raise RobinPilError(
            f"--port must be a whole number from 1 to 65535 (0: any free port), got {quote(text)}"
        ) from None
    if not 0 <= port <= 65535:
        raise RobinPilError(f"--port must lie from 1 to 65535 (0: any free port), got {port}")
    return port
