"""The studies beyond the paper: the same seed gives byte-identical result files."""

from __future__ import annotations

from pathlib import Path

import pytest

from robin_sim.cli.main import main

COMMANDS = {
    "adapt": ["adapt", "--systems", "pil,tamer", "--rates", "0.8"],
    "transfer": ["transfer", "--systems", "pil", "--rates", "0.8"],
    "people": ["people", "--systems", "pil", "--rates", "0.8", "--tables", "4"],
}
FILES = {"adapt": "adaptation.csv", "transfer": "transfer.csv", "people": "people.csv"}


@pytest.mark.parametrize("command", sorted(COMMANDS))
def test_same_seed_same_results_file(tmp_path: Path, command: str) -> None:
    texts = []
    for seed, name in ((3, "a"), (3, "b"), (4, "c")):
        argv = [*COMMANDS[command], "--reps", "3", "--seed", str(seed), "--no-progress"]
        assert main([*argv, "--out", str(tmp_path / name)]) == 0
        texts.append((tmp_path / name / FILES[command]).read_bytes())
    assert texts[0] == texts[1]
    assert texts[0] != texts[2]


BAD = [
    (["--seed", "-1"], "--seed must be"),
    (["--reps", "0"], "--reps must be"),
    (["--rates", "0.8,0.8"], "given twice"),
]


@pytest.mark.parametrize("command", sorted(COMMANDS))
@pytest.mark.parametrize(("extra", "message"), BAD)
def test_bad_common_options_exit_2_before_anything_runs(
    tmp_path: Path, capsys: pytest.CaptureFixture, command: str, extra: list[str], message: str
) -> None:
    out = tmp_path / "never"
    assert main([command, *extra, "--out", str(out)]) == 2
    err = capsys.readouterr().err
    assert err.startswith(f"robin-pil {command}: error:") and message in err
    assert len(err.strip().splitlines()) == 1 and not out.exists()
