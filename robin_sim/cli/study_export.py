"""``robin-pil study-export DIR``: a study's CSV files and its archive with a manifest.

Writes ``DIR/exports/trials.csv`` (one row per step), ``questionnaires_wide.csv`` (one row per
participant) and ``long.csv`` (one value a row), then ``DIR/archive/<study>-<time>.zip``: every
file of the folder (the report too, when ``robin-pil report DIR`` ran before) and a manifest
that ``robin-pil study-verify`` checks.
"""

from __future__ import annotations

import argparse
from pathlib import Path


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """The command's options."""
    parser.add_argument("dir", type=Path, metavar="DIR", help="the study folder")
    parser.add_argument(
        "--no-archive", action="store_true", help="write the CSV files only, no archive"
    )


def run(args: argparse.Namespace) -> int:
    """Write the exports and the archive; list them."""
    from robin_sim.cli.help_format import package_version
    from robin_sim.lab.archive import archive_digest, write_archive
    from robin_sim.lab.exports import write_exports
    from robin_sim.lab.study_file import load_study

    study = load_study(args.dir)
    for path in write_exports(study):
        print(path)
    if not args.no_archive:
        archive = write_archive(study, package_version())
        print(f"archive SHA-256 {archive_digest(archive)} (keep it apart from the archive):")
        print(archive)
    return 0
