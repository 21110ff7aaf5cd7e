"""A live session's options: every bad value is refused with one clear error, nothing written."""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path

import pytest

from pil.errors import RobinPilError
from pil.task.seeds import block_seed
from robin_sim.live.config import LiveConfig
from robin_sim.live.files import session_folder
from robin_sim.live.session import LiveSession


@pytest.mark.parametrize(
    ("changes", "message"),
    [
        ({"participant": "P 1"}, "participant 'P 1' is not a valid name; use 1-32 letters"),
        ({"participant": "x" * 33}, "is not a valid name"),
        ({"session": "../up"}, "session '../up' is not a valid name"),
        ({"system": "robot"}, "unknown system 'robot'; valid choices: 'pil', 'c1'"),
        ({"scenario": "nowhere"}, "one of the shipped scenarios: assembly"),
        ({"handover_types": ("A", "Q")}, "unknown handover type 'Q'; valid choices: A, B, C"),
        ({"handover_types": ()}, "handover_types must be a non-empty list"),
        ({"width": 641}, "frame size must be even"),
        ({"height": 0}, "frame height must be a whole number from 2 to 1920"),
        ({"fps": 14.5}, "fps must be a whole number from 1 to 60, got 14.5"),
        ({"fps": 0}, "fps must be a whole number from 1 to 60, got 0"),
        ({"speed": float("nan")}, "speed must be a number from 0.1 to 10.0, got nan"),
        ({"speed": 50}, r"speed must lie in \[0.1, 10.0\]"),
        ({"feedback_window": -1}, r"feedback_window must lie in \[0.5, 60.0\]"),
        ({"seed": -3}, "seed"),
        ({"block": -1}, "block must be a whole number from 0"),
        ({"video": "yes"}, "video must be true or false"),
        ({"render_workers": 99}, "render_workers must be a whole number from 0 to 64"),
    ],
)
def test_bad_options_are_refused_before_anything_is_built(
    tmp_path: Path, changes: dict, message: str
) -> None:
    with pytest.raises(RobinPilError, match=message):
        LiveSession(LiveConfig(out_root=tmp_path, **changes))
    assert list(tmp_path.iterdir()) == []


def test_the_block_types_and_the_default_scenario() -> None:
    assert LiveConfig().checked().scenario_of().tables == 1  # the assembly: one table
    block = LiveConfig(scenario="assembly", handover_types=("B", "A")).checked()
    assert [t.name for t in block.scenario_of().pool()] == ["B", "A"]


def test_session_names_never_reuse_a_folder(tmp_path: Path) -> None:
    first = session_folder(LiveConfig(out_root=tmp_path))
    first.mkdir(parents=True)
    second = session_folder(LiveConfig(out_root=tmp_path))
    assert second != first and second.parent == first.parent == tmp_path / "P01"


def test_the_scenario_file_is_loaded_once(monkeypatch: pytest.MonkeyPatch) -> None:
    """checked() loads the scenario and builds the learner side; checking again (the
    conductor, the session) and run_spec() reuse it; a changed scenario is loaded anew."""
    import robin_sim.live.config as spec_module

    loads: list[object] = []
    real = spec_module.load_scenario

    def counting(*args: object) -> object:
        loads.append(args)
        return real(*args)  # type: ignore[arg-type]

    monkeypatch.setattr(spec_module, "load_scenario", counting)
    config = LiveConfig(scenario="assembly", handover_types=("B", "A")).checked()
    again = config.checked()
    spec = again.run_spec()
    assert [t.name for t in again.scenario_of().pool()] == ["B", "A"]
    assert spec.scenario.sequence == ("B", "A") and spec.seed == 0 and len(loads) == 1
    assert replace(config, scenario="one_handover", handover_types=None).checked().run_spec()
    assert len(loads) == 2


def test_a_block_changes_only_a_blocks_fields_of_a_checked_config() -> None:
    """for_block is for a checked config, and only for the block's own fields (the shared
    options were checked once): anything else is refused naming the valid fields."""
    with pytest.raises(RobinPilError, match="call checked\\(\\) first"):
        LiveConfig().for_block(block=1)
    checked = LiveConfig(study_seed=4, participant="P03").checked()
    assert checked.seed == block_seed(4, "P03", 0)  # derived, as the command line's --seed
    block = checked.for_block(block=2, system="c1")
    assert block.is_checked and (block.seed, block.system) == (block_seed(4, "P03", 2), "c1")
    with pytest.raises(RobinPilError, match=r"not \['speed'\]; valid: block, block_actions"):
        checked.for_block(speed=3.0)
    with pytest.raises(RobinPilError, match="system"):
        checked.for_block(system="nope")
