"""The ``robin-pil`` command: ``study``, ``episode``, ``sweep``, ``report`` and the others.

Each subcommand lives in its own module exposing ``add_arguments(parser)`` and
``run(args) -> int``; modules are imported only when their command is chosen, so
``robin-pil study`` never loads MuJoCo. This module imports only ``sys`` at the top, so that
:func:`main` notes a Ctrl-C as early as it can (see :func:`main`).
"""

from __future__ import annotations

import sys
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    import argparse

    from pil.signal_policy import CommandSignals

# command -> (module, one-line help)
COMMANDS: dict[str, tuple[str, str]] = {
    "study": ("robin_sim.cli.study", "the paper's simulation study (learner only)"),
    "episode": ("robin_sim.cli.episode", "one physical episode rendered headless to MP4"),
    "baselines": (
        "robin_sim.cli.baselines",
        "bandit and TAMER tuned on held-out seeds, paired tests against PIL (learner only)",
    ),
    "sweep": ("robin_sim.cli.sweep", "a resumable grid of runs, local pool or Dask cluster"),
    "report": ("robin_sim.cli.report", "summary, t-tests, figures: a results CSV or live sessions"),
    "model-path": ("robin_sim.cli.model_path", "print where the MJCF model files are installed"),
    "adapt": ("robin_sim.cli.adapt", "a gesture's meaning changes mid-task (learner only)"),
    "transfer": ("robin_sim.cli.transfer", "a second task from scratch vs from saved tables"),
    "people": ("robin_sim.cli.people", "two people's mappings: one shared table vs one each"),
    "train-gestures": (
        "robin_sim.cli.train_gestures",
        "render the gesture data set, train the eye-camera gesture model, report",
    ),
    "vision-conditions": (
        "robin_sim.cli.vision_conditions",
        "measured detection rate per camera condition (light x noise) and PIL's costs",
    ),
    "live": ("robin_sim.cli.live", "a browser page: a live person gestures, Robin learns"),
    "replay": ("robin_sim.cli.replay", "re-render a recorded episode or live session to MP4"),
    "study-init": ("robin_sim.cli.study_init", "a new study folder: study file and protocol"),
    "study-status": (
        "robin_sim.cli.study_status",
        "a study's state: who ran, what is left, what is unfinished",
    ),
    "study-withdraw": (
        "robin_sim.cli.study_withdraw",
        "withdraw a participant: marked in the registry, left out of the analysis",
    ),
    "study-export": (
        "robin_sim.cli.study_export",
        "a study's CSVs (trials, wide, long) and its archive with a manifest",
    ),
    "study-verify": ("robin_sim.cli.study_verify", "check a study archive against its manifest"),
}


def build_parser(command: str | None = None) -> argparse.ArgumentParser:
    """The top-level parser; ``command``'s own options are added (its module imported)."""
    import argparse
    import importlib

    from robin_sim.cli.help_format import DefaultsHelpFormatter, package_version

    parser = argparse.ArgumentParser(
        prog="robin-pil",
        description="Robin learns which action each hand gesture means (Proactive Incremental "
        "Learning), in a learner-only study or physically in MuJoCo.",
        epilog="Start with: robin-pil episode (one handover table, video in out/). "
        "Each command's options: robin-pil COMMAND --help.",
        formatter_class=DefaultsHelpFormatter,
    )
    parser.add_argument("--version", action="version", version=f"%(prog)s {package_version()}")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND", title="commands")
    for name, (module_name, help_text) in COMMANDS.items():
        sub_parser = sub.add_parser(
            name, help=help_text, description=help_text, formatter_class=DefaultsHelpFormatter
        )
        if name == command:
            module = importlib.import_module(module_name)
            module.add_arguments(sub_parser)
            sub_parser.set_defaults(_module=module)
    return parser


def main(argv: list[str] | None = None, *, exiting: bool | None = None) -> int:
    """Entry point; bad input, and a file that cannot be written (full disk), end with one clear
    message and exit code 2, Ctrl-C and SIGTERM with 130.

    From its first line SIGINT and SIGTERM follow one policy, whatever disposition the process
    inherited (:class:`pil.signal_policy.CommandSignals`): noted while the command's modules
    import and its options parse (the command then ends with 130 before it starts), raised as
    ``KeyboardInterrupt`` once while it runs (its finished work is kept), ignored in teardown.
    A command whose module sets ``HOLDS_SIGNALS`` (the episode) keeps them noted while it runs
    and acts on them itself once its files are open. ``exiting`` (default: no ``argv`` given,
    i.e. the ``robin-pil`` entry point) says the process ends with the command; otherwise
    (a command run from Python) the signal handlers found are put back when it returns.
    """
    from pil.signal_policy import INTERRUPTED, CommandSignals  # imports nothing heavy

    policy = CommandSignals().install()
    exiting = argv is None if exiting is None else exiting
    try:
        argv = sys.argv[1:] if argv is None else list(argv)
        command = next((arg for arg in argv if not arg.startswith("-")), None)
        parser = build_parser(command if command in COMMANDS else None)
        args = parser.parse_args(argv)
        if args.command is None:  # bare robin-pil: the command list, as a missing argument
            parser.print_help(sys.stderr)
            return 2
        holding = bool(getattr(args._module, "HOLDS_SIGNALS", False))
        if policy.requested is not None and not holding:  # nothing started yet
            print(f"robin-pil {command}: interrupted before starting", file=sys.stderr)
            return INTERRUPTED
        return _run(args, policy, holding)
    finally:
        policy.finish(exiting)  # teardown: a late signal no longer changes the exit code


def _run(args: argparse.Namespace, policy: CommandSignals, holding: bool) -> int:
    """Run the chosen command: its exit code, 2 for bad input, 130 for Ctrl-C or SIGTERM."""
    from pil.errors import RobinPilError, os_error_line
    from pil.signal_policy import INTERRUPTED

    try:
        with policy.running(holding=holding):
            return int(args._module.run(args) or 0)
    except RobinPilError as error:
        print(f"robin-pil {args.command}: error: {error}", file=sys.stderr)
        return 2
    except OSError as error:  # a full disk, a too-long name, a folder made read-only mid-run
        print(f"robin-pil {args.command}: error: {os_error_line(error)}", file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        print(f"robin-pil {args.command}: interrupted; finished work is kept", file=sys.stderr)
        return INTERRUPTED


if __name__ == "__main__":
    sys.exit(main())
