"""Render checks during an episode: after each grasp, handover and placement, look and compare.

:class:`RenderChecks` hooks into :class:`robin_sim.robot.world.PhysicalWorld`: when a wanted close,
or an open over the person's palm or a table spot, has succeeded physically, it renders
close-ups (:mod:`robin_sim.render.checks`) before the person takes anything away, and keeps the
result
for the step's log line: what the render says, what physics says, and whether they agree.
"""

from __future__ import annotations

from typing import Any

from pil.types import Action
from robin_sim.closing import ClosesOnExit
from robin_sim.model import names
from robin_sim.robot.actions import ActionResult
from robin_sim.robot.world import PhysicalWorld


class RenderChecks(ClosesOnExit):
    """Verifies the world's physical successes from off-screen renders (when ``enabled``)."""

    def __init__(self, world: PhysicalWorld, *, enabled: bool = True) -> None:
        self.world = world
        self.enabled = enabled
        self._renderer: Any = None  # a CloseUpRenderer once the first check needs one
        self._pending: dict[str, Any] | None = None
        if enabled:
            world.add_result_hook(self._on_result)

    def _close_up(self) -> Any:
        if self._renderer is None:  # built on the first check
            from robin_sim.render.renderer import CloseUpRenderer

            self._renderer = CloseUpRenderer(self.world.model)
        return self._renderer

    def _on_result(self, result: ActionResult) -> None:
        """Called by the world right after a wanted action, before anything else moves."""
        from robin_sim.render import checks as verify

        world, model, data = self.world, self.world.model, self.world.data
        leg = result.measurements.get("leg")
        if result.action is Action.CLOSE:
            held = world.held_leg()
            if held is None:
                return
            check = verify.verify_in_hand(model, data, held, names.ACTIVE_SIDE, self._close_up())
            what, leg, physics = "in hand", held, True
        elif result.action is Action.OPEN and leg is not None and result.succeeded:
            place = world.last_release
            if place is None:
                return
            point = place.point
            leg = int(leg)
            if place.kind == "palm":
                check = verify.verify_on_palm(model, data, leg, self._close_up())
                what = "on palm"
            else:
                spot = (float(point[0]), float(point[1]))
                check = verify.verify_at_spot(model, data, leg, spot, renderer=self._close_up())
                what = "at spot"
            physics = True
        else:
            return
        self._pending = {
            "check": what,
            "leg": int(leg),
            "render_ok": check.ok,
            "physics_ok": physics,
            "agrees": check.ok == physics,
            "detail": check.detail,
            "view": check.view,
            "pixels": check.pixels,  # the evidence the decision rests on
            "leg_pixels": check.leg_pixels,  # every leg pixel of the deciding view(s)
        }

    def take(self) -> dict[str, Any] | None:
        """The check made since the last call, if any."""
        pending, self._pending = self._pending, None
        return pending

    def close(self) -> None:
        """Free the renderer."""
        if self._renderer is not None:
            self._renderer.close()
            self._renderer = None
