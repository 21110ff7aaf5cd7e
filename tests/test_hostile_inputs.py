"""Inputs that used to pass the first checks and fail late (or with a traceback).

Each is refused up front (exit 2, one line, nothing written), or now works.
"""

from __future__ import annotations

import csv
import os
import subprocess
import sys
import time
from pathlib import Path

import pytest

from robin_sim.cli.main import main

ROOT = Path(__file__).parents[1]
SWEEP = ["sweep", "--reps", "1", "--systems", "pil", "--quiet", "--no-report"]


def refused(argv: list[str], capsys: pytest.CaptureFixture[str], *needles: str) -> str:
    code = main(argv)
    err = capsys.readouterr().err
    lines = [line for line in err.splitlines() if line.strip()]
    assert code == 2, err
    assert len(lines) == 1 and lines[0].startswith(f"robin-pil {argv[0]}: error: "), err
    for needle in needles:
        assert needle in lines[0], (needle, lines[0])
    return lines[0]


def test_rate_0_is_refused_before_the_episode_starts(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    out = tmp_path / "out"
    started = time.monotonic()
    for argv in (
        ["episode", "--rate", "0", "--no-video", "--quiet"],
        ["episode", "--rate", "0.0", "--no-video", "--quiet"],
        ["study", "--rates", "0,1.0", "--reps", "1", "--no-progress"],
        ["people", "--rates", "0", "--reps", "1", "--no-progress"],
        [*SWEEP, "--rates", "0"],
    ):
        refused([*argv, "--out", str(out)], capsys, "(0, 1]", "never")
    assert time.monotonic() - started < 20
    assert not out.exists()
    refused(["episode", "--rate", "1.5", "--out", str(out)], capsys, "(0, 1]", "'1.5'")


def test_a_missing_measured_file_is_refused_before_the_first_run(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    out = tmp_path / "sweep"
    broken = tmp_path / "broken.json"
    broken.write_text("{")
    for value, needle in (("/nonexistent", "no such file"), (str(broken), "not readable JSON")):
        argv = [*SWEEP, "--rates", "1.0", "--workers", "1", "--out", str(out)]
        refused([*argv, "--param", f"detector=exact,measured:{value}"], capsys, needle, value)
        assert not out.exists()
    refused(
        [
            "episode",
            "--no-video",
            "--quiet",
            "--detector",
            "measured:/nonexistent",
            "--out",
            str(out),
        ],
        capsys,
        "no such file",
    )
    assert not out.exists()


def test_a_tls_scheduler_without_tls_settings_is_one_line_at_once(tmp_path: Path) -> None:
    started = time.monotonic()
    done = subprocess.run(
        [
            sys.executable,
            "-m",
            "robin_sim.cli.main",
            *SWEEP,
            "--scheduler",
            "tls://127.0.0.1:1",
            "--connect-timeout",
            "1",
            "--out",
            str(tmp_path / "s"),
        ],
        capture_output=True,
        text=True,
        timeout=60,
        env={"PATH": "/usr/bin:/bin", "PYTHONPATH": str(ROOT), "HOME": str(tmp_path)},
    )
    assert done.returncode == 2, done.stderr
    assert done.stderr.strip().count("\n") == 0 and "Traceback" not in done.stderr, done.stderr
    assert "TLS settings" in done.stderr and "tcp://" in done.stderr
    assert time.monotonic() - started < 30
    assert not (tmp_path / "s").exists()


def test_people_with_one_table_runs(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    out = tmp_path / "people"
    argv = ["people", "--tables", "1", "--reps", "2", "--rates", "1.0", "--systems", "pil"]
    assert main([*argv, "--no-progress", "--out", str(out)]) == 0, capsys.readouterr().err
    with (out / "people.csv").open() as handle:
        rows = list(csv.DictReader(handle))
    assert {row["mode"] for row in rows} == {"shared", "per-person"}
    assert all(row["tables"] == "1" and row["legs"] == "4" for row in rows)
    assert all(int(row["actions"]) >= int(row["gestures"]) > 0 for row in rows)


def test_devices_and_fifos_as_input_files_are_refused_at_once(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    fifo = tmp_path / "fifo.json"
    os.mkfifo(fifo)
    out = tmp_path / "out"
    started = time.monotonic()
    for path in ("/dev/zero", str(fifo)):
        refused(
            [
                "transfer",
                "--table",
                path,
                "--reps",
                "1",
                "--rates",
                "1.0",
                "--no-progress",
                "--out",
                str(out),
            ],
            capsys,
            "not a regular file",
        )
        refused(
            [
                *SWEEP,
                "--rates",
                "1.0",
                "--workers",
                "1",
                "--out",
                str(out),
                "--param",
                f"detector=measured:{path}",
            ],
            capsys,
            "not a regular file",
        )
    assert time.monotonic() - started < 20
    assert not out.exists()


# --- inputs that were taken silently (issue 26)


def test_a_rate_below_the_smallest_is_refused_like_0(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    from pil.task.params import MIN_RATE

    out = tmp_path / "out"
    for text in ("1e-320", "5e-324", f"{MIN_RATE / 2:g}"):
        refused(
            ["episode", "--rate", text, "--no-video", "--quiet", "--out", str(out)],
            capsys,
            f"'{text}'",
            f"the smallest positive value is {MIN_RATE:g}; less is refused as 0 is",
        )
        refused([*SWEEP, "--rates", text, "--out", str(out)], capsys, "smallest")
    assert not out.exists()


def test_episode_vision_with_a_rate_names_the_valid_combination(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    out = tmp_path / "out"
    for argv in (
        ["episode", "--detector", "vision", "--rate", "0.5"],
        ["episode", "--param", "detector=vision", "--rate", "1.0"],
    ):
        refused([*argv, "--no-video", "--out", str(out)], capsys, "--rate", "--detector vision")
    assert not out.exists()


def test_the_summary_of_a_vision_episode_names_no_rate() -> None:
    from robin_sim.cli.episode_text import summary_text

    fields = {
        "status": "finished",
        "error": "",
        "legs_delivered": 1,
        "legs_total": 1,
        "legs_to_person": 1,
        "legs_placed": 0,
        "system_name": "PIL",
        "scenario": "one_handover",
        "rate": 1.0,
        "seed": 0,
        "gestures": 1,
        "repeats": 0,
        "corrections": 0,
        "actions": 1,
        "rejected": 0,
        "interrupted_actions": 0,
        "drops": 0,
        "handover_success_rate": 1.0,
        "mean_handover_s": 3.0,
        "sim_time_s": 3.0,
        "wall_time_s": 1.0,
    }
    assert "detection rate 1" in summary_text(fields, Path("."))
    shown = summary_text({**fields, "vision": {"readings": 3}}, Path("."))
    assert "detection rate" not in shown and "eye cameras" in shown


def test_adapt_on_bad_yaml_is_our_own_one_line(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    change = tmp_path / "change.yaml"
    change.write_text("name: x\nchange: {from_table: 2,\n  gesture: [unclosed\n")
    line = refused(
        ["adapt", "--change", str(change), "--reps", "1", "--out", str(tmp_path / "o")],
        capsys,
        str(change),
        "malformed YAML at line",
    )
    assert "while parsing" not in line and 'in "<unicode string>"' not in line


@pytest.mark.parametrize(
    "text",
    [
        "tables: 2\ntables: 3\n",
        "name: a\nassembly:\n  tables: 1\n  tables: 2\n",
    ],
)
def test_a_yaml_key_given_twice_is_refused(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], text: str
) -> None:
    scenario = tmp_path / "twice.yaml"
    scenario.write_text(text)
    out = tmp_path / "out"
    refused(
        ["episode", "--scenario", str(scenario), "--no-video", "--out", str(out)],
        capsys,
        "'tables' appears twice",
        "line",
    )
    assert not out.exists()


def test_every_yaml_reader_refuses_a_key_twice(tmp_path: Path) -> None:
    from pil.errors import RobinPilError
    from pil.experiments.adaptation import load_change
    from pil.task.scenario import load_scenario
    from robin_sim.lab.study_file import load_study
    from robin_sim.live.protocol import load_protocol

    twice = "name: a\nname: b\n"
    for load, name in (
        (load_scenario, "s.yaml"),
        (load_protocol, "p.yaml"),
        (load_change, "c.yaml"),
    ):
        path = tmp_path / name
        path.write_text(twice)
        with pytest.raises(RobinPilError, match="'name' appears twice"):
            load(path)
    (tmp_path / "study").mkdir()
    (tmp_path / "study" / "study.yaml").write_text(twice)
    with pytest.raises(RobinPilError, match="'name' appears twice"):
        load_study(tmp_path / "study")
    # and no module reads YAML around that loader
    for source in [*(ROOT / "pil").rglob("*.py"), *(ROOT / "robin_sim").rglob("*.py")]:
        text = source.read_text(encoding="utf-8")
        if source.name != "yaml_files.py":
            for call in ("yaml.safe_load", "yaml.load(", "yaml.full_load", "yaml.unsafe_load"):
                assert call not in text, (source, call)
