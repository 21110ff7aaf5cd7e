"""The files ``robin-pil bench`` finds in its results folder or is given (issue 39): the runs
journal, the stamp, the results tables, ``--tuned`` and the suite's condition files are read
through the guarded reader. A device, a FIFO or a value of the wrong type is one message naming
the file (and the line), exit code 2, before anything runs; a torn last line of the journal is
left out and said, and every finished run before it is kept."""

from __future__ import annotations

import json
import math
import os
import subprocess
import sys
from pathlib import Path

import pytest
from hypothesis import HealthCheck, assume, given, settings
from hypothesis import strategies as st

from pil.bench.journal import RUNS, STAMP, Journal, read_runs
from pil.bench.results import read_table, write_results
from pil.bench.run import Entrant, run_bench
from pil.bench.suite import load_suite
from pil.regular_files import UnreadableFileError
from robin_sim.cli.main import main

SUITE = load_suite()
QUICK = ["--agent", "random", "--track", "assembly", "--quick", "--no-progress"]


def _journal(out: Path, seeds: int = 3) -> list[str]:
    """A real journal of ``seeds`` random runs (assembly, quick, d60); its lines."""
    journal = Journal(out, SUITE, "dev", True)
    seed_list = SUITE.seeds("dev", True)[:seeds]
    run_bench(
        SUITE, [Entrant("random", "random")], ["assembly"], journal, seed_list, conditions=["d60"]
    )
    return (out / RUNS).read_text(encoding="utf-8").splitlines()


@pytest.fixture(scope="module")
def journal_lines(tmp_path_factory: pytest.TempPathFactory) -> list[str]:
    return _journal(tmp_path_factory.mktemp("journal"))


def _write(out: Path, lines: list[str], tail: bytes = b"") -> None:
    out.mkdir(parents=True, exist_ok=True)
    stamp = {**SUITE.stamp(), "block": "dev", "quick": True, "commit": "test"}
    (out / STAMP).write_text(json.dumps(stamp))
    (out / RUNS).write_bytes("".join(line + "\n" for line in lines).encode() + tail)


def _one_error(capsys: pytest.CaptureFixture[str]) -> str:
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "Traceback" not in err[0], err
    return err[0]


def _cli(argv: list[str], cwd: Path) -> subprocess.CompletedProcess[str]:
    """``robin-pil`` in a process of its own: a file that blocks (a FIFO) cannot hang the
    tests; the limit only catches a hang, the test asserts what the command said."""
    code = "import sys; from robin_sim.cli.main import main; sys.exit(main(sys.argv[1:]))"
    return subprocess.run(
        [sys.executable, "-c", code, *argv],
        cwd=cwd,
        capture_output=True,
        text=True,
        timeout=300,
        check=False,
    )


def test_a_journal_linked_to_a_device_is_refused_naming_it(tmp_path, capsys):
    out = tmp_path / "out"
    out.mkdir()
    (out / RUNS).symlink_to("/dev/zero")
    assert main(["bench", *QUICK, "--out", str(out)]) == 2
    line = _one_error(capsys)
    assert str(out / RUNS) in line and "not a regular file" in line
    assert not (out / "summary.csv").exists()  # nothing ran


@pytest.mark.parametrize("name", [RUNS, STAMP])
def test_a_fifo_in_the_results_folder_is_refused_not_waited_on(name, tmp_path):
    out = tmp_path / "out"
    out.mkdir()
    os.mkfifo(out / name)
    done = _cli(["bench", *QUICK, "--out", str(out)], tmp_path)
    assert done.returncode == 2, done.stderr
    assert str(out / name) in done.stderr and "not a regular file" in done.stderr


@pytest.mark.parametrize(
    ("field", "text", "said"),
    [
        ("actions", "NaN", "NaN"),
        ("curve_area", "Infinity", "Infinity"),
        ("actions", '"lots"', "'actions'"),
        ("seed", "1.5", "'seed'"),
        ("track", '"nowhere"', "valid choices"),
        ("condition", '"d99"', "valid choices"),
        ("stalled", '"no"', "'stalled'"),
        ("curve", "[1, -2]", "'curve'"),
    ],
)
def test_a_bad_row_is_one_message_naming_the_line(
    field, text, said, journal_lines, tmp_path, capsys
):
    lines = list(journal_lines)
    row = json.loads(lines[1])
    row[field] = "@"
    lines[1] = json.dumps(row, sort_keys=True).replace('"@"', text)
    out = tmp_path / "out"
    _write(out, lines)
    before = (out / RUNS).read_bytes()
    assert main(["bench", *QUICK, "--out", str(out)]) == 2
    line = _one_error(capsys)
    assert f"{out / RUNS}:2" in line and said in line
    assert (out / RUNS).read_bytes() == before  # nothing appended


def test_a_row_of_unknown_or_missing_fields_is_refused(journal_lines, tmp_path):
    row = json.loads(journal_lines[0])
    for changed in ({**row, "colour": "red"}, {k: v for k, v in row.items() if k != "actions"}):
        out = tmp_path / str(len(changed))
        _write(out, [json.dumps(changed)])
        with pytest.raises(UnreadableFileError, match=f"{RUNS}:1"):
            read_runs(out, SUITE)


def test_a_torn_tail_is_left_out_said_and_the_resumed_results_are_a_clean_run_s(tmp_path, capsys):
    clean, torn = tmp_path / "clean", tmp_path / "torn"
    assert main(["bench", *QUICK, "--out", str(clean)]) == 0
    lines = (clean / RUNS).read_text(encoding="utf-8").splitlines()
    half = lines[5][: len(lines[5]) // 2].encode() + "é".encode()[:1]  # a torn UTF-8 byte too
    _write(torn, lines[:5], half)
    capsys.readouterr()
    assert main(["bench", *QUICK, "--out", str(torn)]) == 0
    err = capsys.readouterr().err
    assert f"{torn / RUNS}:6" in err and "left out" in err
    for name in ("summary.csv", "tests.csv", "equivalence.csv"):
        assert (torn / name).read_text() == (clean / name).read_text()
    assert len(read_runs(torn, SUITE)) == len(lines)  # every run, the torn one run again


@settings(
    max_examples=40, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture]
)
@given(tail=st.binary(max_size=300).filter(lambda b: b"\n" not in b and b.strip()))
def test_no_tail_ever_costs_a_finished_run(tail, journal_lines, tmp_path_factory):
    out = tmp_path_factory.mktemp("tail")
    _write(out, journal_lines, tail)
    journal = Journal(out, SUITE, "dev", True)
    expected = [json.loads(line) for line in journal_lines]
    assert [r["seed"] for r in journal.rows] == [r["seed"] for r in expected]
    assert f"{out / RUNS}:{len(journal_lines) + 1}" in journal.dropped
    journal.add([{**expected[0], "seed": 7}])  # the next run starts on a line of its own
    assert [r["seed"] for r in read_runs(out, SUITE)][-1] == 7


_WRONG = st.one_of(
    st.text(max_size=5),
    st.lists(st.integers(), max_size=2),
    st.dictionaries(st.text(max_size=2), st.integers(), max_size=1),
    st.booleans(),
    st.floats(allow_nan=False, allow_infinity=False).filter(lambda x: x != int(x)),
    st.integers(max_value=-1),
)


@settings(
    max_examples=60, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture]
)
@given(
    field=st.sampled_from(["actions", "gestures", "seed", "scripted", "longest_wait", "curve"]),
    value=_WRONG,
)
def test_a_value_of_the_wrong_type_is_refused_naming_field_and_line(
    field, value, journal_lines, tmp_path_factory
):
    curve = isinstance(value, list) and value and all(type(v) is int and v >= 0 for v in value)
    assume(not (field == "curve" and curve))  # that is a curve
    out = tmp_path_factory.mktemp("wrong")
    row = json.loads(journal_lines[0])
    _write(out, [journal_lines[1], json.dumps({**row, field: value})])
    with pytest.raises(UnreadableFileError, match=f"{RUNS}:2: .*'{field}'"):
        read_runs(out, SUITE)


@pytest.mark.parametrize(
    "stamp",
    [
        [1, 2],
        {"suite_version": "1.2", "quick": "yes"},
        {**SUITE.stamp(), "block": "dev", "quick": True, "commit": "x", "resumed_at": 5},
    ],
)
def test_a_stamp_of_the_wrong_shape_is_refused(stamp, tmp_path, capsys):
    out = tmp_path / "out"
    out.mkdir()
    (out / STAMP).write_text(json.dumps(stamp))
    assert main(["bench", *QUICK, "--out", str(out)]) == 2
    assert str(out / STAMP) in _one_error(capsys)


def test_a_results_table_is_read_strictly(journal_lines, tmp_path):
    out = tmp_path / "out"
    _write(out, journal_lines)
    write_results(SUITE, out)
    table = out / "summary.csv"
    assert len(read_table(table)) == 1
    text = table.read_text()
    header, row = text.splitlines()
    for bad, said in (
        (f"{header}\n{row},9\n", "cells"),  # a cell too many
        (f"{header}\n{row[: len(row) // 2]}\n", "cells"),  # a row cut in half
        (f"{header}\n{row.replace('assembly,random,d60,3', 'assembly,random,d60,inf')}\n", "runs"),
        (f"{header}\n{row.replace('assembly,random,d60,3', 'assembly,random,d60,1_0')}\n", "runs"),
        (header.replace("runs", "rums") + f"\n{row}\n", "columns"),
    ):
        table.write_text(bad)
        with pytest.raises(UnreadableFileError, match=f"{table}.*{said}"):
            read_table(table)
    table.unlink()
    table.symlink_to("/dev/zero")
    with pytest.raises(UnreadableFileError, match="not a regular file"):
        read_table(table)


@pytest.mark.parametrize(
    ("content", "said"),
    [
        ('{"pil-paper": {"params": [1]}}', "pil-paper"),
        ('{"pil-paper": {"params": {"x": 1}}}', "takes no parameters"),
        ('{"tamer": {"params": {"step": 0.5}}}', "step_size"),
        ('{"tamer": {"params": {"step_size": 5}}}', "0-1"),
        ('{"tamer": {"params": {"step_size": NaN}}}', "NaN"),
        ('{"tamer": {"params": {"step_size": true}}}', "step_size"),
        ('{"egreedy": {"params": {"epsilon": 0.1}}}', "prior"),
        ('{"nobody": {"params": {}}}', "valid choices"),
        ('{"tamer": 3}', "tamer"),
        ("[1]", "mapping"),
    ],
)
def test_a_bad_tuned_file_is_refused_naming_agent_and_parameters(content, said, tmp_path, capsys):
    tuned = tmp_path / "tuned.json"
    tuned.write_text(content)
    argv = ["bench", "--agent", "tamer", *QUICK[2:], "--tuned", str(tuned)]
    assert main([*argv, "--out", str(tmp_path / "out")]) == 2
    line = _one_error(capsys)
    assert str(tuned) in line and said in line
    assert not (tmp_path / "out").exists()


def test_a_tuned_file_that_is_a_device_or_a_fifo_is_refused(tmp_path, capsys):
    tuned = tmp_path / "zero.json"
    tuned.symlink_to("/dev/zero")
    assert main(["bench", *QUICK, "--tuned", str(tuned), "--out", str(tmp_path / "o")]) == 2
    assert str(tuned) in _one_error(capsys)
    fifo = tmp_path / "fifo.json"
    os.mkfifo(fifo)
    done = _cli(["bench", *QUICK, "--tuned", str(fifo), "--out", str(tmp_path / "o")], tmp_path)
    assert done.returncode == 2 and str(fifo) in done.stderr


def test_the_shipped_tuned_parameters_are_read_back(tmp_path):
    from pil.bench.tuned import read_tuned

    shipped = Path(__file__).parents[1] / "bench/results/leaderboard/tuned.json"
    found = read_tuned(shipped, SUITE)
    assert found and set(found) <= set(SUITE.grids)
    for agent, entry in found.items():
        assert set(entry["params"]) == {a.name for a in SUITE.grids[agent]}


def test_a_condition_file_that_is_a_fifo_is_refused(tmp_path):
    import shutil

    from pil.bench.suite import SuiteError

    suite_file = tmp_path / "suite.yaml"
    shutil.copy(SUITE.path, suite_file)
    text = suite_file.read_text().replace("../../robin_sim/vision/data/measured.json", "m.json")
    suite_file.write_text(text)
    os.mkfifo(tmp_path / "m.json")
    code = (
        "import sys; from pil.bench.suite import load_suite\n"
        "try:\n    load_suite(sys.argv[1])\nexcept Exception as e:\n"
        "    print(type(e).__name__, e); sys.exit(3)"
    )
    done = subprocess.run(
        [sys.executable, "-c", code, str(suite_file)],
        capture_output=True,
        text=True,
        timeout=300,
        check=False,
    )
    assert done.returncode == 3 and SuiteError.__name__ in done.stdout
    assert "m.json" in done.stdout and "not a regular file" in done.stdout


def test_the_measured_thumbs_are_checked(tmp_path):
    from pil.bench.noise import thumb_rows

    good = json.loads(
        (Path(__file__).parents[1] / "robin_sim/vision/data/measured.json").read_text()
    )
    path = tmp_path / "m.json"
    path.write_text(json.dumps(good))
    rows = thumb_rows(str(path))
    assert all(math.isclose(sum(row), 1.0, abs_tol=1e-3) for row in rows.values())
    for bad in ({**good, "feedback_confusion": [[0.5, 0.5]] * 2}, {**good, "feedback": ["OK"]}):
        path.write_text(json.dumps(bad))
        with pytest.raises(UnreadableFileError, match=r"m\.json"):
            thumb_rows(str(path))
