"""The ``robin-pil`` command explains itself: version, bare command list, defaults in every help,
one progress switch, and ``--systems`` help from the systems registry."""

from __future__ import annotations

import argparse
import subprocess
import sys

import pytest

from pil.task.systems import SYSTEMS
from robin_sim.cli.help_format import package_version
from robin_sim.cli.main import COMMANDS, build_parser, main


def _subparser(command: str) -> argparse.ArgumentParser:
    parser = build_parser(command)
    sub = next(a for a in parser._actions if isinstance(a, argparse._SubParsersAction))
    return sub.choices[command]


def _option_help(parser: argparse.ArgumentParser, action: argparse.Action) -> str:
    formatter = parser._get_formatter()
    return formatter._expand_help(action) if action.help else ""


VALUE_OPTIONS = [
    (command, action.option_strings[-1])
    for command in COMMANDS
    for action in _subparser(command)._actions
    if action.option_strings
    and action.nargs != 0  # switches (store_true, help) have no default worth a word
    and action.help is not argparse.SUPPRESS
]


@pytest.mark.parametrize(("command", "option"), VALUE_OPTIONS)
def test_every_value_option_shows_its_default(command: str, option: str) -> None:
    parser = _subparser(command)
    action = next(a for a in parser._actions if option in a.option_strings)
    text = _option_help(parser, action)
    assert "default" in text.lower(), f"robin-pil {command} {option}: {text!r}"


def test_help_pages_render_the_defaults(capsys: pytest.CaptureFixture[str]) -> None:
    with pytest.raises(SystemExit) as stop:
        main(["episode", "--help"])
    assert stop.value.code == 0
    page = " ".join(capsys.readouterr().out.split())
    for shown in ("(default: 640x480)", "(default: 30)", "(default: 1.0)", "(default: out)"):
        assert shown in page


def test_version(capsys: pytest.CaptureFixture[str]) -> None:
    with pytest.raises(SystemExit) as stop:
        main(["--version"])
    assert stop.value.code == 0
    assert capsys.readouterr().out.strip() == f"robin-pil {package_version()}"
    assert package_version()[0].isdigit()


def test_bare_command_lists_every_command() -> None:
    done = subprocess.run(
        [sys.executable, "-m", "robin_sim.cli.main"], capture_output=True, text=True, timeout=60
    )
    assert done.returncode == 2  # a missing command is bad input (argparse's convention)
    assert "Traceback" not in done.stderr
    for command in COMMANDS:
        assert f"    {command} " in done.stderr or f"    {command}\n" in done.stderr, command


PROGRESS_COMMANDS = [
    "study",
    "episode",
    "sweep",
    "adapt",
    "transfer",
    "people",
    "train-gestures",
    "vision-conditions",
]


@pytest.mark.parametrize("command", PROGRESS_COMMANDS)
def test_one_progress_switch_with_the_old_name_hidden(command: str) -> None:
    parser = _subparser(command)
    shown = parser.format_help()
    assert "--no-progress" in shown and "--quiet" not in shown
    for switch in ("--no-progress", "--quiet"):
        args = build_parser(command).parse_args([command, switch])
        assert args.no_progress is True
    assert build_parser(command).parse_args([command]).no_progress is False


@pytest.mark.parametrize(("command", "accepts"), [("study", SYSTEMS), ("sweep", SYSTEMS)])
def test_systems_help_lists_every_accepted_system(command: str, accepts: dict) -> None:
    parser = _subparser(command)
    action = next(a for a in parser._actions if "--systems" in a.option_strings)
    text = _option_help(parser, action)
    for name in accepts:
        assert name in text.replace(",", " ").split(), f"{command} --systems help lacks {name}"


def test_the_episode_bar_gives_the_whole_episode_time_left() -> None:
    import io

    from robin_sim.episode.run import progress_bar

    clock = [0.0]
    bar = progress_bar(8, file=io.StringIO(), mininterval=0)
    bar._time = lambda: clock[0]  # tqdm's own clock, stepped by hand
    bar.start_t = bar.last_print_t = 0.0
    for leg in range(4):  # a leg every 60 s, ten steps to a leg, most of them deliver nothing
        for step in range(10):
            clock[0] = leg * 60.0 + (step + 1) * 6.0
            bar.update(1 if step == 9 else 0)
    meter = bar.format_dict
    left = (meter["total"] - meter["n"]) / meter["rate"] if meter["rate"] else None
    if left is None:  # no smoothed rate: tqdm uses the mean, n / elapsed
        left = (meter["total"] - meter["n"]) * meter["elapsed"] / meter["n"]
    assert left == pytest.approx(4 * 60.0), left  # 4 legs to go at 60 s each
    bar.close()
