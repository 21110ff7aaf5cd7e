"""Hostile scenario files: wrong types, alias bombs, devices and huge files are refused fast."""

from __future__ import annotations

import os
import time
from pathlib import Path

import pytest

from pil.task.scenario import ScenarioError, load_scenario
from robin_sim.cli.main import main

TYPES = Path(__file__).parents[1] / "scenarios" / "handover_types.yaml"


def scenario_file(tmp_path: Path, text: str) -> Path:
    """A scenario beside a copy of the shipped handover types."""
    (tmp_path / "handover_types.yaml").write_text(TYPES.read_text())
    path = tmp_path / "scenario.yaml"
    path.write_text("types: handover_types.yaml\n" + text)
    return path


# a few hundred bytes that expand to 10**8 list items when aliases are followed
BOMB = "a: &a [lol]\n" + "".join(
    f"{chr(97 + i)}: &{chr(97 + i)} [" + ", ".join([f"*{chr(96 + i)}"] * 10) + "]\n"
    for i in range(1, 9)
)


@pytest.mark.parametrize(
    ("text", "needle"),
    [
        ("name: [1, 2]\n", "name: expected a text, got [1, 2]"),
        ("name: {a: 1}\n", "name: expected a text"),
        ("description: [x]\n", "description: expected a text"),
        ("name: " + "x" * 3000 + "\n", "name: at most 2000 characters"),
        ("x: &x [1, 2]\nname: *x\n", "aliases"),
    ],
)
def test_every_scenario_key_is_type_checked(tmp_path: Path, text: str, needle: str) -> None:
    with pytest.raises(ScenarioError, match=r"scenario\.yaml") as caught:
        load_scenario(scenario_file(tmp_path, text))
    assert needle in str(caught.value)


def test_a_type_description_is_type_checked(tmp_path: Path) -> None:
    path = tmp_path / "scenario.yaml"
    steps = "[pointing -> object, grasp -> close, give me -> human, release -> open]"
    path.write_text(f"types:\n  a:\n    description: [1]\n    steps: {steps}\n")
    with pytest.raises(ScenarioError, match=r"types\.a: description: expected a text"):
        load_scenario(path)


@pytest.mark.parametrize("key", ["name", "tables"])
def test_an_alias_bomb_is_refused_at_once(tmp_path: Path, key: str) -> None:
    path = tmp_path / "bomb.yaml"
    path.write_text(BOMB + f"{key}: *i\n")
    assert path.stat().st_size < 1500
    started = time.monotonic()
    with pytest.raises(ScenarioError, match="aliases"):
        load_scenario(path)
    assert time.monotonic() - started < 2.0


def test_a_device_a_fifo_and_a_huge_file_are_refused_at_once(tmp_path: Path) -> None:
    fifo = tmp_path / "fifo.yaml"
    os.mkfifo(fifo)
    huge = tmp_path / "huge.yaml"
    huge.write_text("name: x\n" + "#" * 2_000_000 + "\n")
    started = time.monotonic()
    for path, needle in (
        (Path("/dev/zero"), "not a regular file"),
        (fifo, "not a regular file"),
        (tmp_path, "not a regular file"),
        (huge, "larger than 1,000,000 bytes"),
    ):
        with pytest.raises(ScenarioError, match=needle):
            load_scenario(path)
    assert time.monotonic() - started < 2.0


def test_episode_refuses_dev_zero_and_a_bomb_with_exit_2(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    bomb = tmp_path / "bomb.yaml"
    bomb.write_text(BOMB + "name: *i\n")
    out = tmp_path / "out"
    for scenario, needle in (("/dev/zero", "not a regular file"), (str(bomb), "aliases")):
        argv = ["episode", "--no-video", "--no-verify", "--quiet", "--out", str(out)]
        assert main([*argv, "--scenario", scenario]) == 2
        err = capsys.readouterr().err.strip()
        assert err.count("\n") == 0 and needle in err, err
    assert not out.exists()


def test_a_study_file_refuses_aliases_and_devices(tmp_path: Path) -> None:
    from pil.experiments.study_files import read_study_file

    bomb = tmp_path / "change.yaml"
    bomb.write_text(BOMB + "scenario: *i\n")
    for path, needle in ((bomb, "aliases"), (Path("/dev/zero"), "not a regular file")):
        with pytest.raises(ScenarioError, match=needle):
            read_study_file(path, ("scenario", "a", "b", "c", "d", "e", "f", "g", "h", "i"), "x")
