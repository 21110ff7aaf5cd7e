"""The grid of a sweep: systems × detection rates × swept parameters × repetitions.

Every run gets a stable, readable id built from its parameters, e.g.
``pil|rate=0.6|tables=10|discard=0.3|rep=0007``, and a seed derived from the base seed and
those parameters (not from the position in the grid, the worker or the order of execution).
The seed does not depend on the system: the systems of one (rate, parameters, repetition) cell
face the same person and detector draws (common random numbers), which makes the comparison
fairer. Everything the user gives is checked here, before any run starts.

Each row is parsed once, when the grid is built, into its kind's typed spec
(:class:`~pil.experiments.sweep_kinds.SweepKind`'s ``parse``): :attr:`GridRow.spec` is what a
worker runs, nothing parsed again there.
"""

from __future__ import annotations

import hashlib
from collections.abc import Sequence
from dataclasses import dataclass, field, replace
from typing import Any

from pil.errors import InvalidChoiceError
from pil.experiments.paper import PAPER_RATES, PAPER_REPS
from pil.experiments.sweep_kinds import (
    RESERVED,
    GridRow,
    SweepGridError,
    SweepKind,
    format_value,
    pair_text,
)
from pil.task.params import ASSEMBLY_DEFAULTS, RATE, REPS, SEED
from pil.task.systems import PAPER_SYSTEMS

__all__ = [
    "DEFAULT_RATES",
    "DEFAULT_SYSTEMS",
    "Grid",
    "GridRow",
    "SweepGridError",
    "build_grid",
    "derive_seed",
    "format_value",
    "longest_first",
    "parse_param",
    "split_list",
]

DEFAULT_SYSTEMS: tuple[str, ...] = tuple(PAPER_SYSTEMS)  # the paper's five
DEFAULT_RATES: tuple[float, ...] = PAPER_RATES


@dataclass(frozen=True, slots=True)
class Grid:
    """A validated grid; :meth:`runs` lists its runs, sorted by id, each parsed once."""

    kind: SweepKind
    systems: tuple[str, ...]
    rates: tuple[float, ...]
    reps: int
    params: tuple[tuple[str, tuple[Any, ...]], ...]  # swept and fixed parameters, in order
    base_seed: int
    rows: tuple[GridRow, ...] = field(default=(), repr=False)  # parsed by build_grid

    @property
    def swept(self) -> tuple[str, ...]:
        """The grid's axes that take more than one value (rate and system included)."""
        axes = [("system", self.systems), ("rate", self.rates), *self.params]
        return tuple(name for name, values in axes if len(values) > 1)

    def runs(self) -> list[GridRow]:
        """Every run of the grid, sorted by run id, with its typed spec."""
        return list(self.rows)

    def expand(self) -> list[GridRow]:
        """Every run of the grid, sorted by run id, not yet parsed (no spec)."""
        combos: list[tuple[tuple[str, Any], ...]] = [()]
        for name, values in self.params:
            combos = [(*combo, (name, value)) for combo in combos for value in values]
        specs = []
        for rate in self.rates:
            for combo in combos:
                cell = "|".join(
                    [f"rate={format_value(rate)}"] + [pair_text(n, v) for n, v in combo]
                )
                for rep in range(self.reps):
                    key = f"{cell}|rep={rep:04d}"
                    seed = derive_seed(self.base_seed, key)
                    for system in self.systems:
                        specs.append(GridRow(f"{system}|{key}", system, rate, rep, seed, combo))
        return sorted(specs, key=lambda spec: spec.run_id)


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


def parse_param(text: str, target: SweepKind) -> tuple[str, tuple[Any, ...]]:
    """``"discard=0,0.3"`` -> ``("discard", (0.0, 0.3))``, checked against the target."""
    name, sep, values = text.partition("=")
    name = name.strip()
    if not sep or not name:
        raise SweepGridError(f"--param {text!r}: write it as NAME=V1,V2,...")
    if name in RESERVED:
        raise SweepGridError(f"--param {name}: not a parameter; use {RESERVED[name]}")
    if name not in target.params and not target.open_params:
        raise InvalidChoiceError(f"{target.name} parameter", name, target.params)
    raw = split_list(values, f"--param {name}")
    if not raw:
        raise SweepGridError(f"empty grid: --param {name} has no values")
    spec = target.spec(name)
    parsed = tuple(spec.parse(item, f"--param {name}") for item in raw)
    if len({format_value(value) for value in parsed}) != len(parsed):
        raise SweepGridError(f"--param {name}: the same value given twice in {values!r}")
    return name, parsed


def build_grid(
    target: SweepKind,
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
    return replace(grid, rows=tuple(parse_rows(target, grid.expand())))


def parse_rows(kind: SweepKind, rows: Sequence[GridRow]) -> list[GridRow]:
    """Each row with its kind's typed spec, parsed once; the kind's whole-run check once per
    distinct parameter combination (not per repetition or system), so that a run that cannot
    start is refused before the first one."""
    cache: dict[Any, Any] = {}
    parsed = [replace(row, spec=kind.parse(row, cache)) for row in rows]
    if kind.check is not None:
        seen: set[str] = set()
        for row in parsed:
            key = row.cell
            if key not in seen:
                seen.add(key)
                kind.check(row.spec)
    return parsed


def longest_first(rows: Sequence[GridRow], kind: SweepKind) -> list[GridRow]:
    """``rows`` in the order to start them: by the kind's expected cost, longest first.

    Starting the longest runs first (LPT scheduling) keeps a worker from being left alone with
    a long run at the end of a sweep. Without a cost function the order is unchanged.
    """
    cost = kind.cost
    if cost is None:
        return list(rows)
    expected = {row.run_id: float(cost(row.spec)) for row in rows}
    return sorted(rows, key=lambda row: -expected[row.run_id])
