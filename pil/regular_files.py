"""Reading a file the project reads: a regular file of bounded size, checked before a byte.

A path given by a user, or found inside a folder, may name a device (``/dev/zero`` never ends),
a FIFO (its open blocks until someone writes), a folder, or a link to one of them. Every read
goes through :func:`open_regular`: opened with ``O_NONBLOCK`` (a FIFO does not block the open),
refused unless ``fstat`` says regular file, and read to at most a per-kind limit
(:data:`LIMITS`), so no file can hang a command or fill its memory. :func:`read_json_file` and
:func:`read_jsonl_file` add the format: UTF-8, JSON without duplicate keys, NaN or infinities,
nested at most :data:`MAX_DEPTH` deep; every problem is one :class:`UnreadableFileError` that
names the file.
"""

from __future__ import annotations

import errno
import json
import os
import stat
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path
from typing import Any, BinaryIO

from pil.errors import RobinPilError

# kind of file -> the most bytes read of it; every file is far below its limit in normal use
LIMITS: dict[str, int] = {
    "summary": 20_000_000,  # a run's summary.json: a few KB
    "registry": 50_000_000,  # a study's participants.json: a few KB per participant
    "settings": 20_000_000,  # a sweep's manifest.json, a study's settings: a few KB
    "questionnaires": 50_000_000,  # questionnaires.jsonl: a few hundred bytes an answer
    "log": 2_000_000_000,  # log.jsonl, events.jsonl, inputs.jsonl, a sweep's journal
    "results": 2_000_000_000,  # a results CSV read whole: millions of runs
    "states": 4_000_000_000,  # states.npz (its members are checked on their own)
    "arrays": 2_000_000_000,  # a gesture model or a rendered data set's chunk (.npz)
    "video": 64_000_000_000,  # an MP4 the command wrote (its boxes are read, never all of it)
}
MAX_DEPTH = 64  # JSON nesting: the project's files are at most a few levels deep


class FileTooLargeError(ValueError):
    """An input file over its size limit (raised by :func:`read_regular_bytes`)."""


class UnreadableFileError(RobinPilError):
    """A file found or given that cannot be read as its kind: the message names the file."""


@contextmanager
def open_regular(path: str | os.PathLike[str]) -> Iterator[BinaryIO]:
    """``path`` opened for binary reading; ``OSError`` (``strerror`` "not a regular file") for
    a device, a FIFO, a folder or a link to one, before anything is read."""
    handle = os.open(Path(path), os.O_RDONLY | os.O_NONBLOCK)  # a FIFO does not block the open
    if not stat.S_ISREG(os.fstat(handle).st_mode):
        os.close(handle)
        raise IsADirectoryError(errno.EISDIR, "not a regular file", str(path))
    with os.fdopen(handle, "rb") as reader:
        yield reader


@contextmanager
def open_bounded(path: str | os.PathLike[str], kind: str) -> Iterator[BinaryIO]:
    """``path`` opened as :func:`open_regular` does, refused (:class:`FileTooLargeError`)
    when larger than ``kind``'s limit: for files read in parts (an archive, an ``.npz``)."""
    with open_regular(path) as reader:
        if os.fstat(reader.fileno()).st_size > LIMITS[kind]:
            raise FileTooLargeError(f"larger than {LIMITS[kind]:,} bytes")
        yield reader


def read_regular_bytes(path: str | os.PathLike[str], limit: int) -> bytes:
    """A regular file's bytes; :class:`FileTooLargeError` when larger than ``limit`` (nothing
    more is read), ``OSError`` as :func:`open_regular`."""
    with open_regular(path) as reader:
        data = reader.read(limit + 1)
    if len(data) > limit:
        raise FileTooLargeError(f"larger than {limit:,} bytes")
    return data


def read_regular_text(path: str | os.PathLike[str], limit: int) -> str:
    """A regular file's UTF-8 text. ``OSError`` when it cannot be opened or is not a regular
    file (``strerror`` "not a regular file"), :class:`FileTooLargeError` when it is larger
    than ``limit`` bytes (nothing more is read), ``UnicodeDecodeError`` when not UTF-8."""
    return read_regular_bytes(path, limit).decode("utf-8")


def read_kind_bytes(path: Path, kind: str, what: str) -> bytes:
    """The bytes of ``path``, a file of ``kind`` (a key of :data:`LIMITS`), or
    :class:`UnreadableFileError` naming it as ``what`` ("the summary", ...)."""
    try:
        return read_regular_bytes(path, LIMITS[kind])
    except OSError as error:
        raise UnreadableFileError(f"{path}: cannot read {what}: {error.strerror}") from None
    except FileTooLargeError as error:
        raise UnreadableFileError(f"{path}: {error}, too large for {what}") from None


def read_kind_text(path: Path, kind: str, what: str) -> str:
    """As :func:`read_kind_bytes`, as UTF-8 text."""
    return _utf8(read_kind_bytes(path, kind, what), path, what)


def _utf8(data: bytes, path: Path, what: str) -> str:
    try:
        return data.decode("utf-8")
    except UnicodeDecodeError as error:
        raise UnreadableFileError(
            f"{path}: {what} is not UTF-8 text (byte {error.start})"
        ) from None


def _no_duplicates(pairs: list[tuple[str, Any]]) -> dict[str, Any]:
    out: dict[str, Any] = {}
    for key, value in pairs:
        if key in out:
            raise ValueError(f"the key {key!r} appears twice")
        out[key] = value
    return out


def _no_constant(name: str) -> float:
    raise ValueError(f"{name} is not a number")


def _depth(value: Any) -> int:
    """How deeply ``value`` nests (a scalar: 0), iteratively (no recursion to overflow)."""
    deepest, todo = 0, [(value, 1)]
    while todo:
        item, level = todo.pop()
        children = (
            item.values() if isinstance(item, dict) else item if isinstance(item, list) else ()
        )
        for child in children:
            if isinstance(child, dict | list):
                if level + 1 > MAX_DEPTH:
                    return level + 1
                todo.append((child, level + 1))
        if isinstance(item, dict | list):
            deepest = max(deepest, level)
    return deepest


def parse_json(text: str, *, finite: bool = False) -> Any:
    """``text`` as strict JSON: ``ValueError`` (its message says why) on a syntax error, a
    key twice, nesting deeper than :data:`MAX_DEPTH`, and with ``finite`` NaN or an infinity."""
    constant = _no_constant if finite else float
    try:
        value = json.loads(text, object_pairs_hook=_no_duplicates, parse_constant=constant)
    except RecursionError:
        raise ValueError(f"nested more than {MAX_DEPTH} levels deep") from None
    except json.JSONDecodeError as error:
        raise ValueError(f"not JSON ({error.msg} at line {error.lineno})") from None
    if _depth(value) > MAX_DEPTH:
        raise ValueError(f"nested more than {MAX_DEPTH} levels deep")
    return value


def read_json_file(path: Path, kind: str, what: str, *, finite: bool = False) -> Any:
    """The JSON value of ``path`` (see :func:`parse_json`); :class:`UnreadableFileError`
    naming the file and the problem."""
    text = read_kind_text(path, kind, what)
    try:
        return parse_json(text, finite=finite)
    except ValueError as error:
        raise UnreadableFileError(f"{path}: {what} is corrupt: {error}") from None


def read_jsonl_file(
    path: Path, kind: str, what: str, *, strict: bool = True, finite: bool = False
) -> list[Any]:
    """The JSON value of every non-blank line of ``path``. A bad line raises naming the file
    and the line, or is skipped when not ``strict`` (a line a crash cut short)."""
    data = read_kind_bytes(path, kind, what)
    # not strict: a torn multi-byte character is replaced, not fatal
    text = _utf8(data, path, what) if strict else data.decode("utf-8", "replace")
    values = []
    for number, line in enumerate(text.splitlines(), 1):
        if not line.strip():
            continue
        try:
            values.append(parse_json(line, finite=finite))
        except ValueError as error:
            if strict:
                raise UnreadableFileError(f"{path}:{number}: {what}: {error}") from None
    return values
