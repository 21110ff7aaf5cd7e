"""``robin-pil bench``: the gesture-action benchmark (``pil/bench/suite.yaml``; docs/bench.md).

* ``--list``: the tracks, conditions and reference agents of the suite.
* ``--agent SPEC`` (repeatable): run an entrant (a reference name, ``pkg.module:factory`` or
  ``file.py:factory``) with the anchors and the oracle on ``--track`` (default: every track but
  the slow one; ``physical``: the episode in MuJoCo, anchors only) and ``--seeds dev|eval``;
  print its leaderboard rows.
* ``--tune``: tune the reference agents' grids on the dev seeds (``--seeds eval`` is refused).
* ``--leaderboard``: tune on dev, run every reference agent on the eval seeds, write the
  results folder and the Markdown page (``--page``).

Runs are journaled in ``--out`` (``runs.jsonl``): Ctrl-C keeps every finished run and the
same command resumes. MuJoCo is imported only for ``--track physical`` (the slow track,
:mod:`robin_sim.cli.bench_physical`). An entrant's code runs with the user's rights; each call
into it is limited to ``--decision-timeout`` seconds (:mod:`pil.bench.guard`).
"""

from __future__ import annotations

import argparse
import json
import re
import sys
from pathlib import Path
from typing import Any

from pil.bench.guard import DECISION_TIMEOUT, MAX_DECISION_TIMEOUT
from pil.bench.leaderboard import REFERENCE_FOLDER
from pil.numbers import is_whole_text
from robin_sim.cli.options import decimal_number, progress_bar

BENCH_OUT = Path("out/bench")
LEADERBOARD_OUT = Path(REFERENCE_FOLDER)
LEADERBOARD_PAGE = Path("docs/leaderboard.md")


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """The benchmark's options."""
    what = parser.add_mutually_exclusive_group()
    what.add_argument("--list", action="store_true", help="list tracks, conditions and agents")
    what.add_argument("--tune", action="store_true", help="tune the reference agents (dev seeds)")
    what.add_argument(
        "--leaderboard",
        action="store_true",
        help="tune, run every reference agent on the eval seeds, write results and page",
    )
    parser.add_argument(
        "--agent",
        action="append",
        default=None,
        help="an entrant: a reference agent's name, pkg.module:factory or file.py:factory "
        "(repeatable; default: none)",
    )
    parser.add_argument(
        "--track", default=None, help="tracks, comma separated (default: all but the slow one)"
    )
    parser.add_argument("--seeds", default="dev", help="seed block: dev or eval (default: dev)")
    parser.add_argument(
        "--quick", action="store_true", help="the quick tracks: fewer tables, the first 3 seeds"
    )
    parser.add_argument(
        "--tuned",
        type=Path,
        default=None,
        help="tuned.json of a --tune run: reference agents take its parameters (default: none)",
    )
    parser.add_argument("--workers", default=1, help="processes (default: %(default)s)")
    parser.add_argument(
        "--decision-timeout",
        type=decimal_number,
        default=DECISION_TIMEOUT,
        metavar="SECONDS",
        help="the longest an entrant's agent may take for one call (building it, a decision, "
        f"a feedback) before the bench stops, up to {MAX_DECISION_TIMEOUT:g} "
        "(default: %(default)g)",
    )
    parser.add_argument(
        "--out", type=Path, default=None, help=f"results folder (default: {BENCH_OUT})"
    )
    parser.add_argument(
        "--page",
        type=Path,
        default=LEADERBOARD_PAGE,
        help="the leaderboard page --leaderboard writes (default: %(default)s)",
    )
    parser.add_argument(
        "--suite", type=Path, default=None, help="suite file (default: the shipped one)"
    )
    parser.add_argument("--no-progress", action="store_true", help="no progress bar")


def _workers(text: Any) -> int:
    from pil.bench.suite import SuiteError

    value = int(str(text)) if is_whole_text(str(text)) else 0
    if value < 1 or value > 64:
        raise SuiteError(f"--workers: expected a whole number from 1 to 64, got {text!r}")
    return value


def _tracks(suite: Any, text: str | None, slow_allowed: bool = True) -> list[str]:
    if text is None:
        return list(suite.quick_tracks())
    names = [t.strip() for t in text.split(",") if t.strip()]
    for name in names:
        suite.track(name)  # an unknown one names the valid choices
    slow = [n for n in names if suite.track(n).slow]
    if slow and not slow_allowed:
        from pil.bench.suite import SuiteError

        raise SuiteError(
            f"--track {','.join(slow)}: the slow physical track is not part of the reference "
            "leaderboard; run it with --agent NAME --track physical. Valid here: "
            + ", ".join(suite.quick_tracks())
        )
    return names


def _entrants(suite: Any, specs: list[str], tuned: dict[str, Any], seconds: float) -> list[Any]:
    from pil.bench.entrants import REFERENCE
    from pil.bench.guard import check_factory
    from pil.bench.run import Entrant

    out = []
    for spec in specs:
        params = tuned.get(spec, {}).get("params", {}) if spec in REFERENCE else {}
        entrant = Entrant(spec, spec, params)
        check_factory(entrant.factory(), f"--agent {spec}", seconds)
        out.append(entrant)
    return out


def _decision_timeout(seconds: float) -> float:
    from pil.bench.suite import SuiteError

    if not 0 < seconds <= MAX_DECISION_TIMEOUT:
        raise SuiteError(
            f"--decision-timeout: expected seconds above 0 and up to {MAX_DECISION_TIMEOUT:g}, "
            f"got {seconds:g}"
        )
    return seconds


def _read_tuned(suite: Any, path: Path | None) -> dict[str, Any]:
    from pil.bench.tuned import read_tuned

    return {} if path is None else read_tuned(path, suite)


def run(args: argparse.Namespace) -> int:
    """The chosen mode; bad input raises a RobinPilError (exit code 2) before any run."""
    from pil.bench.suite import BLOCKS, SUITE_FILE, SuiteError, load_suite
    from pil.provenance import source_commit

    suite = load_suite(args.suite or SUITE_FILE)
    workers = _workers(args.workers)
    args.decision_timeout = _decision_timeout(args.decision_timeout)
    args.commit = source_commit().label()  # once, as the code was loaded: what every stamp names
    if args.seeds not in BLOCKS:
        raise SuiteError(f"--seeds {args.seeds!r}; valid choices: " + ", ".join(BLOCKS))
    if args.list:
        return _list(suite)
    if args.tune:
        from pil.bench.tuning import check_block

        check_block(args.seeds)
        out = args.out or BENCH_OUT / "tuning"
        _tune(suite, out, args, workers)
        print(f"wrote {out / 'tuned.json'}")
        return 0
    if args.leaderboard:
        args.tracks = _tracks(suite, args.track, slow_allowed=False)
        if not re.fullmatch(r"[0-9a-f]{40}", args.commit):
            raise SuiteError(
                f"--leaderboard names the commit that made it, and the code is at "
                f"{args.commit}: commit your changes first"
            )
        return _leaderboard(suite, args, workers)
    if not args.agent:
        raise SuiteError("give --agent SPEC (or --list, --tune, --leaderboard)")
    tracks = _tracks(suite, args.track)
    tuned = _read_tuned(suite, args.tuned)
    entrants = _entrants(suite, args.agent, tuned, args.decision_timeout)
    return _run_entrants(suite, entrants, tracks, args, workers)


def _list(suite: Any) -> int:
    print(f"{suite.name}, suite version {suite.version}")
    print("tracks:")
    for name, t in suite.tracks.items():
        print(f"  {name:<15} {t.description}{' (slow)' if t.slow else ''}")
    print("conditions: " + ", ".join(suite.conditions))
    print("reference agents: " + ", ".join(suite.agents))
    print(
        f"anchors: {', '.join(suite.anchors)}; seeds: dev {suite.counts['dev']}, "
        f"eval {suite.counts['eval']} (quick: {suite.quick_count})"
    )
    return 0


def _journal(out: Path, suite: Any, block: str, args: Any) -> Any:
    """The results folder's journal; what a damaged last line lost is said on stderr."""
    from pil.bench.journal import Journal

    journal = Journal(out, suite, block, args.quick, args.commit)
    if journal.dropped:
        print(f"robin-pil bench: {journal.dropped}", file=sys.stderr)
    return journal


def _run_entrants(
    suite: Any, entrants: list[Any], tracks: list[str], args: Any, workers: int
) -> int:
    from pil.bench.analysis import ORACLE
    from pil.bench.leaderboard import row_line
    from pil.bench.results import analyse, write_results
    from pil.bench.run import Entrant, plan, run_bench

    out = args.out or BENCH_OUT
    journal = _journal(out, suite, args.seeds, args)
    names = {e.name for e in entrants}
    references = [Entrant(n, n) for n in (*suite.anchors, ORACLE) if n not in names]
    everyone = [*entrants, *references]
    seeds = suite.seeds(args.seeds, args.quick)
    learner_only = [t for t in tracks if not suite.track(t).slow]
    slow = [t for t in tracks if suite.track(t).slow]
    anchored = [e for e in everyone if e.name != ORACLE]  # the oracle needs the symbolic world
    total = len(plan(suite, everyone, learner_only, seeds, args.quick))
    total += len(plan(suite, anchored, slow, seeds, args.quick))
    with progress_bar(total, "bench", args) as bar:
        rows = run_bench(
            suite,
            everyone,
            learner_only,
            journal,
            seeds,
            workers=workers,
            progress=bar.update,
            decision_timeout=args.decision_timeout,
        )
        if slow:
            from robin_sim.cli.bench_physical import run_physical_track  # MuJoCo: the slow track

            rows += run_bench(
                suite,
                anchored,
                slow,
                journal,
                seeds,
                progress=bar.update,
                runner=run_physical_track,
                decision_timeout=args.decision_timeout,
            )
    write_results(suite, out)
    found = analyse(suite, rows, args.quick)
    for track in tracks:
        for entrant in entrants:
            print(row_line(suite, found, track, entrant.name))
    print(
        f"results in {out} (suite {suite.version}, {args.seeds} seeds, commit "
        f"{journal.stamp['commit']})"
    )
    return 0


def _tune(suite: Any, out: Path, args: Any, workers: int) -> dict[str, Any]:
    from pil.atomic import write_text_atomic
    from pil.bench.tuning import TUNING_BLOCK, tune

    journal = _journal(out, suite, TUNING_BLOCK, args)
    found = {}
    with progress_bar(None, "tuning", args) as bar:  # type: ignore[arg-type]
        for agent in suite.grids:
            found[agent] = tune(
                suite, agent, journal, quick=args.quick, workers=workers, progress=bar.update
            )
    tuned = {a: {k: v for k, v in t.items() if k != "scores"} for a, t in found.items()}
    write_text_atomic(out / "tuned.json", json.dumps(tuned, indent=1, sort_keys=True) + "\n")
    from pil.bench.results import csv_text

    scores = [s for t in found.values() for s in t["scores"]]
    write_text_atomic(out / "tuning.csv", csv_text(scores, ("agent", "params", "score", "chosen")))
    return tuned


def _leaderboard(suite: Any, args: Any, workers: int) -> int:
    import shutil

    from pil.atomic import write_text_atomic
    from pil.bench.leaderboard import render
    from pil.bench.results import write_results
    from pil.bench.run import Entrant

    out = args.out or LEADERBOARD_OUT
    tracks = args.tracks
    tuned = _tune(suite, out / "tuning", args, workers)
    out.mkdir(parents=True, exist_ok=True)
    shutil.copyfile(out / "tuning" / "tuned.json", out / "tuned.json")
    entrants = [Entrant(a, a, tuned.get(a, {}).get("params", {})) for a in suite.agents]
    from pil.bench.run import plan, run_bench

    journal = _journal(out, suite, "eval", args)
    seeds = suite.seeds("eval", args.quick)
    with progress_bar(
        len(plan(suite, entrants, tracks, seeds, args.quick)), "leaderboard", args
    ) as bar:
        run_bench(suite, entrants, tracks, journal, seeds, workers=workers, progress=bar.update)
    written = write_results(suite, out)
    page = write_text_atomic(args.page, render(suite, out, source=out.as_posix()))
    print("wrote " + ", ".join(str(p) for p in [*written, page]))
    return 0
