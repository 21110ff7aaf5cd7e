"""The architecture, checked statically: no import cycle, a MuJoCo-free `pil`, a tidy robin_sim.

Every import statement of every module under pil/ and robin_sim/ counts, wherever it stands
(module level, inside a function, under `if TYPE_CHECKING:`): the source is parsed with `ast`,
nothing is imported. An import edge goes to the deepest module of ours that the statement names
(`from pil.task import parts` -> pil.task.parts; `from pil.task import Scenario` -> pil.task).
"""

from __future__ import annotations

import ast
import functools
import re
from collections.abc import Iterable, Mapping
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
PACKAGES = ("pil", "robin_sim")


# `pil` is the learner and the symbolic task: it runs without any of these installed.
PIL_FORBIDDEN = ("mujoco", "mink", "dm_control", "robin_sim")

MAX_LOOSE_ROBIN_SIM_MODULES = 10


def module_files(root: Path, packages: Iterable[str] = PACKAGES) -> dict[str, Path]:
    """Dotted module name -> source file, for every .py file under the given packages."""
    found: dict[str, Path] = {}
    for package in packages:
        for path in sorted((root / package).rglob("*.py")):
            parts = list(path.relative_to(root).with_suffix("").parts)
            if parts[-1] == "__init__":
                parts.pop()
            found[".".join(parts)] = path
    return found


def _absolute(module: str, is_package: bool, level: int, name: str | None) -> str:
    """The absolute dotted name of a (possibly relative) `from ... import` source."""
    if level == 0:
        return name or ""
    base = module.split(".") if is_package else module.split(".")[:-1]
    base = base[: len(base) - (level - 1)]
    return ".".join([*base, name] if name else base)


def imported_names(module: str, path: Path) -> set[str]:
    """Every dotted name the module's import statements name, absolute (`from a import b`: a.b)."""
    tree = ast.parse(path.read_text(encoding="utf-8"), filename=str(path))
    is_package = path.name == "__init__.py"
    names: set[str] = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            names.update(alias.name for alias in node.names)
        elif isinstance(node, ast.ImportFrom):
            source = _absolute(module, is_package, node.level, node.module)
            names.update(source if a.name == "*" else f"{source}.{a.name}" for a in node.names)
    return names


def import_graph(modules: Mapping[str, Path]) -> dict[str, set[str]]:
    """Module -> the modules of ours it imports (the deepest existing module of each name)."""
    graph: dict[str, set[str]] = {}
    for module, path in modules.items():
        targets: set[str] = set()
        for name in imported_names(module, path):
            parts = name.split(".")
            for end in range(len(parts), 0, -1):
                candidate = ".".join(parts[:end])
                if candidate in modules:
                    targets.add(candidate)
                    break
        targets.discard(module)
        graph[module] = targets
    return graph


def cycles(graph: Mapping[str, set[str]]) -> list[list[str]]:
    """One concrete cycle (a, b, ..., a) per strongly connected component of several modules."""
    index: dict[str, int] = {}
    low: dict[str, int] = {}
    stack: list[str] = []
    on_stack: set[str] = set()
    components: list[set[str]] = []

    def visit(node: str) -> None:  # Tarjan's algorithm; the graph has ~100 nodes
        index[node] = low[node] = len(index)
        stack.append(node)
        on_stack.add(node)
        for nxt in sorted(graph.get(node, ())):
            if nxt not in index:
                visit(nxt)
                low[node] = min(low[node], low[nxt])
            elif nxt in on_stack:
                low[node] = min(low[node], index[nxt])
        if low[node] == index[node]:
            component: set[str] = set()
            while True:
                member = stack.pop()
                on_stack.discard(member)
                component.add(member)
                if member == node:
                    break
            if len(component) > 1:
                components.append(component)

    for node in sorted(graph):
        if node not in index:
            visit(node)
    return [_cycle_in(graph, component) for component in components]


def _cycle_in(graph: Mapping[str, set[str]], component: set[str]) -> list[str]:
    """A shortest cycle through the component's first module (breadth-first, inside it)."""
    start = min(component)
    parents: dict[str, str] = {}
    frontier = [start]
    while frontier:
        nxt_frontier = []
        for node in frontier:
            for nxt in sorted(graph[node] & component):
                if nxt == start:
                    path = [node]
                    while path[-1] != start:
                        path.append(parents[path[-1]])
                    return [start, *reversed(path[:-1]), start]
                if nxt not in parents:
                    parents[nxt] = node
                    nxt_frontier.append(nxt)
        frontier = nxt_frontier
    raise AssertionError(f"no cycle in strongly connected component {sorted(component)}")


@pytest.fixture(scope="module")
def graph() -> dict[str, set[str]]:
    return import_graph(module_files(ROOT))


def test_no_import_cycle(graph: dict[str, set[str]]) -> None:
    found = cycles(graph)
    assert not found, "import cycles: " + "; ".join(" -> ".join(c) for c in found)


def package_of(module: str, modules: Mapping[str, Path]) -> str:
    """The subpackage a module belongs to (``robin_sim.robot.world`` -> ``robin_sim.robot``);
    a loose module of a top package (``pil.learner``) belongs to the top package."""
    parts = module.split(".")
    for end in range(len(parts), 0, -1):
        candidate = ".".join(parts[:end])
        if candidate in modules and modules[candidate].name == "__init__.py" and end > 1:
            return candidate
    return parts[0]


def package_graph(
    graph: Mapping[str, set[str]], modules: Mapping[str, Path]
) -> dict[str, set[str]]:
    """Subpackage -> the subpackages its modules import (itself left out).

    A top package's ``__init__`` (``pil``, ``robin_sim``: the public API, ``__all__``) is a
    facade over every layer and left out; the module graph still refuses any module that
    imports it back."""
    packages: dict[str, set[str]] = {}
    for module, targets in graph.items():
        if "." not in module:
            continue
        mine = package_of(module, modules)
        found = packages.setdefault(mine, set())
        found.update(package_of(t, modules) for t in targets)
        found.discard(mine)
    return packages


def test_no_import_cycle_between_packages(graph: dict[str, set[str]]) -> None:
    """E.g. robot -> person -> robot (the person's hand belongs below both, in control)."""
    found = cycles(package_graph(graph, module_files(ROOT)))
    assert not found, "package cycles: " + "; ".join(" -> ".join(c) for c in found)


def test_package_checker_finds_a_cycle_of_packages(tmp_path: Path) -> None:
    for name, body in {
        "robin_sim/__init__.py": "",
        "robin_sim/robot/__init__.py": "",
        "robin_sim/robot/world.py": "from robin_sim.person.hand import HumanHand\n",
        "robin_sim/person/__init__.py": "",
        "robin_sim/person/hand.py": "",
        "robin_sim/person/body.py": "from robin_sim.robot import world\n",
    }.items():
        (tmp_path / name).parent.mkdir(parents=True, exist_ok=True)
        (tmp_path / name).write_text(body)
    modules = module_files(tmp_path, ("robin_sim",))
    assert cycles(import_graph(modules)) == []  # no module-level cycle ...
    found = cycles(package_graph(import_graph(modules), modules))
    assert found and set(found[0]) == {
        "robin_sim.robot",
        "robin_sim.person",
    }  # ... but a package one


def test_no_cli_command_imports_another_command(graph: dict[str, set[str]]) -> None:
    """A command's module (robin_sim.cli.main.COMMANDS) imports no other command's module;
    they share code through helper modules (options, help_format, ...) or the layers below."""
    from robin_sim.cli.main import COMMANDS

    commands = {module for module, _help in COMMANDS.values()}
    assert len(commands) >= 10
    offenders = [
        f"{module} imports {target}"
        for module in sorted(commands)
        for target in sorted(graph.get(module, ()))
        if target in commands
    ]
    assert not offenders, "; ".join(offenders)


def test_pil_imports_no_simulation() -> None:
    offenders = []
    for module, path in module_files(ROOT, ("pil",)).items():
        for name in sorted(imported_names(module, path)):
            if name.split(".")[0] in PIL_FORBIDDEN:
                offenders.append(f"{module} imports {name}")
    assert not offenders, "; ".join(offenders)


def test_few_loose_modules_in_robin_sim() -> None:
    loose = sorted(p.name for p in (ROOT / "robin_sim").glob("*.py") if p.name != "__init__.py")
    assert len(loose) <= MAX_LOOSE_ROBIN_SIM_MODULES, f"{len(loose)} loose modules: {loose}"


@functools.cache
def _model_names() -> frozenset[str]:
    """Every named element of the project scene (bodies, joints, geoms, sites, actuators...)."""
    import mujoco

    from robin_sim.model.scene import build_model

    model = build_model()
    obj = mujoco.mjtObj
    sizes = {
        obj.mjOBJ_BODY: model.nbody,
        obj.mjOBJ_JOINT: model.njnt,
        obj.mjOBJ_GEOM: model.ngeom,
        obj.mjOBJ_SITE: model.nsite,
        obj.mjOBJ_ACTUATOR: model.nu,
        obj.mjOBJ_CAMERA: model.ncam,
        obj.mjOBJ_EQUALITY: model.neq,
        obj.mjOBJ_MATERIAL: model.nmat,
    }
    found = set()
    for kind in sizes:
        for i in range(sizes[kind]):
            name = mujoco.mj_id2name(model, kind, i)
            if name:
                found.add(name)
    return frozenset(found)


def _name_like_fstrings(path: Path) -> list[str]:
    """f-strings that build a name of the model (``f"{side}_{finger}_dist"``, ``f"leg{i}"``):
    their pattern, with each ``{...}`` read as any text, matches a named element of the scene."""
    tree = ast.parse(path.read_text(encoding="utf-8"))
    specs = {
        id(v.format_spec) for v in ast.walk(tree) if isinstance(v, ast.FormattedValue)
    }  # the `.3f` of f"{x:.3f}" is an f-string of its own
    found = []
    for node in ast.walk(tree):
        if not isinstance(node, ast.JoinedStr) or id(node) in specs:
            continue
        parts = node.values
        if not any(isinstance(p, ast.Constant) for p in parts) or any(
            isinstance(p, ast.FormattedValue) and (p.format_spec or p.conversion != -1)
            for p in parts
        ):
            continue
        pattern = "".join(
            re.escape(p.value) if isinstance(p, ast.Constant) else "[A-Za-z0-9_]+" for p in parts
        )
        if any(re.fullmatch(pattern, name) for name in _model_names()):
            found.append(f"{path.relative_to(ROOT)}:{node.lineno}: {ast.unparse(node)}")
    return found


def _error_classes(modules: Mapping[str, Path]) -> dict[str, str]:
    """Every subclass of RobinPilError defined in our code: class name -> defining module."""
    bases: dict[str, tuple[str, set[str]]] = {}
    for module, path in modules.items():
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
            if isinstance(node, ast.ClassDef):
                names = {b.id if isinstance(b, ast.Name) else ast.unparse(b) for b in node.bases}
                bases[node.name] = (module, {n.rsplit(".", 1)[-1] for n in names})
    errors = {"RobinPilError"}
    while True:
        more = {name for name, (_, parents) in bases.items() if parents & errors} - errors
        if not more:
            break
        errors |= more
    return {name: bases[name][0] for name in errors - {"RobinPilError"}}


def _constructs(path: Path) -> set[str]:
    """Names the module calls (``Name(...)``, ``module.Name(...)``) or raises bare."""
    found = set()
    for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
        target = node.func if isinstance(node, ast.Call) else None
        if isinstance(node, ast.Raise) and isinstance(node.exc, ast.Name | ast.Attribute):
            target = node.exc
        if isinstance(target, ast.Name):
            found.add(target.id)
        elif isinstance(target, ast.Attribute):
            found.add(target.attr)
    return found


def test_errors_live_next_to_what_raises_them() -> None:
    # One base class (pil.errors.RobinPilError); a subclass lives in the module that raises it,
    # or in pil.errors when it is a family that several modules raise (InvalidChoiceError).
    modules = module_files(ROOT)
    made = {module: _constructs(path) for module, path in modules.items()}
    misplaced = []
    for error, home in sorted(_error_classes(modules).items()):
        raisers = sorted(m for m, names in made.items() if error in names)
        shared = home == "pil.errors" and len(raisers) >= 2
        if home not in raisers and not shared:
            misplaced.append(f"{error} (in {home}, raised in {', '.join(raisers) or 'nothing'})")
    assert not misplaced, "errors defined away from what raises them: " + "; ".join(misplaced)


# The checker itself, on small packages written for the purpose: it must see what it claims to.


def _write(root: Path, files: Mapping[str, str]) -> None:
    for rel, text in files.items():
        path = root / rel
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text(text, encoding="utf-8")


def test_checker_finds_function_level_and_relative_cycles(tmp_path: Path) -> None:
    _write(
        tmp_path,
        {
            "pk/__init__.py": "",
            "pk/a.py": "def f():\n    from pk.sub import b\n",
            "pk/sub/__init__.py": "",
            "pk/sub/b.py": "from . import c\n",
            "pk/sub/c.py": "from ..a import f\n",
            "pk/d.py": "import pk.a\n",
        },
    )
    found = cycles(import_graph(module_files(tmp_path, ("pk",))))
    assert found == [["pk.a", "pk.sub.b", "pk.sub.c", "pk.a"]]


def test_checker_accepts_a_package_reexporting_its_modules(tmp_path: Path) -> None:
    _write(
        tmp_path,
        {
            "pk/__init__.py": "from pk.a import f\nfrom .b import g\n",
            "pk/a.py": "from pk.b import g\n",
            "pk/b.py": "import os\ng = os.sep\n",
        },
    )
    graph = import_graph(module_files(tmp_path, ("pk",)))
    assert graph == {"pk": {"pk.a", "pk.b"}, "pk.a": {"pk.b"}, "pk.b": set()}
    assert cycles(graph) == []
    _write(tmp_path, {"pk/b.py": "from pk import f\n"})  # a module importing its package back
    assert cycles(import_graph(module_files(tmp_path, ("pk",)))) == [["pk", "pk.b", "pk"]]
