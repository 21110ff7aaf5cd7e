"""The robust PIL rule (``pil-robust``): :class:`RobustLearner` (see :mod:`pil.robust.learner`)."""

from pil.robust.learner import RobustLearner

__all__ = ["RobustLearner"]
