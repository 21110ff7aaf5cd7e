"""What a run tells a study's log of each block (:attr:`Conductor.journal`): the fields of a
block that starts and of one that ends, JSON-ready (the session folder as a path)."""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    from robin_sim.live.session import LiveSession


def block_fields(session: LiveSession, status: dict[str, Any] | None = None) -> dict[str, Any]:
    """A block's journal fields; with its final ``status``, what became of it (legs, caps)."""
    config = session.config
    fields: dict[str, Any] = {
        "block": config.block,
        "condition": config.system,
        "practice": config.practice,
        "session": session.out_dir,
    }
    if status is None:
        return {**fields, "seed": config.seed}
    return {
        **fields,
        "status": status.get("status"),
        "legs_delivered": status.get("legs_delivered"),
        "legs_total": status.get("legs_total"),
        "limits": None if session.caps is None else session.caps.status(),
    }
