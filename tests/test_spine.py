"""One spine (issue 18): a run's values are parsed once at the edge into a RunSpec, one
assembly builds every kind of run, and a run's sub-seeds are derived in one place.

The counts are real: :meth:`ParamSpec.parse` (the one registry's check) is wrapped, the real
method still runs, and the episode command runs from its command line to the world's end.
"""

from __future__ import annotations

import ast
import json
from collections import Counter
from pathlib import Path
from typing import Any

import pytest

from pil.task.assemble import assemble, script_of
from pil.task.param_spec import ParamSpec
from pil.task.params import ASSEMBLY, PARAMS
from pil.task.seeds import block_seed, sub_seeds
from pil.task.spec import (
    DetectorSettings,
    LearnerSettings,
    PersonSettings,
    group_params,
    parse_run_spec,
)

ROOT = Path(__file__).resolve().parents[1]


# the checks besides the registry's specs, by the name they are counted under: the system's
# name, the video frame's size and a confusion matrix (a matrix parameter's own check)
VALIDATORS: dict[str, tuple[str, str]] = {
    "system": ("pil.task.systems", "check_system"),
    "frame size": ("robin_sim.render.frame_spec", "check_size"),
    "confusion matrix": ("pil.task.detector", "check_confusion"),
}
# modules that import one of the VALIDATORS by name (whatever the earlier tests loaded)
CHECKING_MODULES = (
    "pil.task.spec",
    "pil.experiments.study",
    "robin_sim.episode.physical_run",
    "robin_sim.episode.config",
    "robin_sim.live.config",
)


@pytest.fixture
def parse_calls(monkeypatch: pytest.MonkeyPatch) -> Counter[str]:
    """Every validation counted by what it checks (the real checks run): each ParamSpec.parse
    by its parameter's name, and each of :data:`VALIDATORS` wherever it was imported. The
    constructors (Detector, ScriptedPerson, Learner, the agents) check nothing: they take
    the values the edge parsed."""
    import importlib
    import sys

    calls: Counter[str] = Counter()
    real = ParamSpec.parse

    def counting(self: ParamSpec, value: Any, label: str | None = None) -> Any:
        calls[self.name] += 1
        return real(self, value, label)

    monkeypatch.setattr(ParamSpec, "parse", counting)
    for module in CHECKING_MODULES:  # loaded now, so that their imported checks are counted
        importlib.import_module(module)
    for what, (module, name) in VALIDATORS.items():
        check = getattr(importlib.import_module(module), name)

        def counted(*args: Any, _check: Any = check, _what: str = what, **kwargs: Any) -> Any:
            calls[_what] += 1
            return _check(*args, **kwargs)

        for loaded in list(sys.modules.values()):
            if getattr(loaded, "__name__", "").split(".")[0] in ("pil", "robin_sim") and (
                getattr(loaded, name, None) is check
            ):
                monkeypatch.setattr(loaded, name, counted)
    return calls


@pytest.mark.slow
def test_an_episode_from_the_cli_to_the_world_checks_each_value_once(
    parse_calls: Counter[str], tmp_path: Path
) -> None:
    from robin_sim.cli.main import main

    argv = [
        "episode",
        "--no-video",
        "--no-verify",
        "--no-progress",
        "--scenario",
        "one_handover",
        "--rate",
        "0.8",
        "--seed",
        "2",
        "--system",
        "c1",
        "--size",
        "320x240",
        "--fps",
        "24",
        "--camera",
        "side",
        "--param",
        "discard=0.3",
        "--param",
        "reaction_time=0.5",
        "--param",
        "exploration=avoid-last",
        "--out",
        str(tmp_path),
    ]
    assert main(argv) == 0
    summary = json.loads((tmp_path / "summary.json").read_text())
    assert summary["status"] == "finished" and summary["rate"] == 0.8
    assert summary["person"]["reaction_time"] == 0.5
    given = {"rate", "seed", "scenario", "size", "fps", "camera", "discard", "reaction_time"}
    given |= {"exploration", "render_workers", "system", "frame size"}
    # --size is two values (width and height), each checked once, and the pair once (even,
    # within the off-screen buffer) by check_size at the edge: no renderer checks it again
    assert parse_calls.pop("size") == 2
    # the scenario file's own assembly keys are checked once, when the file is read
    file_keys = set(ASSEMBLY)
    assert set(parse_calls) == (given - {"size"}) | file_keys, parse_calls
    assert all(count == 1 for count in parse_calls.values()), parse_calls


@pytest.mark.parametrize("system", ["c3", "bandit"])
def test_a_learner_run_checks_each_value_once(parse_calls: Counter[str], system: str) -> None:
    """Every value given is checked once (the learner's exploration rule and the agent's
    settings included): by the registry, not again by the constructors."""
    from pil.experiments.run_row import spec_row

    given = {"discard": "0.3", "patience": "2", "exploration": "avoid-last", "epsilon": "0.2"}
    spec = parse_run_spec(system=system, rate="0.6", seed="4", params={"tables": "1", **given})
    row = spec_row(spec)
    assert row["tables"] == 1 and row["discard"] == 0.3 and row["patience"] == 2
    names = {"rate", "seed", "system", *given}
    # the scenario file's own assembly keys: checked once, when the file is read
    assert set(parse_calls) == names | set(ASSEMBLY), parse_calls
    assert all(parse_calls[name] == 1 for name in names), parse_calls
    # tables: once as given, once as the scenario file's own value when the file is read
    assert parse_calls["tables"] == 2, parse_calls


def test_a_sweep_checks_each_value_once(parse_calls: Counter[str]) -> None:
    """The grid parses every value once and each row once into its typed spec (the scenario
    file read once for the sweep); the worker (called here in this process) runs the typed
    spec as given: nothing is parsed again, no ``**params`` spread, and the row is the one a
    learner run of the same values given as text makes."""
    from learner_rows import learner_row

    from pil.experiments.sweep_exec import execute_run
    from pil.experiments.sweep_grid import build_grid
    from pil.experiments.sweep_kinds import load_kind
    from pil.task.spec import RunSpec

    kind = load_kind("learner")
    grid = build_grid(
        kind,
        systems=["pil", "c1"],
        rates=["0.6", "1.0"],
        reps=2,
        params=["discard=0,0.3", "patience=2"],
        tables=1,
    )
    runs = grid.runs()
    assert all(isinstance(run.spec, RunSpec) for run in runs)
    outcomes = [execute_run(kind.run, run.spec) for run in runs]
    assert len(outcomes) == 2 * 2 * 2 * 2, len(outcomes)
    assert all(outcome["status"] == "ok" for outcome in outcomes), outcomes[0]
    # once each value as given (two rates, two discards), once the table count and the seed
    assert parse_calls.pop("rate") == 2 and parse_calls.pop("discard") == 2, parse_calls
    assert parse_calls.pop("patience") == 1 and parse_calls.pop("seed") == 1, parse_calls
    assert parse_calls.pop("reps") == 1, parse_calls
    assert parse_calls.pop("system", 0) == 0, parse_calls  # checked against the kind's systems
    # tables: once as given, once as the scenario file's own value when the file is read once
    assert parse_calls.pop("tables") == 2, parse_calls
    assert parse_calls == Counter(dict.fromkeys(set(ASSEMBLY) - {"tables"}, 1)), parse_calls
    last = runs[-1]
    text = {name: str(value) for name, value in last.params}
    again = learner_row(last.system, str(last.rate), str(last.seed), **text)
    assert {k: v for k, v in outcomes[-1]["metrics"].items() if k in again} == again


@pytest.mark.slow
def test_a_physical_sweep_parses_each_value_once(parse_calls: Counter[str], tmp_path: Path) -> None:
    """A physical sweep's grid to the episode's end: each value checked once (by the grid),
    each row parsed once into an EpisodeSpec, which the worker (called here in this process,
    so that its checks are counted) runs as given, to a flat row with the legs delivered."""
    from pil.experiments.sweep_exec import execute_run
    from pil.experiments.sweep_grid import build_grid
    from pil.experiments.sweep_kinds import load_kind
    from robin_sim.episode.config import EpisodeSpec

    kind = load_kind("physical")
    grid = build_grid(
        kind,
        systems=["pil"],
        rates=["1.0"],
        reps=1,
        params=["legs_per_table=1", "verify=false"],
        tables=None,
    )
    runs = grid.runs()
    assert all(isinstance(run.spec, EpisodeSpec) for run in runs)
    outcomes = [execute_run(kind.run, run.spec) for run in runs]
    assert [o["status"] for o in outcomes] == ["ok"], outcomes
    row = outcomes[0]["metrics"]  # a flat row: the summary's fields and the share delivered
    assert row["ended"] == "finished" and row["error"] == "" and row["physical_failures"] == 0
    assert (row["legs_total"], row["legs_delivered"], row["legs_delivered_fraction"]) == (1, 1, 1.0)
    assert row["sim_time_s"] > 0 and not any(isinstance(v, dict) for v in row.values())
    for name in ("rate", "seed", "reps", "verify"):
        assert parse_calls.pop(name) == 1, (name, parse_calls)
    # legs_per_table: once as given, once as the scenario file's own value (read once)
    assert parse_calls.pop("legs_per_table") == 2, parse_calls
    assert parse_calls == Counter(dict.fromkeys(set(ASSEMBLY) - {"legs_per_table"}, 1))


def test_a_live_session_checks_each_value_once(
    parse_calls: Counter[str], tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """``robin-pil live`` from its command line to the sessions the conductor holds: each
    value checked once, by the session's config (the command line passes --speed and the
    watchdog's limits as text; the conductor and the session take the checked config as it
    is). Its own checks are counted by the value they check, beside the registry's."""
    from robin_sim.cli.live import session_configs
    from robin_sim.cli.main import build_parser
    from robin_sim.live import config as live_config
    from robin_sim.live import limits
    from robin_sim.live.conductor import Conductor

    for name in ("_name", "_whole", "_number"):
        real = getattr(live_config, name)

        def counted(value: Any, what: str, *args: Any, _real: Any = real) -> Any:
            parse_calls[what] += 1
            return _real(value, what, *args)

        monkeypatch.setattr(live_config, name, counted)
    real_watchdog = limits.WatchdogLimits.checked

    def watchdog(self: Any) -> Any:
        parse_calls["max_attempts"] += 1
        parse_calls["max_step_seconds"] += 1
        return real_watchdog(self)

    monkeypatch.setattr(limits.WatchdogLimits, "checked", watchdog)
    argv = ["live", "--participant", "P07", "--system", "c1", "--speed", "2", "--seed", "3"]
    argv += ["--max-attempts", "5", "--no-video", "--session", "s1", "--out", str(tmp_path)]
    configs = session_configs(build_parser("live").parse_args(argv))
    conductor = Conductor(configs)
    (config,) = conductor.configs
    assert conductor.sessions[0].config is config and config.speed == 2.0
    assert (config.participant, config.system, config.max_attempts) == ("P07", "c1", 5)
    # the study seed once, by the config (the command line passes --seed as text); the
    # session's own seed is derived from it (pil.task.seeds), not parsed again
    assert parse_calls.pop("seed") == 1, parse_calls
    assert (config.study_seed, config.seed) == (3, block_seed(3, "P07", 0))
    assert parse_calls.pop("size") == 2, parse_calls  # the frame's width and height, once each
    file_keys = dict.fromkeys(ASSEMBLY, 1)  # the scenario file's keys, read once
    own = ["participant", "session", "system", "frame size", "fps", "speed", "feedback_window"]
    own += ["render_workers", "stream_level", "max_attempts", "max_step_seconds"]
    assert parse_calls == Counter({**file_keys, **dict.fromkeys(own, 1)}), parse_calls


def test_a_protocols_blocks_check_the_shared_options_once(
    parse_calls: Counter[str], tmp_path: Path
) -> None:
    """``live --protocol``: the options every block shares (speed, frame, fps, the study seed,
    the watchdog's limits) are checked once, before the protocol file is read; each block
    checks only its own values (its condition, its session folder), its seed derived."""
    from robin_sim.cli.live import session_configs
    from robin_sim.cli.main import build_parser

    argv = ["live", "--participant", "P02", "--protocol", "reactive_vs_proactive"]
    argv += ["--speed", "2", "--seed", "7", "--no-video", "--out", str(tmp_path)]
    configs = session_configs(build_parser("live").parse_args(argv))
    assert len(configs) == 4 and all(c.is_checked for c in configs)
    assert [c.seed for c in configs] == [block_seed(7, "P02", k) for k in range(4)]
    for shared in ("seed", "fps", "frame size"):
        assert parse_calls[shared] == 1, (shared, parse_calls)
    assert parse_calls["size"] == 2, parse_calls  # width and height, once each
    assert parse_calls["system"] == 1 + len(configs), parse_calls  # --system, then each block's
    # the scenario files: the default (the options' own) and the protocol's, each read once,
    # and the protocol's once more by the protocol loader (checking its blocks' types)
    assert all(parse_calls[key] <= 3 for key in ASSEMBLY), parse_calls


@pytest.mark.slow
def test_the_episode_walk_goes_down_without_returning() -> None:
    """The episode's config from the command line to the assembled run (stopped before the
    step loop; tests/config_walk.py): handed down the layers it never climbs back up nor
    returns to a module it left. Read as data (the config objects' own methods counted too)
    it makes 8 stops and comes back 3 times, each to read the typed config, never to check it:
    cli.episode makes the EpisodeConfig and then parses it (two calls into the config
    module), the learner's assembly applies the system's own parameters
    (RunSpec.effective) and reads the scenario's types (Scenario's methods)."""
    import tempfile

    from config_walk import ARGV, walk_episode

    with tempfile.TemporaryDirectory() as folder:
        handed = walk_episode([*ARGV, str(Path(folder) / "a")], methods=False)
        data = walk_episode([*ARGV, str(Path(folder) / "b")])
        every = walk_episode([*ARGV, str(Path(folder) / "c")], data=False)
    assert handed.figures()["returns"] == 0 and handed.figures()["climbs"] == 0, handed.returns
    assert data.figures()["climbs"] == 0 and every.figures()["climbs"] == 0, every.climbs
    assert data.figures()["stops"] <= 8 and data.figures()["returns"] <= 3, data.returns
    assert set(data.returns) <= {
        ("robin_sim.cli.episode", "robin_sim.episode.config"),
        ("pil.task.assemble", "pil.task.spec"),
        ("pil.task.assemble", "pil.task.scenario"),
    }, data.returns


def test_the_settings_cover_the_registry_exactly() -> None:
    """Each run parameter is a field of exactly one settings class (or an assembly field of
    the scenario): the typed spec and the registry name the same facts."""
    names = [
        *group_params(LearnerSettings),
        *group_params(PersonSettings),
        *group_params(DetectorSettings),
    ]
    assert len(names) == len(set(names))
    assert set(names) | set(ASSEMBLY) == set(PARAMS) and not set(names) & set(ASSEMBLY)


def test_every_part_draws_from_the_specs_sub_seeds() -> None:
    spec = parse_run_spec(system="c1", rate=0.6, seed=7, params={"tables": 1})
    seeds = sub_seeds(7)
    assert spec.seeds == seeds and seeds.body == 7
    run = assemble(spec)
    test = seeds.phase("test")
    assert run.person.script == script_of(spec.scenario, "test", test)
    again = assemble(parse_run_spec(system="c1", rate=0.6, seed=7, params={"tables": 1}))
    assert [r.to_dict() for r in run.steps()] == [r.to_dict() for r in again.steps()]
    assert sub_seeds(8) != seeds and len(set(seeds.words)) == len(seeds.words)


def _calls(path: Path, names: set[str]) -> list[str]:
    found = []
    for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
        if isinstance(node, ast.Call):
            func = node.func
            name = func.attr if isinstance(func, ast.Attribute) else getattr(func, "id", "")
            if name in names:
                found.append(name)
    return found


def test_sub_seeds_are_derived_in_one_place() -> None:
    """Only pil/task/seeds.py turns a run seed into sub-seeds; robin_sim never derives one,
    and the body and the eye cameras are built (and seeded) only by robin_sim's assembly."""
    derivers = {"SeedSequence", "derive_seeds", "sub_seeds"}
    run_path = [
        *(ROOT / "pil" / "task").glob("*.py"),
        ROOT / "pil" / "experiments" / "run_row.py",
        *(ROOT / "robin_sim").rglob("*.py"),
    ]
    deriving = {str(p.relative_to(ROOT)) for p in run_path if "SeedSequence" in _calls(p, derivers)}
    assert deriving == {"pil/task/seeds.py"}
    in_robin = {
        str(p.relative_to(ROOT))
        for p in (ROOT / "robin_sim").rglob("*.py")
        if _calls(p, {"derive_seeds", "sub_seeds"})
    }
    assert in_robin == set()
    builders = {
        str(p.relative_to(ROOT))
        for p in (ROOT / "robin_sim").rglob("*.py")
        if _calls(p, {"PhysicalBody", "VisionDetector"})
        and "vision/" not in str(p.relative_to(ROOT / "robin_sim"))
    }
    assert builders == {"robin_sim/episode/physical_assembly.py"}


def test_the_vision_detector_is_a_registry_entry_not_a_swap() -> None:
    from pil.task.assemble import DETECTORS
    from pil.task.detector import CAMERAS

    assert CAMERAS not in DETECTORS  # learner-only runs have no eyes
    with pytest.raises(Exception, match="eye cameras"):
        parse_run_spec(params={"detector": CAMERAS})  # refused at the edge, once
    spec = parse_run_spec(params={"detector": CAMERAS}, world="physical")
    assert spec.detector.model == CAMERAS  # kept as given: no swap for 'exact'
    source = (ROOT / "robin_sim" / "episode" / "physical_assembly.py").read_text()
    assert "CAMERAS as VISION" in source and "VISION: vision_factory(" in source
    assert not (ROOT / "robin_sim" / "episode" / "reading.py").exists()


def test_the_public_api_imports_lazily() -> None:
    """``from robin_sim import PhysicalWorld, run_episode, RunSpec, assemble_physical`` works;
    importing the packages alone pulls in neither MuJoCo nor the run assembly."""
    import subprocess
    import sys

    code = (
        "import sys, pil, robin_sim\n"
        "assert 'mujoco' not in sys.modules and 'pil.task.assemble' not in sys.modules\n"
        "from robin_sim import PhysicalWorld, RunSpec, assemble_physical, run_episode\n"
        "import pil\n"
        "assert pil.RunSpec is RunSpec and callable(assemble_physical) and callable(run_episode)\n"
        "assert set(robin_sim.__all__) <= set(dir(robin_sim)) and 'mujoco' in sys.modules\n"
        "print(PhysicalWorld.__name__)\n"
    )
    done = subprocess.run(
        [sys.executable, "-c", code],
        env={"PYTHONPATH": str(ROOT), "MUJOCO_GL": "egl", "PATH": "/usr/bin:/bin"},
        capture_output=True,
        text=True,
        timeout=120,
    )
    assert done.returncode == 0, done.stderr
    assert done.stdout.strip() == "PhysicalWorld"


@pytest.mark.parametrize(
    ("command", "extra"),
    [
        ("adapt", ["--systems", "pil"]),
        ("transfer", ["--systems", "pil"]),
        ("people", ["--systems", "pil"]),
        ("baselines", ["--tuning-reps", "1", "--tables", "1"]),
    ],
)
def test_a_studys_rates_are_checked_once_by_its_command_line(
    parse_calls: Counter[str], tmp_path: Path, command: str, extra: list[str]
) -> None:
    """``--rates`` of adapt, transfer, people and baselines: each rate checked once, at the
    command line (run_options, or baselines' BaselineConfig); the study functions take the
    typed rates and systems as given. Every other value is checked once too."""
    from robin_sim.cli.main import main

    argv = [command, "--rates", "0.8,1.0", "--reps", "1", *extra, "--no-progress"]
    assert main([*argv, "--out", str(tmp_path / command)]) == 0
    assert parse_calls.pop("rate") == 2, parse_calls  # two rates, each once
    assert parse_calls["system"] == 0, parse_calls  # checked against the command's systems
    # the scenario files' own assembly keys: checked once per file, when it is read
    # (transfer reads two: the assembly and the tidying task)
    files = 2 if command == "transfer" else 1
    assert {name: parse_calls.pop(name, 0) for name in set(ASSEMBLY) - {"tables"}} == {
        name: files for name in set(ASSEMBLY) - {"tables"}
    }, parse_calls
    if command == "baselines":
        assert parse_calls.pop("reps") == 2, parse_calls  # --reps and --tuning-reps
        # tables: once as given, once as the scenario file's own value when the file is read
        assert parse_calls.pop("tables") == 2, parse_calls
    else:
        assert parse_calls.pop("tables") == files, parse_calls
    assert all(count == 1 for count in parse_calls.values()), parse_calls


def test_the_studys_detector_and_its_file_are_checked_once(
    parse_calls: Counter[str], tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """``robin-pil study --detector measured:FILE``: the detector is checked once, by the
    study's config (the registry), and the file read and checked once (its rate and every
    run's detector reuse it); the command line checks neither. The systems, repetitions and
    seed are checked once too, by the config."""
    import shutil

    from pil.task import detector
    from robin_sim.cli.main import main

    measured = tmp_path / "measured.json"  # a file of its own: read fresh by this test
    shutil.copy(ROOT / "robin_sim" / "vision" / "data" / "measured.json", measured)
    reads: list[str] = []
    real = detector.read_measured

    def counted(path: str) -> detector.MeasuredErrors:
        reads.append(path)
        return real(path)

    monkeypatch.setattr(detector, "read_measured", counted)
    argv = ["study", "--detector", f"measured:{measured}", "--systems", "pil,c3", "--reps", "2"]
    assert main([*argv, "--tables", "1", "--no-progress", "--out", str(tmp_path / "s")]) == 0
    assert parse_calls.pop("rate", 0) == 0, parse_calls  # the file's measured rate
    assert parse_calls.pop("system") == 2, parse_calls  # pil and c3, each once
    # tables: once as given, once as the scenario file's own value when the file is read
    assert parse_calls.pop("tables") == 2, parse_calls
    assert {"detector", "reps", "seed", "exploration"} <= set(parse_calls), parse_calls
    assert all(count == 1 for count in parse_calls.values()), parse_calls
    assert reads == [str(measured)], reads
    rows = (tmp_path / "s" / "runs.csv").read_text().splitlines()
    rate = f",{real(str(measured)).rate:.4f},"  # the file's own (the shipped model's) rate
    assert len(rows) == 1 + 2 * 2 and all(rate in row for row in rows[1:]), rows[:2]


def test_the_parts_below_the_edge_check_nothing() -> None:
    """The person's reaction time takes the values the registry checked (reaction_time,
    reaction_spread in PARAMS): it has no check of its own."""
    from pil.task.watching import ReactionTime

    assert "__post_init__" not in vars(ReactionTime)
    assert PARAMS["reaction_time"].high == 10.0 and PARAMS["reaction_spread"].low == 0.0
