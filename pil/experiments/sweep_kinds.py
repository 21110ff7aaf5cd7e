"""The kinds of sweep run, one registry entry each (:class:`SweepKind`), and custom ones.

A kind names its parameters (specs of :mod:`pil.task.params`) and valid systems, and turns a
grid row (:class:`~pil.experiments.sweep_grid.GridRow`, its values parsed by those specs) into
its typed spec once, when the grid is built (``parse``); the sweep checks a spec once per
distinct cell (``check``), orders the runs by ``cost`` and ships each worker the kind's
``run`` and the typed spec, nothing else: no worker parses a value or spreads ``**params``.

* ``learner`` (this module's :data:`LEARNER_RUNS`): a learner-only run, a
  :class:`pil.task.spec.RunSpec` and its row (:func:`pil.experiments.run_row.spec_row`);
* ``physical`` (``robin_sim.episode.physical_run:PHYSICAL_RUNS``): an episode without video;
* a custom function (``--run-function MODULE:FUNCTION``, :func:`custom_kind`): called as
  ``function(system, rate, seed, **params)`` with the grid's typed values (its own interface).
"""

from __future__ import annotations

import importlib
import inspect
from collections.abc import Callable, Mapping, MutableMapping
from dataclasses import dataclass, field
from typing import Any

from pil.errors import InvalidChoiceError, RobinPilError
from pil.task.params import PARAMS, RUN_OPTIONS, ParamSpec, spec_for
from pil.task.systems import SYSTEM_SPECS

# where each kind's registry entry lives (physical runs need robin_sim: named by import path)
KINDS: dict[str, str] = {
    "learner": "pil.experiments.sweep_kinds:LEARNER_RUNS",
    "physical": "robin_sim.episode.physical_run:PHYSICAL_RUNS",
}
# what a sweep folder of each kind is bound to (its sweep.json's "function"): the names earlier
# versions recorded, kept so that their folders resume
BOUND_AS: dict[str, str] = {
    "learner": "pil.experiments.systems:run_one",
    "physical": "robin_sim.episode.physical_run:run_physical",
}
RESERVED: dict[str, str] = {
    "system": "--systems",
    "rate": "--rates",
    "seed": "--seed",
    "rep": "--reps",
}
_SYSTEMS_MODULE = "pil.task.systems"

Parse = Callable[["GridRow", MutableMapping[Any, Any]], Any]  # a kind's row -> its spec


class SweepGridError(RobinPilError):
    """A sweep grid that cannot run: empty, an unknown name, a value of the wrong type."""


@dataclass(frozen=True, slots=True)
class GridRow:
    """One run of the grid: who (system), at which rate, with which parameters and seed, and
    its kind's typed spec (:attr:`spec`, what a worker runs; None until the grid parses it)."""

    run_id: str
    system: str
    rate: float
    rep: int
    seed: int
    params: tuple[tuple[str, Any], ...]  # (name, value) in the grid's parameter order
    spec: Any = field(default=None, repr=False, compare=False)

    @property
    def cell(self) -> str:
        """The text of this row's parameter values (its cell, whatever system, rate, rep)."""
        return "|".join(pair_text(name, value) for name, value in self.params)

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


def format_value(value: Any) -> str:
    """Canonical text of a parameter value (floats by ``repr``: 0.3 -> '0.3')."""
    return repr(value) if isinstance(value, float) else str(value)


def pair_text(name: str, value: Any) -> str:
    """``name=value`` with the value's canonical text."""
    return f"{name}={format_value(value)}"


@dataclass(frozen=True, slots=True)
class SweepKind:
    """One kind of sweep run: its parameters, and how a grid row becomes a run.

    ``parse(row, cache)`` makes the row's typed spec (``cache``: one per grid, for what the
    rows of a cell share, e.g. the scenario file read once); ``check(spec)`` raises on a run
    that cannot start (called once per distinct cell, before the first run); ``cost(spec)``
    its expected length (longest first); ``run(spec)`` the run, a flat dict of metrics, in a
    worker (module-level functions: a worker needs nothing but the installed package).
    """

    name: str
    function: str  # what a sweep folder is bound to (sweep.json's "function"; BOUND_AS)
    params: Mapping[str, ParamSpec]  # valid parameter name -> its spec (type, range, default)
    systems: tuple[str, ...] | None  # None: any system name is passed through
    parse: Parse
    run: Callable[[Any], dict[str, Any]]
    check: Callable[[Any], None] | None = None
    cost: Callable[[Any], float] | None = None
    open_params: bool = False  # a custom function taking **params and naming no PARAMS

    def spec(self, name: str) -> ParamSpec:
        """The spec of parameter ``name`` (an open kind's unknown names: any value)."""
        return self.params.get(name) or spec_for(name, None)


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


def load_kind(kind: str, function: str | None = None) -> SweepKind:
    """The registry entry of ``kind`` (``learner`` or ``physical``), or a custom ``function``'s
    kind named ``kind`` (:func:`custom_kind`) when one is named."""
    if function is not None:
        return custom_kind(function, kind)
    if kind not in KINDS:
        raise InvalidChoiceError("run kind", kind, KINDS)
    entry = import_object(KINDS[kind])
    assert isinstance(entry, SweepKind), KINDS[kind]
    return entry


def scenario_of(name: str | None, cache: MutableMapping[Any, Any]) -> Any:
    """The scenario file ``name`` (None: the assembly), read once per grid (``cache``)."""
    from pil.task.assemble import cached
    from pil.task.scenario import load_scenario

    return cached(
        cache, ("scenario", name), lambda: load_scenario(*([] if name is None else [name]))
    )


# --- the learner-only kind ------------------------------------------------------------------
def parse_learner(row: GridRow, cache: MutableMapping[Any, Any]) -> Any:
    """The :class:`~pil.task.spec.RunSpec` of a learner row (values parsed by the grid: built,
    not parsed again; the scenario file read once per grid)."""
    from pil.task.assemble import cached
    from pil.task.spec import build_run_spec

    def cell() -> Any:
        values = dict(row.params)
        scenario = scenario_of(values.pop("scenario", None), cache)
        return build_run_spec(system="pil", rate=1.0, seed=0, scenario=scenario, values=values)

    return cached(cache, ("learner", row.cell), cell).for_run(row.system, row.rate, row.seed)


def run_learner(spec: Any) -> dict[str, Any]:
    """A learner-only run's row (:func:`pil.experiments.run_row.spec_row`)."""
    from pil.experiments.run_row import spec_row

    return spec_row(spec)


LEARNER_RUNS = SweepKind(
    name="learner",
    function=BOUND_AS["learner"],
    params=dict(sorted({**PARAMS, **RUN_OPTIONS}.items())),
    systems=tuple(SYSTEM_SPECS),
    parse=parse_learner,
    run=run_learner,
)


# --- a custom run function ------------------------------------------------------------------
@dataclass(frozen=True, slots=True)
class CustomCall:
    """A custom function's run: its import path and the row's typed values."""

    function: str
    system: str
    rate: float
    seed: int
    params: tuple[tuple[str, Any], ...]


@dataclass(frozen=True, slots=True)
class _CustomParse:
    """A custom row's spec: the function and the row's typed values, as they are."""

    function: str

    def __call__(self, row: GridRow, cache: MutableMapping[Any, Any]) -> CustomCall:
        return CustomCall(self.function, row.system, row.rate, row.seed, row.params)


def run_custom(call: CustomCall) -> dict[str, Any]:
    """A custom function's row: what it returns."""
    function = import_object(call.function)
    result = function(call.system, call.rate, call.seed, **dict(call.params))
    if not isinstance(result, Mapping):
        raise TypeError(f"{call.function} returned {type(result).__name__}, not a dict")
    return dict(result)


@dataclass(frozen=True, slots=True)
class _CustomCheck:
    """A custom module's ``check_run``, called with a row's typed values."""

    check: str  # import path of the module's check_run(system, rate, seed, **params)

    def __call__(self, call: CustomCall) -> None:
        import_object(self.check)(call.system, call.rate, call.seed, **dict(call.params))


def custom_kind(function: str, name: str = "custom") -> SweepKind:
    """The kind of a custom run ``function`` (``"package.module:function"``).

    Its parameters are its keyword-only arguments plus ``PARAMS`` or ``DEFAULT_VALUES`` of its
    module, if any (specs or defaults); its systems are ``SYSTEMS`` of its module or of
    ``pil.task.systems``; its whole-run check is ``check_run`` of its module, if any.
    """
    run_function = import_object(function)
    if not callable(run_function):
        raise SweepGridError(f"{function!r} is not a function")
    module = importlib.import_module(function.partition(":")[0])
    source = getattr(module, "PARAMS", None) or getattr(module, "DEFAULT_VALUES", None) or {}
    params = {name: spec_for(name, value) for name, value in source.items()}
    systems: tuple[str, ...] | None = None
    for owner in (module, importlib.import_module(_SYSTEMS_MODULE)):
        if systems is None and getattr(owner, "SYSTEMS", None):
            systems = tuple(str(s) for s in owner.SYSTEMS)
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
    check = None
    if callable(getattr(module, "check_run", None)):
        check = _CustomCheck(f"{module.__name__}:check_run")
    return SweepKind(
        name=name,
        function=function,
        params=dict(sorted(params.items())),
        systems=systems,
        parse=_CustomParse(function),
        run=run_custom,
        check=check,
        open_params=open_params,
    )
