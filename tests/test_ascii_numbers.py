"""Numbers are read as a person types them: ASCII digits, never Python's wider grammar."""

from __future__ import annotations

from pathlib import Path

import pytest

from pil.numbers import parse_decimal, parse_whole
from robin_sim.cli.main import main

NOT_TYPED = ("1_0", "٣", "١", "１", "1_000", "inf", "nan", "0x10", "")


@pytest.mark.parametrize("text", NOT_TYPED)
def test_text_python_reads_as_a_number_is_refused(text: str) -> None:
    with pytest.raises(ValueError, match="digits 0-9"):
        parse_whole(text)
    with pytest.raises(ValueError, match="digits 0-9"):
        parse_decimal(text)


def test_what_a_person_types_is_read() -> None:
    assert parse_whole(" 12 ") == 12 and parse_whole("-3") == -3
    assert parse_decimal("0.5") == 0.5 and parse_decimal(".5") == 0.5
    assert parse_decimal("1e-3") == 0.001 and parse_decimal("2.") == 2.0


@pytest.mark.parametrize(
    ("argv", "needle"),
    [
        (["study", "--reps", "1_0"], "'1_0' is not a whole number"),
        (["study", "--reps", "٣"], "'٣' is not a whole number"),
        (["study", "--rates", "٠.٥", "--reps", "1"], "'٠.٥'"),
        (["episode", "--tables", "١", "--no-video"], "'١'"),
        (["sweep", "--reps", "1", "--systems", "pil", "--param", "patience=1_0"], "'1_0'"),
        (["people", "--reps", "1_0"], "'1_0'"),
        (["replay", "nowhere", "--render-workers", "٢"], "'٢'"),
    ],
)
def test_commands_refuse_numbers_not_typed_in_ascii(
    argv: list[str], needle: str, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    out = tmp_path / "out"
    with pytest.raises(SystemExit) as stopped:  # argparse's own refusal, or the command's
        raise SystemExit(main([*argv, "--out", str(out)]))
    assert stopped.value.code == 2
    assert needle in capsys.readouterr().err
    assert not out.exists()
