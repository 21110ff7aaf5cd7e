"""Errors the physical simulation raises on purpose (subclasses of ``RobinPilError``)."""

from __future__ import annotations

import math
from collections.abc import Sequence

from pil.errors import RobinPilError


class UnreachableTargetError(RobinPilError):
    """A motion target the arm cannot reach; raised before anything moves."""

    def __init__(
        self,
        target: str,
        position: Sequence[float],
        missed_by: float,
        turned_short_by: float,
        region: str,
    ) -> None:
        where = "(" + ", ".join(f"{v:.3f}" for v in position) + ")"
        super().__init__(
            f"{target} at {where} m is out of the arm's reach (the IK stops {missed_by * 100:.1f}"
            f" cm and {math.degrees(turned_short_by):.1f} degrees short); reachable: {region}."
            " Move it into the reachable region of the layout."
        )
        self.target = target
        self.position = tuple(float(v) for v in position)
        self.missed_by = missed_by
        self.turned_short_by = turned_short_by
        self.region = region
