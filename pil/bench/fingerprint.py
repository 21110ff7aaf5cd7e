"""The suite's fingerprint: one hash over the suite file and every file its conditions read.

A condition's numbers can come from a file beside the suite (the eye cameras' measured
confusion, ``robin_sim/vision/data/measured.json``): retraining the eye cameras changes what
``eyes`` means without a change to ``suite.yaml``. :func:`condition_files` lists those files
(by the path the suite file gives, relative to it); :func:`fingerprint` hashes the suite file's
text and each file's bytes into the one ``suite_sha256`` every stamp carries, and returns each
input's own hash (``suite_inputs`` in the stamp) so a stale folder can say which file changed
(:func:`staleness`).
"""

from __future__ import annotations

import hashlib
from collections.abc import Mapping
from pathlib import Path
from typing import Any

from pil.errors import RobinPilError, quote
from pil.regular_files import UnreadableFileError, read_kind_bytes

#: where a condition names a file: (section, key) of its mapping
FILE_KEYS: tuple[tuple[str, str], ...] = (("gestures", "file"), ("feedback", "measured"))


def condition_files(conditions: Mapping[str, Any]) -> list[str]:
    """The files the raw suite conditions read, as written (relative to the suite file),
    each once, in the order they first appear."""
    found: dict[str, None] = {}
    for raw in conditions.values():
        if not isinstance(raw, Mapping):
            continue
        for section, key in FILE_KEYS:
            part = raw.get(section)
            if isinstance(part, Mapping) and part.get(key) is not None:
                found[str(part[key])] = None
    return list(found)


def fingerprint(
    text: str, base: Path, files: list[str], error: type[RobinPilError]
) -> tuple[str, dict[str, str]]:
    """The suite's hash (its ``text`` and every file in ``files``, read relative to ``base``)
    and each input file's own sha256; a file that cannot be read raises ``error``."""
    whole = hashlib.sha256(text.encode("utf-8"))
    inputs: dict[str, str] = {}
    for name in files:
        path = (base / name).resolve()
        try:
            data = read_kind_bytes(path, "settings", "a condition file")
        except UnreadableFileError as exc:
            raise error(f"the suite's condition file {quote(name)}: {exc}") from None
        inputs[name] = hashlib.sha256(data).hexdigest()
        whole.update(b"\0" + name.encode("utf-8") + b"\0" + inputs[name].encode("ascii"))
    return whole.hexdigest(), inputs


def staleness(stamp: Mapping[str, Any], sha256: str, inputs: Mapping[str, str]) -> str:
    """Why a results folder stamped ``stamp`` is stale for the suite of hash ``sha256`` and
    ``inputs`` ("" when it is not): the suite file or which of its input files changed."""
    if stamp.get("suite_sha256") == sha256:
        return ""
    made = stamp.get("suite_inputs")
    if not isinstance(made, Mapping):
        return "its results were made with another suite (a suite hash of before 1.2)"
    changed = [n for n in sorted({*made, *inputs}) if made.get(n) != inputs.get(n)]
    if changed:
        return "its results were made with other contents of " + ", ".join(changed)
    return "its results were made with another suite file"
