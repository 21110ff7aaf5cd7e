"""``robin-pil study-status DIR``: who ran, what is left, what is unfinished, who comes next."""

from __future__ import annotations

import argparse
from pathlib import Path


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """The command's options."""
    parser.add_argument("dir", type=Path, metavar="DIR", help="the study folder")
    parser.add_argument(
        "--json", action="store_true", help="print the state as JSON instead of tables"
    )


def run(args: argparse.Namespace) -> int:
    """Print the study's state."""
    import json

    from robin_sim.lab.state import state_text, study_state
    from robin_sim.lab.study_file import load_study

    state = study_state(load_study(args.dir))
    print(
        json.dumps(state, indent=2) if args.json else state_text(state),
        end="\n" if args.json else "",
    )
    return 0
