"""``robin-pil study-init DIR``: a new study folder, its study file and a protocol to edit."""

from __future__ import annotations

import argparse
from pathlib import Path


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """The command's options."""
    from robin_sim.lab.study_file import DESIGNS

    parser.add_argument("dir", type=Path, metavar="DIR", help="the new study folder")
    parser.add_argument(
        "--protocol",
        default=None,
        help="a protocol file (copied into DIR) or a shipped protocol's name (default: a small "
        "protocol.yaml of two conditions, written into DIR)",
    )
    parser.add_argument(
        "--design",
        default="within",
        help=f"the design, one of {', '.join(DESIGNS)} (default: %(default)s)",
    )


def run(args: argparse.Namespace) -> int:
    """Write the folder, check it, say what comes next."""
    from robin_sim.lab.template import init_study

    study = init_study(args.dir, args.protocol, args.design)
    protocol = Path(study.protocol.source)
    wrote = [str(study.source)] + ([str(protocol)] if protocol.parent == study.folder else [])
    print(f"robin-pil study-init: wrote {' and '.join(wrote)} (design {study.design})")
    print(f"next: edit them, then robin-pil live --study {args.dir}")
    return 0
