"""``robin-pil study`` through the real CLI entry point."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest

from robin_sim.cli.main import main


def test_study_command_writes_its_outputs(tmp_path: Path, capsys: pytest.CaptureFixture) -> None:
    out = tmp_path / "study"
    code = main(["study", "--reps", "2", "--tables", "2", "--rates", "0.6,1.0", "--out", str(out),
                 "--no-progress"])  # fmt: skip
    assert code == 0
    assert {p.name for p in out.iterdir()} == {
        "runs.csv", "summary.md", "gestures.png", "actions.png", "training.png"
    }  # fmt: skip
    assert "20 runs" in capsys.readouterr().out


@pytest.mark.parametrize(
    ("argv", "message"),
    [
        (["--rates", "1.5"], "--rates must be a number in [0, 1], got '1.5'"),
        (["--rates", "0.4,abc"], "--rates must be a number in [0, 1], got 'abc'"),
        (["--reps", "0"], "--reps must be a whole number from 1 to 100000, got '0'"),
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
    result = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                            check=True)  # fmt: skip
    assert result.stdout.strip() == "False"


def test_study_command_never_loads_mujoco(tmp_path: Path) -> None:
    code = (
        "import sys\n"
        "from robin_sim.cli.main import main\n"
        f"code = main(['study', '--reps', '1', '--tables', '1', '--rates', '1.0', '--out', "
        f"{str(tmp_path)!r}, '--no-progress'])\n"
        "print(code, 'mujoco' in sys.modules)\n"
    )
    result = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                            check=True)  # fmt: skip
    assert result.stdout.split()[-2:] == ["0", "False"]
