"""Which group and condition order a new participant gets: balanced, in a seeded order.

A study's *cells* are its groups (one, ``all``, in a within design) and, in each, the condition
orders the protocol's ``order`` makes over the group's conditions (:func:`order_rows`: fixed,
counterbalanced, a balanced Latin square). A new participant goes to the group with the fewest
participants, then to that group's order with the fewest; ties are broken by a permutation
drawn from the study seed and the round (how many each tied cell has), so the sequence is
balanced in every round, not predictable from the list, and the same for the same registry.
Participants who declined or were withdrawn fill no cell (the next one takes the place).
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import numpy as np

from robin_sim.lab.registry import FILLING
from robin_sim.lab.study_file import Study
from robin_sim.live.protocol import order_rows


def group_orders(study: Study, group: str) -> list[tuple[str, ...]]:
    """The condition orders (system keys) of ``group``."""
    conditions = next(g.conditions for g in study.groups if g.name == group)
    return [
        tuple(conditions[i] for i in row)
        for row in order_rows(len(conditions), study.protocol.order)
    ]


def cells(study: Study) -> list[tuple[str, tuple[str, ...]]]:
    """Every (group, condition order) a participant may be assigned."""
    return [(g.name, order) for g in study.groups for order in group_orders(study, g.name)]


def assign(study: Study, entries: Sequence[dict[str, Any]]) -> tuple[str, tuple[str, ...]]:
    """The group and condition order of the next participant (see the module doc)."""
    filling = [e for e in entries if e.get("status") in FILLING]
    by_group = {g.name: sum(e.get("group") == g.name for e in filling) for g in study.groups}
    group = _least(list(by_group), by_group, study.seed, "group")
    orders = group_orders(study, group)
    by_order = {
        order: sum(e.get("group") == group and tuple(e.get("order", ())) == order for e in filling)
        for order in orders
    }
    return group, _least(orders, by_order, study.seed, group)


def _least(choices: list[Any], counts: dict[Any, int], seed: int, what: str) -> Any:
    """The first of the least-filled ``choices`` in the round's seeded permutation."""
    low = min(counts.values())
    entropy = [int(seed), low, *what.encode("utf-8")]
    order = np.random.default_rng(entropy).permutation(len(choices))
    return next(choices[i] for i in order if counts[choices[i]] == low)
