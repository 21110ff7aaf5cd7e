"""Proactive Incremental Learning (PIL) of gesture-action associations; no MuJoCo inside.

The public API: the learner and its vocabulary, and a run's spec and assembly::

    from pil import assemble, parse_run_spec

    stats = assemble(parse_run_spec(system="c1", rate=0.6, seed=3)).run()
"""

from pil.errors import RobinPilError
from pil.learner import Decision, Learner
from pil.table import AssociationTable
from pil.table_io import load_table, save_table
from pil.task.assemble import Run, assemble
from pil.task.spec import RunSpec, parse_run_spec
from pil.types import Action, Feedback, Gesture, Hand, State
from pil.validity import is_valid

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
