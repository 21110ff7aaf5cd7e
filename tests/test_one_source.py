"""One source per fact: each constant is defined in one module, and its consumers import it.

Checked statically (the source is parsed with `ast` or read as text; nothing is imported for the
generic checks), so a copy that comes back (a second definition of a name, a second literal of a
fact) fails here even when every value still agrees.
"""

from __future__ import annotations

import ast
import functools
import re
from collections import defaultdict
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
PACKAGES = ("pil", "robin_sim")

# Upper-case names defined in more than one module on purpose: each means a different thing
# in each module (or awaits the run-assembly refactor); name -> the modules allowed to define it.
# A constant name defined anywhere else twice fails the test: import the one definition instead,
# or give the new meaning its own name.
SHARED_NAMES: dict[str, frozenset[str]] = {
    name: frozenset(modules)
    for name, modules in {
        # the CLI's sub-commands; the experimenter's commands on the live page
        "COMMANDS": ("robin_sim/cli/main.py", "robin_sim/live/commands.py"),
        # each command's own default output folder
        "DEFAULT_OUT": (
            "robin_sim/cli/adapt.py",
            "robin_sim/cli/baselines.py",
            "robin_sim/cli/people.py",
            "robin_sim/cli/study.py",
            "robin_sim/cli/transfer.py",
        ),
        # P(next state) to act unasked; the gesture classifier's confidence
        "DEFAULT_THRESHOLD": ("pil/anticipation.py", "robin_sim/vision/train.py"),
        # the environment's observation index of a discarded reading; the vision reading's label
        "DISCARDED": ("pil/env/assembly.py", "robin_sim/vision/train.py"),
        # the video overlay's font; the reading picture's font
        "FONT": ("robin_sim/render/overlay.py", "robin_sim/vision/picture.py"),
        # each file kind's format version
        "FORMAT": (
            "pil/experiments/rep_journal.py",
            "pil/experiments/sweep_store.py",
            "pil/table_io.py",
            "robin_sim/render/state_log.py",
            "robin_sim/vision/classifier.py",
        ),
        # JSON's deepest nesting read; the segmenter's farthest depth (m)
        "MAX_DEPTH": ("pil/regular_files.py", "robin_sim/vision/segment.py"),
        # a type variable of generic helpers
        "T": ("pil/task/assemble.py", "pil/worker_pool.py"),
        # the live stream's JPEG quality; the replay page's
        "JPEG_QUALITY": ("robin_sim/live/frames.py", "robin_sim/replay/serve.py"),
        # each module's logger
        "LOG": (
            "robin_sim/live/conductor.py",
            "robin_sim/live/connections.py",
            "robin_sim/live/guard.py",
            "robin_sim/live/server.py",
            "robin_sim/live/tabs.py",
        ),
        # a valid message's size; the socket's limit above which it closes
        "MAX_MESSAGE_BYTES": ("robin_sim/live/inputs.py", "robin_sim/live/server.py"),
        # a matrix value's text; a task file's name or description; a questionnaire's item
        "MAX_TEXT": (
            "pil/task/param_spec.py",
            "pil/task/yaml_files.py",
            "robin_sim/live/questionnaires.py",  # a questionnaire's item text
        ),
        # each report's own columns
        "METRICS": (
            "pil/experiments/baselines.py",
            "pil/experiments/results_report.py",
            "pil/experiments/study.py",
        ),
        # a render check's smallest visible object; the segmenter's smallest hand
        "MIN_PIXELS": ("robin_sim/render/checks.py", "robin_sim/vision/segment.py"),
        # the detection models; the MJCF model files
        "MODELS": ("pil/task/detector.py", "robin_sim/cli/model_path.py"),
        # the run parameters (left to the run-assembly refactor, issue 18)
        # a run's phases (train, test); the live participant's turn
        "PHASES": ("pil/task/seeds.py", "robin_sim/live/participant.py"),
        # the exploration rules; the validity rules
        "RULES": ("pil/exploration.py", "pil/validity.py"),
        # each web page's own static folder
        "STATIC_DIR": ("robin_sim/live/pages.py", "robin_sim/replay/serve.py"),
        # each task file kind's keys
        "_KEYS": (
            "pil/experiments/adaptation.py",
            "pil/experiments/people.py",
            "pil/table_io.py",
        ),
    }.items()
}


def source_files() -> list[Path]:
    """Every module of the packages."""
    return [p for package in PACKAGES for p in sorted((ROOT / package).rglob("*.py"))]


def rel(path: Path) -> str:
    return path.relative_to(ROOT).as_posix()


def _names(target: ast.expr) -> list[str]:
    if isinstance(target, ast.Name):
        return [target.id]
    if isinstance(target, ast.Tuple | ast.List):
        return [name for element in target.elts for name in _names(element)]
    return []


def module_constants(path: Path) -> set[str]:
    """The upper-case names the module assigns at its top level (``A = ...``, ``A: T = ...``)."""
    tree = ast.parse(path.read_text(encoding="utf-8"), filename=str(path))
    found: set[str] = set()
    for node in tree.body:
        targets: list[ast.expr] = []
        if isinstance(node, ast.Assign):
            targets = node.targets
        elif isinstance(node, ast.AnnAssign) and node.value is not None:
            targets = [node.target]
        for target in targets:
            found.update(n for n in _names(target) if n.lstrip("_") and n.upper() == n)
    return found


def definitions() -> dict[str, set[str]]:
    """Constant name -> the modules defining it."""
    where: dict[str, set[str]] = defaultdict(set)
    for path in source_files():
        for name in module_constants(path):
            where[name].add(rel(path))
    return where


def test_no_constant_is_defined_in_two_modules() -> None:
    copies = {
        name: sorted(modules)
        for name, modules in definitions().items()
        if len(modules) > 1 and not modules <= SHARED_NAMES.get(name, frozenset())
    }
    assert not copies, (
        "constants defined in more than one module (import the one definition, or give a "
        f"different meaning its own name): {copies}"
    )


@pytest.mark.parametrize(
    ("name", "module"),
    [
        ("POINT_OFFSET", "robin_sim/model/robot_spec.py"),
        ("ROW_COLUMNS", "pil/experiments/run_row.py"),
        ("ACTION_INDEX", "pil/table.py"),
        ("STATE_ID_BY_OBJECT", "pil/table.py"),
        ("DISCARDED", "robin_sim/vision/train.py"),
        ("EPSILON", "pil/agents/bandit.py"),
        ("EPSILON_RANGE", "pil/agents/bandit.py"),
        ("EPSILON_DECAY", "pil/agents/bandit.py"),
        ("EPSILON_DECAY_RANGE", "pil/agents/bandit.py"),
        ("STEP_SIZE", "pil/agents/tamer.py"),
        ("STEP_SIZE_RANGE", "pil/agents/tamer.py"),
        ("FPS", "robin_sim/render/frame_spec.py"),
        ("SIDE", "robin_sim/render/frame_spec.py"),
        ("BASELINE", "pil/experiments/paper.py"),
        ("INPUTS_NAME", "pil/experiments/sessions_load.py"),
        ("PAIR_BY", "pil/experiments/study_tests.py"),
        ("QUESTIONNAIRES_NAME", "pil/file_names.py"),
        ("HUMAN_VIS_PREFIX", "robin_sim/model/names.py"),
    ],
)
def test_issue_18_facts_have_their_one_home(name: str, module: str) -> None:
    where = definitions()[name]
    if name == "DISCARDED":  # the environment's observation index is another fact
        where = where - {"pil/env/assembly.py"}
    assert where == {module}


@pytest.mark.parametrize(
    ("name", "meanings"),
    [
        ("CAMERAS", 1),  # the detector that reads with the eyes; the filming ones: SCENE_CAMERAS
        ("FINGERS", 1),  # Robin's; the person's: hand_poses.HUMAN_FINGERS
        # the condition names are CONDITION_PARAMS' keys (episode/reading.py is gone); the
        # detector's defaults: VISION_DEFAULTS
        ("VISION_PARAMS", 0),
        ("GESTURES", 1),  # pil.types' tuple; the live page's keys: inputs.GESTURE_BY_KEY
    ],
)
def test_names_with_two_meanings_were_told_apart(name: str, meanings: int) -> None:
    assert len(definitions()[name]) == meanings, definitions()[name]


def literal_count(pattern: str, packages: tuple[str, ...] = PACKAGES) -> dict[str, int]:
    """Module -> number of matches of the regex ``pattern`` in its source (where any)."""
    found = {}
    for path in (p for package in packages for p in sorted((ROOT / package).rglob("*.py"))):
        n = len(re.findall(pattern, path.read_text(encoding="utf-8")))
        if n:
            found[rel(path)] = n
    return found


@pytest.mark.parametrize(
    ("pattern", "home"),
    [
        # the pointing hand's offset above its place
        (r"0\.14,\s*0\.0,\s*0\.13", "robin_sim/model/robot_spec.py"),
        # H.264's even frame size
        (r"must be even in both dimensions", "robin_sim/render/frame_spec.py"),
        # the row's columns: the training counts are named once
        (r'"train_rejected"', "pil/experiments/run_row.py"),
        # states looked up by object id
        (r"\{id\(s\)", "pil/table.py"),
        # the reading label of a discarded reading
        (r'(?m)^[A-Z_]+(\s*:[^=\n]+)?\s*=\s*"discarded"', "robin_sim/vision/train.py"),
        # the detection rate's range: one spec (no second rate check, e.g. check_rate)
        (r'"gesture detection rate",\s*0\.0,\s*1\.0', "pil/task/params.py"),
    ],
)
def test_a_fact_is_written_once(pattern: str, home: str) -> None:
    assert literal_count(pattern) == {home: 1}


@pytest.mark.parametrize(
    ("pattern", "homes"),
    [
        # the default repetitions: the paper's 20 (also the registry's REPS default)
        (
            r"(?i)reps\b[^\n=(]*=\s*20\b|\"reps\",\s*\"int\",\s*20\b",
            ("pil/task/params.py",),
        ),
        # robin-pil transfer's rates; adapt's and people's (two studies, two facts)
        (r"[(\"]0\.6,\s*0\.8,\s*1\.0[)\"]", ("pil/experiments/transfer.py",)),
        (r"[(\"]0\.8,\s*1\.0[)\"]", ("pil/experiments/adaptation.py", "pil/experiments/people.py")),
        # the exact dice's name
        (r"[\"']exact[\"']", ("pil/task/detector.py",)),
        # the six hand signs' names: the gestures' own (pil.types derives them), the thumbs'
        (r"[\"']give_me[\"']", ()),
        (r"[\"']thumb_up[\"']", ("pil/types.py",)),
        (r"[\"']thumb_down[\"']", ("pil/types.py",)),
        # the files the commands write and read
        *(
            (rf"[\"']{re.escape(name)}[\"']", ("pil/file_names.py",))
            for name in (
                "summary.json",
                "episode.jsonl",
                "episode.mp4",
                "runs.csv",
                "results.csv",
                "measured.json",
            )
        ),
    ],
)
def test_a_value_is_written_once(pattern: str, homes: tuple[str, ...]) -> None:
    """The value itself (not only its name) is written in its home alone: everywhere else
    imports the name."""
    assert literal_count(pattern) == dict.fromkeys(homes, 1)


def test_the_live_page_takes_the_signs_from_python() -> None:
    """Neither webcam.js, live.js nor index.html retypes the six signs' names or labels: the
    participant's page carries them (and the gesture keys live.js sends, with their keyboard
    shortcuts, and "That was wrong"'s label, key and window) from the Python source."""
    import html
    import json

    from pil.types import SIGN_NAMES, sign_label
    from robin_sim.live.inputs import (
        GESTURE_KEYS,
        GESTURE_SHORTCUTS,
        TAKE_BACK_LABEL,
        TAKE_BACK_SHORTCUT,
    )
    from robin_sim.live.pages import PAGE_CONSTANTS
    from robin_sim.live.take_back import TAKE_BACK_WINDOW_S

    for name in ("webcam.js", "live.js", "index.html"):
        script = (ROOT / "robin_sim" / "live" / "static" / name).read_text(encoding="utf-8")
        quoted = set(re.findall(r"[\"'`]([^\"'`\n]*)[\"'`]", script))
        assert not [n for n in SIGN_NAMES if n in quoted or sign_label(n) in quoted], (name, quoted)
        assert not {TAKE_BACK_LABEL, TAKE_BACK_SHORTCUT} & quoted, (name, quoted)
    constants = json.loads(html.unescape(PAGE_CONSTANTS))
    assert constants == {
        "signs": {name: sign_label(name) for name in SIGN_NAMES},
        "cursor": "pointing",
        "gestures": list(GESTURE_KEYS),
        "shortcuts": GESTURE_SHORTCUTS,
        "take_back": {
            "label": TAKE_BACK_LABEL,
            "key": TAKE_BACK_SHORTCUT,
            "window_s": TAKE_BACK_WINDOW_S,
        },
    }
    assert sorted(GESTURE_SHORTCUTS) == sorted(GESTURE_KEYS)
    assert len(set(GESTURE_SHORTCUTS.values())) == len(GESTURE_SHORTCUTS)
    live_js = (ROOT / "robin_sim" / "live" / "static" / "live.js").read_text(encoding="utf-8")
    fixed = re.search(r"const KEYS = \{([^}]*)\}", live_js)
    assert fixed is not None  # the page's own keys (thumbs, End, Start): no key twice
    own = re.findall(r"(\w+):", fixed.group(1))
    keys = [*own, *GESTURE_SHORTCUTS.values(), TAKE_BACK_SHORTCUT]
    assert len(keys) == len(set(keys)) and "u" in own and "e" in own, keys
    assert len(SIGN_NAMES) == 6
    page = (ROOT / "robin_sim" / "live" / "static" / "index.html").read_text(encoding="utf-8")
    assert 'data-constants="{{CONSTANTS}}"' in page


@functools.cache
def _top_level(kind: type) -> dict[str, set[str]]:
    """Name -> the modules defining a top-level ``kind`` (class or function) of that name."""
    where: dict[str, set[str]] = defaultdict(set)
    for path in source_files():
        for node in ast.parse(path.read_text(encoding="utf-8")).body:
            if isinstance(node, kind):
                where[node.name].add(rel(path))  # type: ignore[attr-defined]
    return where


def test_no_two_classes_share_a_name() -> None:
    """Issue 26: one ``RunSpec`` (the grid's rows are ``GridRow``), ``EyeCondition`` and
    ``ProtocolCondition``, ``EyeReading`` and ``HandReading``."""
    classes = _top_level(ast.ClassDef)
    assert {n: m for n, m in classes.items() if len(m) > 1} == {}
    assert classes["RunSpec"] == {"pil/task/spec.py"} and classes["GridRow"]


@pytest.mark.parametrize(
    ("name", "home"),
    [
        ("draw_spots", "robin_sim/render/spots.py"),  # numbered from a given first spot
        ("cpu_count", "pil/cpus.py"),  # every default number of workers reads it
        ("reject_unknown", "pil/task/yaml_files.py"),  # every file's check of its keys
        ("spec_row", "pil/experiments/run_row.py"),
        ("person_seed", "pil/task/seeds.py"),
        ("assemble", "pil/task/assemble.py"),  # robin_sim's is assemble_physical
        ("source_commit", "pil/provenance.py"),  # the bench journal's and the archive's
    ],
)
def test_a_function_has_one_home(name: str, home: str) -> None:
    assert _top_level(ast.FunctionDef)[name] == {home}


def test_what_issue_26_retired_is_gone() -> None:
    """The sweep's untyped entry points, the second systems module, the second assembly."""
    functions = _top_level(ast.FunctionDef)
    gone = ["run_checked", "check_run", "_row_spec", "run_physical", "expected_cost"]
    gone += ["run_physical_checked", "assemble_phase", "default_workers", "_reject_unknown"]
    gone += ["git_commit", "ignored_for_children"]
    assert [name for name in gone if name in functions] == []
    # the appearance study's run_one runs one appearance run: not the sweep's, gone
    assert functions["run_one"] == {"robin_sim/appearance/runs.py"}
    assert [p.name for p in source_files()].count("systems.py") == 1
    assert [p.name for p in source_files()].count("assemble.py") == 1


def test_agent_settings_are_the_agents_defaults_and_ranges() -> None:
    """epsilon, epsilon_decay and step_size: the run parameters read the agents' values (no
    copy), so the TAMER agent's [0, 1] step_size is the parameter's range too."""
    from pil.agents import bandit, tamer
    from pil.task.params import PARAMS

    for name, default, (low, high) in (
        ("epsilon", bandit.EPSILON, bandit.EPSILON_RANGE),
        ("epsilon_decay", bandit.EPSILON_DECAY, bandit.EPSILON_DECAY_RANGE),
        ("step_size", tamer.STEP_SIZE, tamer.STEP_SIZE_RANGE),
    ):
        spec = PARAMS[name]
        assert (spec.default, spec.low, spec.high) == (default, low, high), name
    assert tamer.STEP_SIZE_RANGE == (0.0, 1.0)
    assert (PARAMS["step_size"].low, PARAMS["step_size"].high) == (0.0, 1.0)


def test_agent_settings_are_never_written_as_numbers_beside_their_name() -> None:
    """No call names ``"epsilon"`` / ``"epsilon_decay"`` / ``"step_size"`` with a number
    literal among its arguments (a ParamSpec copying a default or a range)."""
    names = {"epsilon", "epsilon_decay", "step_size"}
    copies = []
    for path in source_files():
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
            if not isinstance(node, ast.Call) or not node.args:
                continue
            first = node.args[0]
            if isinstance(first, ast.Constant) and first.value in names:
                numbers = [
                    a.value
                    for a in [*node.args[1:], *(k.value for k in node.keywords)]
                    if isinstance(a, ast.Constant) and isinstance(a.value, int | float)
                ]
                if numbers:
                    copies.append(f"{rel(path)}:{node.lineno} {first.value} {numbers}")
    assert not copies


def test_a_frame_size_is_checked_once_at_each_edge() -> None:
    """The episode, the live page and a replay's recorded settings check a size (even, within
    the scene's off-screen buffer) with frame_spec's check, once; the renderers, the render
    pool, the eyes and the MP4 writer below them check nothing again (issue 26: six places)."""
    from robin_sim.episode import config as episode_config
    from robin_sim.live import config as live_config
    from robin_sim.render import frame_spec

    assert episode_config.check_size is frame_spec.check_size
    assert live_config.check_size is frame_spec.check_size
    assert episode_config.FPS is frame_spec.FPS
    assert literal_count(r"\bcheck_size\(") == {
        "robin_sim/render/frame_spec.py": 1,  # its definition
        "robin_sim/episode/config.py": 2,  # --size WxH, and the API's width and height
        "robin_sim/live/config.py": 1,
        "robin_sim/render/state_checks.py": 1,
    }
    assert literal_count(r"\bcheck_frame_size\b") == {}
    assert literal_count(r"\bFPS\.parse\(") == {
        "robin_sim/episode/config.py": 1,
        "robin_sim/render/state_checks.py": 1,
    }
    assert literal_count(r"\bmujoco\.Renderer\(") == {"robin_sim/render/renderer.py": 1}
    # the live page narrows the episode's ranges, and only their upper ends
    for live, episode in (
        (live_config.LIVE_FPS, frame_spec.FPS),
        (live_config.LIVE_SIDE, frame_spec.SIDE),
    ):
        assert (live.kind, live.low) == (episode.kind, episode.low)
        assert live.high is not None and episode.high is not None and live.high <= episode.high


def test_row_columns_and_lookups_are_imported_not_copied() -> None:
    from pil import learner, table
    from pil.experiments import run_row, study

    assert study.STUDY_COLUMNS[1:] == run_row.ROW_COLUMNS
    assert learner.ACTION_INDEX is table.ACTION_INDEX
    assert learner.STATE_ID_BY_OBJECT is table.STATE_ID_BY_OBJECT


def test_no_module_imports_a_private_name_of_another() -> None:
    """A name shared between modules is public (e.g. the figures' ``pyplot`` and
    ``finish_figure`` in :mod:`pil.experiments.plotting`, once ``figures._pyplot``)."""
    private = []
    for path in source_files():
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
            if isinstance(node, ast.ImportFrom) and (node.module or "").split(".")[0] in PACKAGES:
                private += [
                    f"{rel(path)}: {node.module}.{a.name}"
                    for a in node.names
                    if a.name.startswith("_") and not a.name.startswith("__")
                ]
    assert not private


def test_one_rate_check() -> None:
    """A detection rate is checked by the RATE spec only: no other function checks one."""
    assert literal_count(r"def check_rate\b") == {}
    assert literal_count(r"\bcheck_rate\(") == {}


def test_a_physical_run_is_assembled_in_one_place() -> None:
    """The world, the person's body and Robin's eyes are built by assemble_physical only: the
    episode, sweeps, the live session and the palm check all go through it (issue 26:
    the palm check built its own). The one other world and body are the gesture data set's:
    it reaches Robin's held-leg arm state by acting in a world of its own, with no learner,
    no run and no eyes (``arm_states.held_leg_qpos``, issue 41)."""
    home = "robin_sim/episode/physical_assembly.py"
    data_set = "robin_sim/vision/arm_states.py"
    for built in (r"\bPhysicalWorld\(", r"\bPhysicalBody\("):
        assert literal_count(built) == {home: 1, data_set: 1}, built
    assert literal_count(r"\bVisionDetector\(") == {home: 1}
