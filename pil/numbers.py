"""Numbers as a user types them: ASCII digits only, checked before Python's own parsers.

``int()`` and ``float()`` accept more than a person means to type: ``"1_0"`` (ten, as in
Python source), Arabic-Indic or other Unicode digits (``"٣"`` is three), full-width digits.
A command's option or a ``--param`` value that reads as a number must be written with the
ASCII digits ``0-9``, an optional sign, a decimal point and an exponent; anything else is
refused with the usual one-line message, never silently read as some other number.
"""

from __future__ import annotations

import re

_WHOLE = re.compile(r"[+-]?[0-9]+", re.ASCII)
_DECIMAL = re.compile(r"[+-]?(?:[0-9]+\.?[0-9]*|\.[0-9]+)(?:[eE][+-]?[0-9]+)?", re.ASCII)
LONGEST = 40  # characters: no number the project takes is longer


def is_whole_text(text: str) -> bool:
    """Whether ``text`` (stripped) is a whole number in ASCII digits, e.g. ``"-12"``."""
    text = text.strip()
    return len(text) <= LONGEST and _WHOLE.fullmatch(text) is not None


def is_decimal_text(text: str) -> bool:
    """Whether ``text`` (stripped) is a decimal number in ASCII, e.g. ``"0.5"``, ``"1e-3"``."""
    text = text.strip()
    return len(text) <= LONGEST and _DECIMAL.fullmatch(text) is not None


def parse_whole(text: str) -> int:
    """``text`` as a whole number; ``ValueError`` naming it unless ASCII digits."""
    if not is_whole_text(text):
        raise ValueError(f"{text!r} is not a whole number written with the digits 0-9")
    return int(text)


def parse_decimal(text: str) -> float:
    """``text`` as a number; ``ValueError`` naming it unless written in ASCII (digits, sign,
    point, exponent: no ``inf``, ``nan``, underscores or other scripts' digits)."""
    if not is_decimal_text(text):
        raise ValueError(f"{text!r} is not a number written with the digits 0-9")
    return float(text)
