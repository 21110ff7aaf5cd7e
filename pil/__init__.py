"""Proactive Incremental Learning (PIL) of gesture-action associations; no MuJoCo inside.

The public API: the learner and its vocabulary, and a run's spec and assembly (imported on
first use, so that ``from pil import Learner`` stays light)::

    from pil import assemble, parse_run_spec

    stats = assemble(parse_run_spec(system="c1", rate=0.6, seed=3)).run()
"""

from __future__ import annotations

import importlib
from typing import TYPE_CHECKING, Any

from pil.errors import RobinPilError
from pil.learner import Decision, Learner
from pil.table import AssociationTable
from pil.table_io import load_table, save_table
from pil.types import Action, Feedback, Gesture, Hand, State
from pil.validity import is_valid

if TYPE_CHECKING:
    from pil.task.assemble import Run, assemble
    from pil.task.spec import RunSpec, parse_run_spec

# name -> the module that defines it, for the names imported on first use (PEP 562)
_LAZY: dict[str, str] = {
    "Run": "pil.task.assemble",
    "RunSpec": "pil.task.spec",
    "assemble": "pil.task.assemble",
    "parse_run_spec": "pil.task.spec",
}
__all__ = [
    "Action",
    "AssociationTable",
    "Decision",
    "Feedback",
    "Gesture",
    "Hand",
    "Learner",
    "RobinPilError",
    "Run",
    "RunSpec",
    "State",
    "assemble",
    "is_valid",
    "load_table",
    "parse_run_spec",
    "save_table",
]


def __getattr__(name: str) -> Any:
    """A run-assembly name, imported from its module on first use."""
    if name not in _LAZY:
        raise AttributeError(f"module 'pil' has no attribute {name!r}")
    value = getattr(importlib.import_module(_LAZY[name]), name)
    globals()[name] = value
    return value


def __dir__() -> list[str]:
    return sorted({*globals(), *__all__})
