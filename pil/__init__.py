"""Proactive Incremental Learning (PIL) of gesture-action associations; no MuJoCo inside.

The public API: the learner and its vocabulary, and a run's spec and assembly (imported on
first use, so that ``from pil import Learner`` stays light)::

    from pil import assemble, parse_run_spec

    stats = assemble(parse_run_spec(system="c1", rate=0.6, seed=3)).run()
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from pil.errors import RobinPilError
from pil.lazy_names import lazy_names
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


__getattr__, __dir__ = lazy_names("pil", _LAZY, globals(), __all__)
