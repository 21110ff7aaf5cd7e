"""Proactive Incremental Learning (PIL) of gesture-action associations; no MuJoCo inside."""

from pil.errors import RobinPilError
from pil.learner import Decision, Learner
from pil.table import AssociationTable
from pil.table_io import load_table, save_table
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
    "State",
    "is_valid",
    "load_table",
    "save_table",
]
