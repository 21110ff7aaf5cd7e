"""Every bad input of the CLI is refused before anything starts: exit 2, one message, no files.

Each case runs the real ``robin-pil`` entry point (:func:`robin_sim.cli.main.main`); the
message must name the problem and the valid choices or range, and the output folder must be
left exactly as it was (here: an earlier episode's files, byte for byte).
"""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest

from pil.errors import QUOTE_LIMIT
from robin_sim.cli.main import main

EARLIER = {"summary.json": '{"status": "finished", "actions": 49}\n', "episode.jsonl": "{}\n" * 5}


@pytest.fixture()
def earlier(tmp_path: Path) -> Path:
    """An output folder holding an earlier episode's files."""
    out = tmp_path / "out"
    out.mkdir()
    for name, text in EARLIER.items():
        (out / name).write_text(text)
    return out


def assert_untouched(out: Path) -> None:
    assert sorted(p.name for p in out.iterdir()) == sorted(EARLIER)
    for name, text in EARLIER.items():
        assert (out / name).read_text() == text


def refused(argv: list[str], capsys: pytest.CaptureFixture[str], *needles: str) -> str:
    code = main(argv)
    err = capsys.readouterr().err
    assert code == 2, err
    lines = [line for line in err.splitlines() if line.strip()]
    assert len(lines) == 1 and lines[0].startswith(f"robin-pil {argv[0]}: error: "), err
    for needle in needles:
        assert needle in lines[0], (needle, lines[0])
    return lines[0]


@pytest.mark.parametrize(
    ("option", "needles"),
    [
        (["--camera", "nope"], ["--camera", "'front', 'side', 'head'", "'nope'"]),
        (["--size", "0x0"], ["--size width", "from 2 to", "'0'"]),
        (["--size=-640x480"], ["--size width", "'-640'"]),
        (["--size", "641x481"], ["even", "642x482"]),
        (["--size", "99998x99998"], ["99998x99998", "off-screen buffer 1280x720"]),
        (["--size", "640"], ["--size must look like 640x480"]),
        (["--fps", "0"], ["--fps", "from 1 to 240", "'0'"]),
        (["--render-workers=-1"], ["--render-workers", "from 0 to 64", "'-1'"]),
        (["--seed=-1"], ["--seed", "from 0 to", "'-1'"]),
        (["--rate", "1.5"], ["--rate", "(0, 1]", "'1.5'"]),
        (["--tables", "1000000000"], ["--tables", "from 1 to 1000", "'1000000000'"]),
        (["--system", "c9"], ["system", "'pil', 'c1'"]),
    ],
)
def test_episode_refuses_bad_options_and_keeps_earlier_files(
    option: list[str], needles: list[str], earlier: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    refused(["episode", "--out", str(earlier), "--quiet", *option], capsys, *needles)
    assert_untouched(earlier)


def test_episode_refuses_bad_scenarios_and_out_folders(
    tmp_path: Path, earlier: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    latin = tmp_path / "latin.yaml"
    latin.write_bytes("tables: 1\nname: caf\xe9\n".encode("latin-1"))
    empty = tmp_path / "empty.yaml"
    empty.write_text("")
    huge = tmp_path / "huge.yaml"
    huge.write_text("types: handover_types.yaml\ntables: 1000000000\n")
    (tmp_path / "handover_types.yaml").symlink_to(
        Path(__file__).parents[1] / "scenarios" / "handover_types.yaml"
    )
    deep = tmp_path / "deep.yaml"
    deep.write_text("tables: " + "[" * 100_000 + "]" * 100_000 + "\n")
    base = ["episode", "--quiet", "--no-video", "--no-verify"]
    for scenario, needle in (
        (latin, "not UTF-8"),
        (empty, "expected a mapping"),
        (tmp_path / "missing.yaml", "one of the shipped scenarios: assembly"),
        (huge, "tables must be a whole number from 1 to 1000, got 1000000000"),
        (deep, "nested too deeply"),
    ):
        refused([*base, "--out", str(earlier), "--scenario", str(scenario)], capsys, needle)
        assert_untouched(earlier)
    a_file = earlier / "summary.json"
    refused([*base, "--out", str(a_file)], capsys, "is a file")
    refused([*base, "--out", str(a_file / "sub")], capsys, "lies under the file")
    refused([*base, "--out", "/proc/robin-pil-x"], capsys, "cannot be written")
    assert_untouched(earlier)


def test_a_huge_bad_value_is_quoted_cut(earlier: Path, capsys: pytest.CaptureFixture[str]) -> None:
    value = "x" * 50_000_000
    line = refused(["episode", "--out", str(earlier), "--camera", value], capsys, "--camera")
    assert len(line) < 400 and "(50000000 characters)" in line
    line = refused(["sweep", "--out", str(earlier), "--param", f"discard={value}"], capsys)
    assert len(line) < 400 and f"{'x' * QUOTE_LIMIT}'..." in line
    assert_untouched(earlier)


@pytest.mark.parametrize(
    ("param", "needle"),
    [
        ("discard=1.5", "--param discard must be a number in [0, 1], got '1.5'"),
        ("silent_ok=2", "--param silent_ok must be a number in [0, 1], got '2'"),
        ("patience=-1", "--param patience must be a whole number from 0 to 1000, got '-1'"),
        ("detector=nope", "one of 'exact', 'independent' or 'measured:FILE', got 'nope'"),
        ("draw=nope", "one of 'balanced', 'cycle', 'random'"),
        ("confusion=abc", "4x4 confusion matrix"),
        ("confusion=[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[0]]]", "4x4 confusion matrix"),
        ("max_actions_per_gesture=0", "from 1 to 1000, got '0'"),
        ("tables=0", "--param tables must be a whole number from 1 to 1000"),
        ("legs_per_table=0", "--param legs_per_table must be a whole number from 1 to 12"),
        ("legs_per_table=13", "got '13'"),
        ("dicsard=0.3", "unknown learner parameter 'dicsard'"),
    ],
)
def test_sweep_refuses_bad_grid_values_before_the_first_run(
    param: str, needle: str, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    out = tmp_path / "sweep"
    argv = ["sweep", "--reps", "1", "--systems", "pil", "--rates", "1.0", "--quiet"]
    refused([*argv, "--workers", "1", "--out", str(out), "--param", param], capsys, needle)
    assert not out.exists()


def test_sweep_refuses_bad_scenarios_seeds_and_connections(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    out = tmp_path / "sweep"
    empty = tmp_path / "empty.yaml"
    empty.write_text("")
    broken = tmp_path / "broken.yaml"
    broken.write_text("tables: [1\n")
    argv = ["sweep", "--reps", "1", "--systems", "pil", "--rates", "1.0", "--quiet"]
    argv += ["--out", str(out)]
    for extra, needle in (
        (["--param", f"scenario={tmp_path / 'missing.yaml'}"], "cannot read the scenario"),
        (["--param", f"scenario={empty}"], "expected a mapping"),
        (["--param", f"scenario={broken}"], "malformed YAML"),
        (["--seed=-1"], "--seed must be a whole number from 0"),
        (["--tables", "1000000000"], "--tables must be a whole number from 1 to 1000"),
        (["--scheduler", "notanaddress"], "SCHEME://HOST:PORT"),
        (["--scheduler", "tcp://127.0.0.1:8786", "--connect-timeout=-1"], "[0.1, 3600]"),
        (["--workers", "0"], "--workers must be a whole number from 1"),
        (["--kind", "physical", "--param", "legs_per_table=5"], "layout has 4 spots and 4 legs"),
        (["--out", "/proc/robin-pil-x"], "cannot be written"),
    ):
        refused([*argv, *extra], capsys, needle)
        assert not out.exists()


def test_scheduler_not_an_address_prints_no_traceback(tmp_path: Path) -> None:
    done = subprocess.run(
        [
            sys.executable,
            "-m",
            "robin_sim.cli.main",
            "sweep",
            "--scheduler",
            "notanaddress",
            "--out",
            str(tmp_path / "s"),
            "--quiet",
        ],
        capture_output=True,
        text=True,
        timeout=120,
    )
    assert done.returncode == 2
    assert done.stderr.strip().count("\n") == 0 and "Traceback" not in done.stderr
    assert "Exception ignored" not in done.stderr


def test_study_refuses_before_computing(
    tmp_path: Path, earlier: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    latin = tmp_path / "latin.yaml"
    latin.write_bytes(b"tables: 1\nname: caf\xe9\n")
    base = ["study", "--reps", "1", "--rates", "1.0", "--no-progress"]
    refused([*base, "--seed=-1", "--out", str(earlier)], capsys, "--seed", "'-1'")
    refused([*base, "--tables", "1000000000", "--out", str(earlier)], capsys, "from 1 to 1000")
    refused([*base, "--scenario", str(latin), "--out", str(earlier)], capsys, "not UTF-8")
    refused([*base, "--out", str(earlier / "summary.json")], capsys, "is a file")
    refused([*base, "--out", str(earlier / "summary.json" / "x")], capsys, "under the file")
    refused([*base, "--out", "/proc/robin-pil-x"], capsys, "cannot be written")
    assert_untouched(earlier)


def test_report_refuses_unknown_baseline_and_non_utf8(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    results = tmp_path / "results.csv"
    results.write_text("system,rate,gestures\npil,1.0,3\nc1,1.0,4\n")
    refused(["report", str(results), "--baseline", "nope"], capsys, "'nope'", "'c1', 'pil'")
    latin = tmp_path / "latin.csv"
    latin.write_bytes(b"system,rate\ncaf\xe9,1.0\n")
    refused(["report", str(latin)], capsys, "not UTF-8")
    assert not (tmp_path / "report").exists()


def test_a_deeply_nested_table_file_is_a_table_error(tmp_path: Path) -> None:
    from pil.table_io import TableFileError, load_table

    path = tmp_path / "table.json"
    path.write_text("[" * 100_000 + "]" * 100_000)
    with pytest.raises(TableFileError, match="nested too deeply"):
        load_table(path)
