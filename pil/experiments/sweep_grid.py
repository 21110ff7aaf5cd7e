"""The grid of a sweep: systems × detection rates × swept parameters × repetitions.

Every run gets a stable, readable id built from its parameters, e.g.
``pil|rate=0.6|tables=10|discard=0.3|rep=0007``, and a seed derived from the base seed and
those parameters (not from the position in the grid, the worker or the order of execution).
The seed does not depend on the system: the systems of one (rate, parameters, repetition) cell
face the same person and detector draws (common random numbers), which makes the comparison
fairer. Everything the user gives is checked here, before any run starts.

Run functions are named by import path (``"pil.experiments.systems:run_one"``), so a worker needs
nothing
but the installed package. A run function is called as
``function(system, rate, seed, tables=..., **params)`` and returns one flat dict of metrics.
"""

from __future__ import annotations

import hashlib
import importlib
import inspect
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import Any

from pil.errors import InvalidChoiceError, RobinPilError
from pil.experiments.paper import PAPER_RATES, PAPER_REPS
from pil.experiments.systems import PAPER_SYSTEMS
from pil.task.params import ASSEMBLY_DEFAULTS, RATE, REPS, SEED, ParamSpec, spec_for

KINDS: dict[str, str] = {
    "learner": "pil.experiments.systems:run_one",
    "physical": "robin_sim.episode.physical_run:run_physical",
}
# what a worker calls for each kind's row: the run function of values the grid parsed (typed,
# trusted: nothing is checked again in the worker); its results are the kind's function's
RUNNERS: dict[str, str] = {
    "learner": "pil.experiments.systems:run_checked",
    "physical": "robin_sim.episode.physical_run:run_physical_checked",
}
# where each kind's parameter specs live (later sources override earlier ones)
PARAM_SOURCES: dict[str, tuple[str, ...]] = {
    "learner": ("pil.task.params:PARAMS", "pil.task.params:RUN_OPTIONS"),
    "physical": (
        "pil.task.params:PARAMS",
        "pil.task.params:RUN_OPTIONS",
        "robin_sim.episode.physical_run:PHYSICAL_PARAMS",
    ),
}
# each kind's whole-run check: check(system, rate, seed, **params) raises on a run that cannot
# start (a missing scenario, a layout without the legs asked for), before the first run
CHECKS: dict[str, str] = {
    "learner": "pil.experiments.systems:check_run",
    "physical": "robin_sim.episode.physical_run:check_physical",
}
# each kind's expected cost of a run, cost(system, rate, seed, **params) -> float, to start the
# longest runs first (learner-only runs are all short: they keep the grid's order)
COSTS: dict[str, str] = {"physical": "robin_sim.episode.physical_run:expected_cost"}
DEFAULT_SYSTEMS: tuple[str, ...] = tuple(PAPER_SYSTEMS)  # the paper's five
DEFAULT_RATES: tuple[float, ...] = PAPER_RATES
RESERVED: dict[str, str] = {
    "system": "--systems",
    "rate": "--rates",
    "seed": "--seed",
    "rep": "--reps",
}
_SYSTEMS_MODULE = "pil.experiments.systems"


class SweepGridError(RobinPilError):
    """A sweep grid that cannot run: empty, an unknown name, a value of the wrong type."""


def import_object(path: str) -> Any:
    """The object named by ``"package.module:attribute"``; a clear error when it is missing."""
    module_name, _, attribute = path.partition(":")
    if not module_name or not attribute:
        raise SweepGridError(f"run function {path!r} must be written 'package.module:function'")
    try:
        module = importlib.import_module(module_name)
    except ImportError as error:
        raise SweepGridError(f"cannot import {module_name!r} for {path!r}: {error}") from None
    try:
        return getattr(module, attribute)
    except AttributeError:
        raise SweepGridError(f"module {module_name!r} has no {attribute!r} ({path!r})") from None


@dataclass(frozen=True, slots=True)
class RunTarget:
    """What a sweep runs: the function's import path, its valid systems and parameters."""

    kind: str
    function: str
    systems: tuple[str, ...] | None  # None: any system name is passed through
    params: Mapping[str, ParamSpec]  # valid parameter name -> its spec (type, range, default)
    open_params: bool  # the function takes **params and names no PARAMS: accept any name
    check: str | None = None  # import path of check(system, rate, seed, **params), if any
    cost: str | None = None  # import path of cost(system, rate, seed, **params), if any
    runner: str | None = None  # what a worker calls (a kind's trusted runner); None: function

    @property
    def worker_function(self) -> str:
        """The import path a worker calls with a grid row's typed values."""
        return self.runner or self.function

    def spec(self, name: str) -> ParamSpec:
        """The spec of parameter ``name`` (an open target's unknown names: any value)."""
        return self.params.get(name) or spec_for(name, None)


def load_target(kind: str, function: str | None = None) -> RunTarget:
    """The run target of ``kind`` (``learner`` or ``physical``) or of a custom ``function``.

    Valid parameters are the keyword-only arguments of the function plus the spec mappings of
    :data:`PARAM_SOURCES` (for a custom function: ``PARAMS`` or ``DEFAULT_VALUES`` of its
    module, if any: specs or defaults); valid systems come from ``SYSTEMS`` of the function's
    module or of ``pil.experiments.systems``; the whole-run check is :data:`CHECKS`' (for a custom
    function: ``check_run`` of its module, if any).
    """
    own = function is None  # the kind's own run function: its whole-run check applies
    if function is None:
        if kind not in KINDS:
            raise InvalidChoiceError("run kind", kind, KINDS)
        function = KINDS[kind]
    run_function = import_object(function)
    if not callable(run_function):
        raise SweepGridError(f"{function!r} is not a function")
    modules = [importlib.import_module(function.partition(":")[0])]
    check: str | None = None
    if kind in KINDS:
        modules.append(importlib.import_module(_SYSTEMS_MODULE))
        sources = [import_object(path) for path in PARAM_SOURCES[kind]]
    else:
        module = modules[0]
        sources = [getattr(module, "PARAMS", None) or getattr(module, "DEFAULT_VALUES", None) or {}]
    cost: str | None = None
    if own:
        check, cost = CHECKS[kind], COSTS.get(kind)
    elif callable(getattr(modules[0], "check_run", None)):
        check = f"{modules[0].__name__}:check_run"
    params: dict[str, ParamSpec] = {}
    for source in sources:
        params.update({name: spec_for(name, value) for name, value in source.items()})
    systems: tuple[str, ...] | None = None
    for module in modules:
        if systems is None and getattr(module, "SYSTEMS", None):
            systems = tuple(str(s) for s in module.SYSTEMS)
    open_params = False
    for parameter in list(inspect.signature(run_function).parameters.values())[3:]:
        if parameter.kind is inspect.Parameter.VAR_KEYWORD:
            open_params = not params
        elif parameter.name not in params:
            default = parameter.default
            default = None if default is inspect.Parameter.empty else default
            params[parameter.name] = spec_for(parameter.name, default)
    for name in RESERVED:
        params.pop(name, None)
    params = dict(sorted(params.items()))
    runner = RUNNERS.get(kind) if own else None
    return RunTarget(kind, function, systems, params, open_params, check, cost, runner)


@dataclass(frozen=True, slots=True)
class RunSpec:
    """One run of the grid: who (system), at which rate, with which parameters and seed."""

    run_id: str
    system: str
    rate: float
    rep: int
    seed: int
    params: tuple[tuple[str, Any], ...]  # (name, value) in the grid's parameter order

    def columns(self) -> dict[str, Any]:
        """The identifying columns of this run's row in the results file."""
        return {
            "run_id": self.run_id,
            "system": self.system,
            "rate": self.rate,
            **dict(self.params),
            "rep": self.rep,
            "seed": self.seed,
        }

    def call_args(self) -> tuple[tuple[str, float, int], dict[str, Any]]:
        """Positional and keyword arguments for the run function."""
        return (self.system, self.rate, self.seed), dict(self.params)


@dataclass(frozen=True, slots=True)
class Grid:
    """A validated grid; :meth:`runs` lists its runs, sorted by id."""

    target: RunTarget
    systems: tuple[str, ...]
    rates: tuple[float, ...]
    reps: int
    params: tuple[tuple[str, tuple[Any, ...]], ...]  # swept and fixed parameters, in order
    base_seed: int

    @property
    def swept(self) -> tuple[str, ...]:
        """The grid's axes that take more than one value (rate and system included)."""
        axes = [("system", self.systems), ("rate", self.rates), *self.params]
        return tuple(name for name, values in axes if len(values) > 1)

    def runs(self) -> list[RunSpec]:
        """Every run of the grid, sorted by run id."""
        combos: list[tuple[tuple[str, Any], ...]] = [()]
        for name, values in self.params:
            combos = [(*combo, (name, value)) for combo in combos for value in values]
        specs = []
        for rate in self.rates:
            for combo in combos:
                cell = "|".join([f"rate={format_value(rate)}"] + [_pair(n, v) for n, v in combo])
                for rep in range(self.reps):
                    key = f"{cell}|rep={rep:04d}"
                    seed = derive_seed(self.base_seed, key)
                    for system in self.systems:
                        specs.append(RunSpec(f"{system}|{key}", system, rate, rep, seed, combo))
        return sorted(specs, key=lambda spec: spec.run_id)


def format_value(value: Any) -> str:
    """Canonical text of a parameter value (floats by ``repr``: 0.3 -> '0.3')."""
    return repr(value) if isinstance(value, float) else str(value)


def _pair(name: str, value: Any) -> str:
    return f"{name}={format_value(value)}"


def derive_seed(base_seed: int, key: str) -> int:
    """A 32-bit seed from the base seed and a run's parameters (SHA-256, platform independent)."""
    digest = hashlib.sha256(f"{base_seed}|{key}".encode()).digest()
    return int.from_bytes(digest[:4], "big")


def split_list(text: str, what: str) -> list[str]:
    """``"a,b, c"`` -> ``["a", "b", "c"]``; an empty item or a repeat is an error."""
    items = [item.strip() for item in text.split(",")] if text.strip() else []
    if any(not item for item in items):
        raise SweepGridError(f"{what}: empty item in {text!r}")
    repeated = sorted({item for item in items if items.count(item) > 1})
    if repeated:
        raise SweepGridError(f"{what}: {', '.join(repeated)} given more than once in {text!r}")
    return items


def parse_param(text: str, target: RunTarget) -> tuple[str, tuple[Any, ...]]:
    """``"discard=0,0.3"`` -> ``("discard", (0.0, 0.3))``, checked against the target."""
    name, sep, values = text.partition("=")
    name = name.strip()
    if not sep or not name:
        raise SweepGridError(f"--param {text!r}: write it as NAME=V1,V2,...")
    if name in RESERVED:
        raise SweepGridError(f"--param {name}: not a parameter; use {RESERVED[name]}")
    if name not in target.params and not target.open_params:
        raise InvalidChoiceError(f"{target.kind} parameter", name, target.params)
    raw = split_list(values, f"--param {name}")
    if not raw:
        raise SweepGridError(f"empty grid: --param {name} has no values")
    spec = target.spec(name)
    parsed = tuple(spec.parse(item, f"--param {name}") for item in raw)
    if len({format_value(value) for value in parsed}) != len(parsed):
        raise SweepGridError(f"--param {name}: the same value given twice in {values!r}")
    return name, parsed


def build_grid(
    target: RunTarget,
    *,
    systems: Sequence[str] = DEFAULT_SYSTEMS,
    rates: Sequence[float | str] = DEFAULT_RATES,
    reps: int = PAPER_REPS,
    params: Sequence[str] = (),
    tables: int | None = ASSEMBLY_DEFAULTS["tables"],
    base_seed: int = 0,
) -> Grid:
    """Validate every part of a grid; raise one clear :class:`SweepGridError` on bad input."""
    if not systems:
        raise SweepGridError("empty grid: no systems given")
    if target.systems is not None:
        for system in systems:
            if system not in target.systems:
                raise InvalidChoiceError("system", system, target.systems)
    if not rates:
        raise SweepGridError("empty grid: no detection rates given")
    checked_rates = tuple(RATE.parse(rate, "--rates") for rate in rates)
    if len(set(checked_rates)) != len(checked_rates):
        raise SweepGridError(f"a detection rate is given twice in {list(rates)}")
    reps = REPS.parse(reps, "--reps")
    swept = [parse_param(text, target) for text in params]
    names = [name for name, _ in swept]
    repeated = sorted({name for name in names if names.count(name) > 1})
    if repeated:
        raise SweepGridError(f"--param {repeated[0]} given more than once")
    if tables is not None:
        if "tables" in names:
            raise SweepGridError("give the tables either with --tables or --param tables=...")
        swept.insert(0, ("tables", (target.spec("tables").parse(tables, "--tables"),)))
    base_seed = SEED.parse(base_seed, "--seed")
    grid = Grid(target, tuple(systems), checked_rates, reps, tuple(swept), base_seed)
    check_runs(grid)
    return grid


def longest_first(specs: Sequence[RunSpec], target: RunTarget) -> list[RunSpec]:
    """``specs`` in the order to start them: by the target's expected cost, longest first.

    Starting the longest runs first (LPT scheduling) keeps a worker from being left alone with
    a long run at the end of a sweep. Without a cost function the order is unchanged.
    """
    if target.cost is None:
        return list(specs)
    cost = import_object(target.cost)
    expected = {}
    for spec in specs:
        args, kwargs = spec.call_args()
        expected[spec.run_id] = float(cost(*args, **kwargs))
    return sorted(specs, key=lambda spec: -expected[spec.run_id])


def check_runs(grid: Grid) -> None:
    """Run the target's whole-run check once per distinct parameter combination (not per
    repetition or system), so a run that cannot start is refused before the first one."""
    if grid.target.check is None:
        return
    check = import_object(grid.target.check)
    seen: set[str] = set()
    for spec in grid.runs():
        key = "|".join(_pair(n, v) for n, v in spec.params)
        if key not in seen:
            seen.add(key)
            args, kwargs = spec.call_args()
            check(*args, **kwargs)
