"""``robin-pil model-path``: the path it prints is a model MuJoCo loads, from any folder."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import mujoco
import pytest

from robin_sim.cli.main import main
from robin_sim.model import names


def test_prints_the_scene_that_mujoco_loads(capsys: pytest.CaptureFixture) -> None:
    assert main(["model-path"]) == 0
    printed = Path(capsys.readouterr().out.strip())
    assert printed.is_absolute() and printed == names.SCENE_XML.resolve()
    model = mujoco.MjModel.from_xml_path(str(printed))  # includes robin/robin.xml beside it
    assert model.body(names.leg_body(0)).id > 0 and model.body(names.HUMAN_MOCAP_BODY).id > 0


@pytest.mark.parametrize("which", ["robot", "hand-test"])
def test_prints_the_other_models(which: str, capsys: pytest.CaptureFixture) -> None:
    assert main(["model-path", which]) == 0
    printed = Path(capsys.readouterr().out.strip())
    assert printed.suffix == ".xml" and printed.is_file()
    mujoco.MjModel.from_xml_path(str(printed))


def test_works_from_another_folder(tmp_path: Path) -> None:
    result = subprocess.run(
        [sys.executable, "-m", "robin_sim.cli.main", "model-path"],
        cwd=tmp_path,
        capture_output=True,
        text=True,
        timeout=60,
        check=False,
        env={**os.environ, "PYTHONSAFEPATH": "1"},  # nothing from the folder it runs in
    )
    assert result.returncode == 0, result.stderr
    assert Path(result.stdout.strip()) == names.SCENE_XML.resolve()


def test_an_unknown_model_is_refused_listing_the_valid_ones(
    capsys: pytest.CaptureFixture,
) -> None:
    with pytest.raises(SystemExit) as raised:
        main(["model-path", "table"])
    assert raised.value.code == 2
    assert "choose from 'scene', 'robot', 'hand-test'" in capsys.readouterr().err
