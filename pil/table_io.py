"""Saving, loading and merging association tables as versioned JSON files.

The file holds everything the learner needs to decide again exactly as before::

    {
      "format": "robin-pil/association-table",
      "version": 1,
      "counts": {"pointing|open|free": {"object": 3}, ...},
      "rejected": {"pointing|open|free": ["close", "open"], ...},
      "transitions": {"start": {"pointing|open|free": 1}, "pointing|open|free": {...}, ...}
    }

``counts`` is T of eq. 2, ``rejected`` the actions that ever got not-OK per state, and
``transitions`` how often an approved state followed another (``"start"``: the task start).
``rejected`` and ``transitions`` may be left out. Keys are written in a fixed order, so the same
table gives byte-identical files. Anything malformed raises :class:`TableFileError` naming the
file and the problem.
"""

from __future__ import annotations

import json
import os
from pathlib import Path

from pil.atomic import write_text_atomic
from pil.errors import InvalidChoiceError, RobinPilError
from pil.regular_files import FileTooLargeError, read_regular_text
from pil.table import AssociationTable, merge_all, state_sort_key
from pil.types import ACTIONS, Action, State

FORMAT = "robin-pil/association-table"
VERSION = 1
SUPPORTED_VERSIONS = (1,)
START_KEY = "start"
_KEYS = ("format", "version", "counts", "rejected", "transitions")


MAX_TABLE_BYTES = 50_000_000  # a saved table is a few KB


class TableFileError(RobinPilError):
    """A saved association table that is corrupt, foreign or of an unsupported version."""


def table_to_dict(table: AssociationTable) -> dict[str, object]:
    """The JSON-ready content of ``table`` in a fixed order."""
    counts = {
        s.key(): {a.value: c for a, c in table.counts(s).items() if c} for s in table.states()
    }
    rejected = {
        s.key(): [a.value for a in ACTIONS if a in table.rejected(s)]
        for s in table.rejected_states()
    }
    transitions = {}
    for previous in table.transition_sources():
        followers = table.transitions(previous)
        key = START_KEY if previous is None else previous.key()
        transitions[key] = {s.key(): followers[s] for s in sorted(followers, key=state_sort_key)}
    return {
        "format": FORMAT,
        "version": VERSION,
        "counts": counts,
        "rejected": rejected,
        "transitions": transitions,
    }


def table_to_json(table: AssociationTable) -> str:
    """:func:`table_to_dict` as indented JSON text ending in a newline."""
    return json.dumps(table_to_dict(table), indent=2) + "\n"


def _no_duplicates(pairs: list[tuple[str, object]]) -> dict[str, object]:
    keys = [k for k, _ in pairs]
    for key in keys:
        if keys.count(key) > 1:
            raise ValueError(f"duplicate key {key!r}")
    return dict(pairs)


def _fail(source: str, problem: str) -> TableFileError:
    return TableFileError(f"association table {source}: {problem}")


def _state(source: str, where: str, key: object, seen: set[State]) -> State:
    if not isinstance(key, str):
        raise _fail(source, f"{where}: state key {key!r} is not text")
    try:
        state = State.from_key(key)
    except InvalidChoiceError as error:
        raise _fail(source, f"{where}: bad state {key!r}: {error}") from None
    if state in seen:
        raise _fail(source, f"{where}: state {state.key()!r} appears twice (as {key!r})")
    seen.add(state)
    return state


def _count(source: str, where: str, value: object) -> int:
    if isinstance(value, bool) or not isinstance(value, int) or value < 0:
        raise _fail(source, f"{where} must be a non-negative integer, got {value!r}")
    return value


def _mapping(source: str, where: str, value: object) -> dict[str, object]:
    if not isinstance(value, dict):
        raise _fail(source, f"{where} must be a JSON object, got {type(value).__name__}")
    return value


def _action(source: str, where: str, name: object) -> Action:
    try:
        return Action.parse(name)  # type: ignore[arg-type]
    except InvalidChoiceError as error:
        raise _fail(source, f"{where}: {error}") from None


def table_from_dict(data: object, source: str = "<data>") -> AssociationTable:
    """Check and convert the content of a saved table (see the module docstring)."""
    data = _mapping(source, "the top level", data)
    unknown = [k for k in data if k not in _KEYS]
    if unknown:
        raise _fail(source, f"unknown key {unknown[0]!r}; valid keys: {', '.join(_KEYS)}")
    if data.get("format") != FORMAT:
        raise _fail(
            source, f"not an association table (format {data.get('format')!r}, expected {FORMAT!r})"
        )
    version = data.get("version")
    if version.__class__ is not int or version not in SUPPORTED_VERSIONS:
        supported = ", ".join(map(str, SUPPORTED_VERSIONS))
        raise _fail(source, f"unsupported version {version!r}; supported versions: {supported}")
    if "counts" not in data:
        raise _fail(source, "missing 'counts'")
    table = AssociationTable()
    seen: set[State] = set()
    for key, row in _mapping(source, "'counts'", data["counts"]).items():
        state = _state(source, "counts", key, seen)
        where = f"counts[{key!r}]"
        actions_seen: set[Action] = set()
        for name, value in _mapping(source, where, row).items():
            action = _action(source, where, name)
            if action in actions_seen:
                raise _fail(source, f"{where}: action {action.value!r} appears twice")
            actions_seen.add(action)
            table.add(state, action, _count(source, f"{where}[{name!r}]", value))
    seen = set()
    for key, names in _mapping(source, "'rejected'", data.get("rejected", {})).items():
        state = _state(source, "rejected", key, seen)
        where = f"rejected[{key!r}]"
        if not isinstance(names, list):
            raise _fail(source, f"{where} must be a list of action names")
        for name in names:
            table.reject(state, _action(source, where, name))
    seen = set()
    sources: set[str] = set()
    for key, followers in _mapping(source, "'transitions'", data.get("transitions", {})).items():
        if key == START_KEY:
            if key in sources:
                raise _fail(source, "transitions: 'start' appears twice")
            sources.add(key)
            previous = None
        else:
            previous = _state(source, "transitions", key, seen)
        where = f"transitions[{key!r}]"
        followers_seen: set[State] = set()
        for next_key, value in _mapping(source, where, followers).items():
            state = _state(source, where, next_key, followers_seen)
            count = _count(source, f"{where}[{next_key!r}]", value)
            table.record_transition(previous, state, count)
    return table


def table_from_json(text: str, source: str = "<json text>") -> AssociationTable:
    """Parse the text of a saved table; raises :class:`TableFileError` if it is corrupt."""
    try:
        data = json.loads(text, object_pairs_hook=_no_duplicates)
    except json.JSONDecodeError as error:
        raise _fail(
            source, f"not valid JSON ({error.msg} at line {error.lineno}, column {error.colno})"
        ) from None
    except ValueError as error:  # a duplicate key
        raise _fail(source, f"not a valid table: {error}") from None
    except RecursionError:  # e.g. 100 000 nested brackets
        raise _fail(source, "nested too deeply to be a table (a table is 3 levels deep)") from None
    return table_from_dict(data, source)


def save_table(table: AssociationTable, path: str | os.PathLike[str]) -> Path:
    """Write ``table`` to ``path`` atomically (a temporary file, then ``os.replace``).

    If writing fails, an existing file at ``path`` is left as it was and
    :class:`TableFileError` is raised.
    """
    if not isinstance(table, AssociationTable):
        raise TypeError(f"expected an AssociationTable, got {type(table).__name__}")
    path = Path(path)
    text = table_to_json(table)
    try:
        write_text_atomic(path, text, make_folder=False)
    except OSError as error:
        raise _fail(str(path), f"could not be saved ({error}); nothing was overwritten") from None
    return path


def load_table(path: str | os.PathLike[str]) -> AssociationTable:
    """Read a table saved by :func:`save_table`; raises :class:`TableFileError` if corrupt."""
    path = Path(path)
    try:
        text = read_regular_text(path, MAX_TABLE_BYTES)  # /dev/zero, a FIFO: refused at once
    except FileNotFoundError:
        raise _fail(str(path), "no such file") from None
    except UnicodeDecodeError:
        raise _fail(str(path), "not UTF-8 text") from None
    except FileTooLargeError as error:
        raise _fail(str(path), f"{error}, too large for a saved table") from None
    except OSError as error:
        raise _fail(str(path), f"cannot be read ({error})") from None
    return table_from_json(text, str(path))


def merge_files(
    first: str | os.PathLike[str],
    second: str | os.PathLike[str],
    out: str | os.PathLike[str],
) -> AssociationTable:
    """Merge two saved tables (counts add) into ``out``; returns the merged table."""
    merged = merge_all((load_table(first), load_table(second)))
    save_table(merged, out)
    return merged
