"""The robot: the five actions, their targets, and ``PhysicalWorld`` (the world in MuJoCo)."""
