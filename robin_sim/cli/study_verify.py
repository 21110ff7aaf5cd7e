"""``robin-pil study-verify ARCHIVE``: every file of a study archive checked against its
manifest (exit 2, naming each file that is missing, changed or not listed)."""

from __future__ import annotations

import argparse
from pathlib import Path


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """The command's options."""
    parser.add_argument(
        "archive", type=Path, metavar="ARCHIVE", help="a .zip written by robin-pil study-export"
    )


def run(args: argparse.Namespace) -> int:
    """Check the archive; say what it holds."""
    from robin_sim.lab.archive import verify_archive

    body = verify_archive(args.archive)
    commit = body["robin_pil"]["commit"]["id"] or "no git checkout"
    print(
        f"robin-pil study-verify: {args.archive}: {len(body['files'])} files match the "
        f"manifest (study {body['study']}, robin-pil {body['robin_pil']['version']}, "
        f"commit {commit})"
    )
    return 0
