"""Saved association tables (pil.table_io): round trip, merge, corrupt files, atomic save."""

from __future__ import annotations

import json
import subprocess
import sys
import textwrap
from pathlib import Path

import pytest

from pil import AssociationTable, Learner, State, load_table, save_table
from pil.errors import RobinPilError
from pil.table_io import FORMAT, TableFileError, merge_files, table_from_json, table_to_json
from pil.types import Action

S = State("pointing", "open", "free")
S2 = State("grasp", "object", "free")


def _sample() -> AssociationTable:
    table = AssociationTable()
    table.update(S, Action.CLOSE, False)
    table.update(S, Action.OBJECT, True)
    table.update(S, Action.OBJECT, True)
    table.update(S2, Action.CLOSE, True)
    table.update(S2, Action.OPEN, False)
    table.record_transition(None, S)
    table.record_transition(S, S2, 2)
    return table


def _valid_content() -> dict:
    return json.loads(table_to_json(_sample()))


def test_round_trip_file_and_text(tmp_path: Path) -> None:
    table = _sample()
    path = save_table(table, tmp_path / "t.json")
    loaded = load_table(path)
    assert loaded == table
    assert loaded.count(S, Action.OBJECT) == 2
    assert loaded.rejected(S2) == {Action.OPEN}
    assert loaded.transitions(S) == {S2: 2}
    assert table_from_json(table_to_json(table)) == table
    data = json.loads(path.read_text())
    assert data["format"] == FORMAT and data["version"] == 1
    assert data["counts"]["pointing|open|free"] == {"object": 2}
    assert data["transitions"]["start"] == {"pointing|open|free": 1}
    assert not list(tmp_path.glob(".t.json.*")), "temporary file left behind"


def test_same_table_gives_byte_identical_text_whatever_the_order() -> None:
    a, b = AssociationTable(), AssociationTable()
    for state, action in [(S, Action.OBJECT), (S2, Action.CLOSE)]:
        a.update(state, action, True)
    for state, action in [(S2, Action.CLOSE), (S, Action.OBJECT)]:
        b.update(state, action, True)
    a.record_transition(S, S2)
    a.record_transition(None, S)
    b.record_transition(None, S)
    b.record_transition(S, S2)
    assert table_to_json(a) == table_to_json(b)


def test_empty_table_round_trips(tmp_path: Path) -> None:
    path = save_table(AssociationTable(), tmp_path / "empty.json")
    assert load_table(path).is_empty()


def test_merge_files_adds_counts(tmp_path: Path) -> None:
    first = save_table(_sample(), tmp_path / "a.json")
    other = AssociationTable()
    other.update(S, Action.OBJECT, True)
    other.update(S, Action.HUMAN, False)
    other.record_transition(S, S2)
    second = save_table(other, tmp_path / "b.json")
    merged = merge_files(first, second, tmp_path / "m.json")
    assert merged == load_table(tmp_path / "m.json")
    assert merged.count(S, Action.OBJECT) == 3
    assert merged.rejected(S) == {Action.CLOSE, Action.HUMAN}
    assert merged.transitions(S) == {S2: 3}


def test_hand_written_table_without_optional_parts(tmp_path: Path) -> None:
    path = tmp_path / "hand.json"
    path.write_text(
        json.dumps(
            {"format": FORMAT, "version": 1, "counts": {"Give_Me|close|occupied": {"human": 4}}}
        )
    )
    table = load_table(path)
    assert table.best(State("give me", "close", "occupied")) is Action.HUMAN


def _corrupt(content: dict, *path_and_value: object) -> str:
    *keys, value = path_and_value
    target = content
    for key in keys[:-1]:
        target = target[key]
    target[keys[-1]] = value
    return json.dumps(content)


CORRUPT = {
    "bad json": ("{not json", "not valid JSON"),
    "not an object": ("[1, 2]", "must be a JSON object"),
    "wrong format": (_corrupt(_valid_content(), "format", "something/else"), "format"),
    "unknown version": (_corrupt(_valid_content(), "version", 7), "supported versions: 1"),
    "version as text": (_corrupt(_valid_content(), "version", "1"), "unsupported version"),
    "version as a float": (_corrupt(_valid_content(), "version", 1.0), "unsupported version 1.0"),
    "version as a bool": (_corrupt(_valid_content(), "version", True), "unsupported version"),
    "unknown gesture": (
        _corrupt(_valid_content(), "counts", "wave|open|free", {"open": 1}),
        "unknown gesture 'wave'; valid choices: 'pointing', 'give me', 'grasp', 'release'",
    ),
    "unknown action": (
        _corrupt(_valid_content(), "counts", "pointing|open|free", {"jump": 1}),
        "unknown action 'jump'; valid choices: 'open'",
    ),
    "bad state key": (
        _corrupt(_valid_content(), "counts", "pointing-open-free", {"open": 1}),
        "gesture|previous_action|hand",
    ),
    "negative count": (
        _corrupt(_valid_content(), "counts", "pointing|open|free", {"object": -1}),
        "must be a non-negative integer, got -1",
    ),
    "fractional count": (
        _corrupt(_valid_content(), "counts", "pointing|open|free", {"object": 1.5}),
        "must be a non-negative integer, got 1.5",
    ),
    "boolean count": (
        _corrupt(_valid_content(), "counts", "pointing|open|free", {"object": True}),
        "must be a non-negative integer, got True",
    ),
    "text count": (
        _corrupt(_valid_content(), "counts", "pointing|open|free", {"object": "3"}),
        "must be a non-negative integer, got '3'",
    ),
    "missing counts": (json.dumps({"format": FORMAT, "version": 1}), "missing 'counts'"),
    "unknown key": (_corrupt(_valid_content(), "extra", 1), "unknown key 'extra'; valid keys"),
    "same state twice": (
        _corrupt(_valid_content(), "counts", "POINTING|open|free", {"open": 1}),
        "appears twice",
    ),
    "duplicate json key": (
        '{"format": "robin-pil/association-table", "version": 1, "counts": {}, "counts": {}}',
        "duplicate key 'counts'",
    ),
    "rejected not a list": (
        _corrupt(_valid_content(), "rejected", "pointing|open|free", "open"),
        "must be a list of action names",
    ),
    "rejected unknown action": (
        _corrupt(_valid_content(), "rejected", "pointing|open|free", ["fly"]),
        "unknown action 'fly'",
    ),
    "negative transition": (
        _corrupt(_valid_content(), "transitions", "start", {"pointing|open|free": -3}),
        "must be a non-negative integer, got -3",
    ),
    "unknown transition state": (
        _corrupt(_valid_content(), "transitions", "begin", {"pointing|open|free": 1}),
        "bad state 'begin'",
    ),
}


@pytest.mark.parametrize("case", sorted(CORRUPT))
def test_corrupt_file_raises_one_clear_error(tmp_path: Path, case: str) -> None:
    text, expected = CORRUPT[case]
    path = tmp_path / "corrupt.json"
    path.write_text(text)
    with pytest.raises(TableFileError) as raised:
        load_table(path)
    message = str(raised.value)
    assert str(path) in message
    assert expected in message
    assert isinstance(raised.value, RobinPilError)
    with pytest.raises(TableFileError, match="<json text>"):
        table_from_json(text)


def test_missing_and_binary_files(tmp_path: Path) -> None:
    with pytest.raises(TableFileError, match="no such file"):
        load_table(tmp_path / "absent.json")
    binary = tmp_path / "binary.json"
    binary.write_bytes(b"\xff\xfe\x00garbage")
    with pytest.raises(TableFileError, match=r"binary\.json: not UTF-8"):
        load_table(binary)


def test_failed_save_leaves_previous_file_intact(tmp_path: Path) -> None:
    """A real write failure: the file-size limit (RLIMIT_FSIZE) of a child process."""
    path = tmp_path / "table.json"
    save_table(AssociationTable(), path)
    before = path.read_bytes()
    script = textwrap.dedent(
        f"""
        import resource, signal
        from pil import AssociationTable, State, save_table
        from pil.table_io import TableFileError
        from pil.validity import VALID_STATES
        signal.signal(signal.SIGXFSZ, signal.SIG_IGN)
        resource.setrlimit(resource.RLIMIT_FSIZE, ({len(before) + 50}, {len(before) + 50}))
        table = AssociationTable()
        for state in VALID_STATES:
            table.update(state, "object", True)
        try:
            save_table(table, {str(path)!r})
        except TableFileError as error:
            print("FAILED:", error)
        """
    )
    result = subprocess.run(
        [sys.executable, "-c", script], capture_output=True, text=True, timeout=60, check=True
    )
    assert "FAILED:" in result.stdout, result.stdout + result.stderr
    assert str(path) in result.stdout and "nothing was overwritten" in result.stdout
    assert path.read_bytes() == before
    assert load_table(path).is_empty()
    assert sorted(p.name for p in tmp_path.iterdir()) == ["table.json"], "temp file left"


def test_save_into_missing_folder_is_a_clear_error(tmp_path: Path) -> None:
    with pytest.raises(TableFileError, match="could not be saved"):
        save_table(AssociationTable(), tmp_path / "no" / "such" / "dir" / "t.json")


def test_learner_save_and_load(tmp_path: Path) -> None:
    learner = Learner(3)
    learner.feedback(S, Action.OBJECT, True)
    learner.feedback(S2, Action.OPEN, False)
    path = learner.save(tmp_path / "learner.json")
    loaded = Learner.load(path, seed=3)
    assert loaded.table == learner.table
    assert loaded.last_ok_state is None


def test_table_module_does_not_import_table_io() -> None:
    """The dependency runs one way: pil.table_io imports pil.table, never the reverse."""
    import ast

    import pil.table

    tree = ast.parse(Path(pil.table.__file__).read_text())
    imported = {n.module for n in ast.walk(tree) if isinstance(n, ast.ImportFrom)}
    imported |= {a.name for n in ast.walk(tree) if isinstance(n, ast.Import) for a in n.names}
    assert "pil.table_io" not in imported
    assert not hasattr(AssociationTable, "to_json") and not hasattr(AssociationTable, "from_json")
