"""``--smoke`` for every bench script: the same code on tiny sizes, to check that it still runs.

``tests/test_benches.py`` runs each bench with ``--smoke``; its figures mean nothing.
"""

from __future__ import annotations

import argparse
from collections.abc import Sequence
from typing import Any


def parse_args(
    parser: argparse.ArgumentParser, argv: Sequence[str] | None = None, **tiny: Any
) -> argparse.Namespace:
    """``parser``'s arguments plus ``--smoke``, which sets each of ``tiny`` (option name to
    value) instead of what was given."""
    parser.add_argument(
        "--smoke", action="store_true", help="tiny sizes: only check that this bench runs"
    )
    args = parser.parse_args(argv)
    if args.smoke:
        for name, value in tiny.items():
            setattr(args, name, value)
    return args
