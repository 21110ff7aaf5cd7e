"""YAML files of the task (scenarios, study protocols): finding shipped ones by name, reading
a file's top-level mapping with one clear error for every way it can be broken.

A task file is small: only regular files of at most :data:`MAX_YAML_BYTES` are read (a
device such as ``/dev/zero`` or a huge file is refused at once), and YAML aliases are refused
(a few hundred bytes of nested aliases expand to gigabytes: an "alias bomb").
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

import yaml

from pil.errors import RobinPilError, quote
from pil.regular_files import FileTooLargeError, read_regular_text

MAX_YAML_BYTES = 1_000_000  # a task file is a few KB; anything larger is a mistake or an attack
MAX_TEXT = 2000  # characters of a name or a description in a task file


class _NoAliasLoader(yaml.SafeLoader):
    """The safe loader, refusing every alias (``*name``) before it is expanded."""

    def compose_node(self, parent: Any, index: Any) -> Any:
        if self.check_event(yaml.AliasEvent):
            event = self.peek_event()
            raise yaml.composer.ComposerError(
                None,
                None,
                "YAML aliases (*name) are not allowed in a task file; write the value out",
                event.start_mark,
            )
        return super().compose_node(parent, index)

    def construct_mapping(self, node: Any, deep: bool = False) -> Any:
        """A mapping, refusing a key given twice (PyYAML would keep the last one silently)."""
        if isinstance(node, yaml.MappingNode):
            seen: set[Any] = set()
            for key_node, _value in node.value:
                key = self.construct_object(key_node, deep=True)
                try:
                    twice = key in seen
                    seen.add(key)
                except TypeError:  # an unhashable key: SafeLoader refuses it below
                    continue
                if twice:
                    raise yaml.constructor.ConstructorError(
                        None,
                        None,
                        f"the key {quote(key)} appears twice in one mapping; give each key once",
                        key_node.start_mark,
                    )
        return super().construct_mapping(node, deep)


def load_yaml_text(text: str) -> Any:
    """``text`` parsed as YAML like ``yaml.safe_load``, but with aliases and a key given twice
    refused (every YAML file of the project is read through here)."""
    return yaml.load(text, Loader=_NoAliasLoader)  # a SafeLoader subclass


def yaml_problem(problem: yaml.YAMLError) -> str:
    """PyYAML's error as one line: "malformed YAML at line L, column C: what"."""
    mark = getattr(problem, "problem_mark", None)
    where = f" at line {mark.line + 1}, column {mark.column + 1}" if mark else ""
    what = getattr(problem, "problem", None) or str(problem).splitlines()[0]
    return f"malformed YAML{where}: {what}"


def shipped_in(folder: Path) -> tuple[str, ...]:
    """Names of the YAML files shipped in ``folder`` (scenarios, protocols), sorted."""
    return tuple(sorted(p.stem for p in folder.glob("*.yaml")))


def find_shipped(path: str | Path, folder: Path) -> Path:
    """``path`` if it names a file; else the file of that name shipped in ``folder``; else
    ``path`` (whose reading then fails with the caller's message)."""
    path = Path(path)
    if path.exists() or path.suffix or len(path.parts) != 1:
        return path
    shipped = folder / f"{path.name}.yaml"
    return shipped if shipped.is_file() else path


def read_yaml_mapping(
    path: Path,
    kind: str,
    error: type[RobinPilError],
    shipped: Sequence[str],
) -> Mapping[str, Any]:
    """A YAML file's top-level mapping; a missing or malformed file raises ``error``.

    ``kind`` names the file in the messages ("scenario", "protocol"); ``shipped``: the names
    listed when the file cannot be read.
    """
    try:
        text = read_small_text(path)
    except OSError as problem:
        raise error(
            f"{path}: cannot read the {kind}: {problem.strerror}; a file, or one of the shipped "
            f"{kind}s: " + ", ".join(shipped)
        ) from None
    except UnicodeDecodeError as problem:
        raise error(
            f"{path}: not UTF-8 text (byte {problem.start}); a {kind} is a UTF-8 YAML file"
        ) from None
    except FileTooLargeError as problem:
        raise error(f"{path}: {problem}; a {kind} is a small YAML file") from None
    try:
        raw = load_yaml_text(text)
    except yaml.YAMLError as problem:
        raise error(f"{path}: {yaml_problem(problem)}") from None
    except RecursionError:
        raise error(f"{path}: nested too deeply to be a {kind}") from None
    if not isinstance(raw, Mapping):
        raise error(f"{path}: expected a mapping at the top level")
    return raw


def reject_unknown(
    raw: Mapping[str, Any],
    valid: Sequence[str],
    where: str,
    error: type[RobinPilError],
    takes: str = "valid choices:",
) -> None:
    """Raise ``error`` on the first key of ``raw`` that is not in ``valid``, naming them all
    after ``takes`` (every file's one check of its keys)."""
    for key in raw:
        if key not in valid:
            shown = ", ".join(valid) if valid else "no options"
            raise error(f"{where}: unknown key {quote(key)}; {takes} {shown}")


def read_small_text(path: Path, limit: int = MAX_YAML_BYTES) -> str:
    """A task file's text: :func:`pil.regular_files.read_regular_text` at the task files'
    size limit."""
    return read_regular_text(path, limit)


def text_field(
    raw: Mapping[str, Any], key: str, default: str, where: str, error: type[RobinPilError]
) -> str:
    """``raw[key]`` as a text of at most :data:`MAX_TEXT` characters (``default`` if absent;
    a number is written as text); a list, a mapping or a longer text raises ``error``."""
    value = raw.get(key, default)
    if isinstance(value, bool) or not isinstance(value, str | int | float):
        raise error(f"{where}: {key}: expected a text, got {quote(value)}")
    text = str(value)
    if len(text) > MAX_TEXT:
        raise error(f"{where}: {key}: at most {MAX_TEXT} characters, got {len(text)}")
    return text
