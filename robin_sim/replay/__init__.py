"""Replaying a recorded run (an episode or a live session) from its ``states.npz``."""
