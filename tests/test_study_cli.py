"""``robin-pil study`` through the real CLI entry point."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest

from robin_sim.cli.main import main


def test_study_command_writes_its_outputs(tmp_path: Path, capsys: pytest.CaptureFixture) -> None:
    out = tmp_path / "study"
    code = main(
        [
            "study",
            "--reps",
            "2",
            "--tables",
            "2",
            "--rates",
            "0.6,1.0",
            "--out",
            str(out),
            "--no-progress",
        ]
    )
    assert code == 0
    assert {p.name for p in out.iterdir()} == {
        "runs.csv",
        "claim_runs.csv",
        "tests.csv",
        "summary.md",
        "gestures.png",
        "actions.png",
        "training.png",
        "reps.jsonl",  # the finished repetitions (a rerun resumes from them)
    }
    assert "20 runs" in capsys.readouterr().out


@pytest.mark.parametrize(
    ("argv", "message"),
    [
        (
            ["--rates", "1.5"],
            "detection rate (comma separated) must be a number in (0, 1], got '1.5'",
        ),
        (["--rates", "0.4,abc"], "must be a number in (0, 1], got 'abc'"),
        (["--reps", "0"], "--reps must be a whole number from 1 to 100000, got 0"),
        (["--seed", "-1"], "--seed must be a whole number from 0 to"),
        (["--rates", "0.4,0.6,0.4"], "rate 0.4 is given twice"),
        (["--systems", "pil,robot"], "unknown --systems: system 'robot'; valid choices: 'pil'"),
        (["--systems", "pil,tamer,pil"], "system 'pil' is given twice"),
    ],
)
def test_bad_input_exits_2_with_one_clear_message(
    tmp_path: Path, capsys: pytest.CaptureFixture, argv: list[str], message: str
) -> None:
    out = tmp_path / "never"
    assert main(["study", *argv, "--out", str(out), "--no-progress"]) == 2
    err = capsys.readouterr().err
    assert message in err and err.startswith("robin-pil study: error:")
    assert not out.exists()


def test_study_cli_imports_fast_without_mujoco() -> None:
    code = "import sys, robin_sim.cli.study, pil.experiments.study; print('mujoco' in sys.modules)"
    result = subprocess.run(
        [sys.executable, "-c", code], capture_output=True, text=True, check=True
    )
    assert result.stdout.strip() == "False"


def test_study_command_never_loads_mujoco(tmp_path: Path) -> None:
    code = (
        "import sys\n"
        "from robin_sim.cli.main import main\n"
        f"code = main(['study', '--reps', '1', '--tables', '1', '--rates', '1.0', '--out', "
        f"{str(tmp_path)!r}, '--no-progress'])\n"
        "print(code, 'mujoco' in sys.modules)\n"
    )
    result = subprocess.run(
        [sys.executable, "-c", code], capture_output=True, text=True, check=True
    )
    assert result.stdout.split()[-2:] == ["0", "False"]


def _out_cases(tmp_path: Path) -> dict[str, tuple[Path, str]]:
    a_file = tmp_path / "a_file"
    a_file.write_text("kept\n")
    return {
        "a file": (a_file, "is a file"),
        "under a file": (a_file / "sub", "lies under"),
        "unwritable": (Path("/proc/robin-pil-study"), "cannot be written"),
    }


@pytest.mark.parametrize("case", ["a file", "under a file", "unwritable"])
def test_bad_out_is_refused_before_anything_runs(
    tmp_path: Path, capsys: pytest.CaptureFixture, case: str
) -> None:
    out, message = _out_cases(tmp_path)[case]
    # progress on: a started study would draw its bar on stderr before any error
    assert main(["study", "--reps", "20", "--out", str(out)]) == 2
    err = capsys.readouterr().err
    assert err.startswith("robin-pil study: error: --out ") and message in err
    assert len(err.strip().splitlines()) == 1, err
    assert (tmp_path / "a_file").read_text() == "kept\n"


def test_study_runs_the_baselines_beside_pil(tmp_path: Path) -> None:
    out = tmp_path / "baselines"
    argv = [
        "study",
        "--systems",
        "pil,bandit,tamer",
        "--reps",
        "2",
        "--tables",
        "1",
        "--rates",
        "0.6",
        "--out",
        str(out),
        "--no-progress",
    ]
    assert main(argv) == 0
    text = (out / "summary.md").read_text()
    for system in ("bandit", "tamer"):
        assert f"| 0.6 | {system} | 2 |" in text
        assert f"| gestures | test tables only | 0.6 | pil | {system} | paired t |" in text
    assert "training" not in {p.stem for p in out.iterdir()}  # no pre-trained system: no figure
