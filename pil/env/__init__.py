"""A ``dm_env.Environment`` of the assembly task, for learners we did not write."""

from pil.env.assembly import (
    DISCARDED,
    AssemblyEnv,
    EnvStats,
    observation_state,
)

__all__ = ["DISCARDED", "AssemblyEnv", "EnvStats", "observation_state"]
