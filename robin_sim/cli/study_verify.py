"""``robin-pil study-verify ARCHIVE ...``: every file of a study archive checked against its
manifest (exit 2, naming each file that is missing, changed or not listed)."""

from __future__ import annotations

import argparse
from pathlib import Path


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """The command's options."""
    parser.add_argument(
        "archives",
        type=Path,
        nargs="+",
        metavar="ARCHIVE",
        help="one or more .zip files written by robin-pil study-export",
    )


def run(args: argparse.Namespace) -> int:
    """Check each archive (all of them, before a mismatch is reported); say what each holds."""
    from robin_sim.lab.archive import ArchiveError, archive_digest, verify_archive

    problems = []
    for archive in args.archives:
        try:
            body = verify_archive(archive)
        except ArchiveError as error:
            problems.append(str(error))
            continue
        commit = body["robin_pil"]["commit"]["id"] or "no git checkout"
        print(
            f"robin-pil study-verify: {archive}: {len(body['files'])} files match the "
            f"manifest (study {body['study']}, robin-pil {body['robin_pil']['version']}, "
            f"commit {commit}); archive SHA-256 {archive_digest(archive)}"
        )
    if problems:
        raise ArchiveError("; ".join(problems))
    return 0
