"""Proactive Incremental Learning (PIL) of gesture-action associations; no MuJoCo inside."""

from pil.errors import RobinPilError
from pil.types import Action, Feedback, Gesture, Hand, State

__all__ = ["Action", "Feedback", "Gesture", "Hand", "RobinPilError", "State"]
