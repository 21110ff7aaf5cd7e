"""How every ``robin-pil`` help page reads: each option's default shown, and the version."""

from __future__ import annotations

import argparse
from importlib.metadata import PackageNotFoundError, version

DISTRIBUTION = "robin-pil"  # the name in pyproject.toml


def package_version() -> str:
    """The installed version of robin-pil ("unknown" when run from a bare source tree)."""
    try:
        return version(DISTRIBUTION)
    except PackageNotFoundError:
        return "unknown"


class DefaultsHelpFormatter(argparse.ArgumentDefaultsHelpFormatter):
    """argparse's defaults formatter, minus noise: an on/off switch (default off) and an
    option whose default is ``None`` (its help says what happens unset) get no "(default: ...)"
    added; a help that names its default already keeps its own wording."""

    def _get_help_string(self, action: argparse.Action) -> str | None:
        text = action.help or ""
        if "default" in text.lower():
            return text
        if action.default is None or action.default is False or isinstance(action.default, bool):
            return text
        if isinstance(action, argparse._VersionAction | argparse._HelpAction):
            return text
        return super()._get_help_string(action)
