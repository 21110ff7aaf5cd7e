"""How the learner picks the next action in a state: the exploration rules.

Equations 2-4 fix the exploit (the unique argmax of P(a|s), eq. 4) but not what happens after a
not-OK: T is left unchanged (eq. 2), so the argmax would stay the same, and section III only
says that the robot then tries "the next best action", and the actions that got not-OK last.
Each rule is one reading of that; all exploit the unique best action first in a step.

* ``next-best`` (the default): after a not-OK, the learnt actions (count > 0) not yet tried in
  this step by falling P (ties at random): section III-B's "next best action"; then, when none
  is left, at random among the actions other than the one just rejected, those that got not-OK
  before included (III-B: "explores the actions which had received not-OK"). It remembers
  two things of the step: every action tried in it (the ranked learnt actions skip them all)
  and the one just refused (the only one the random draw avoids), so a random draw can
  repeat an unlearnt action refused two actions ago.
* ``avoid-last``: after a not-OK, at random among the four actions other than the one just
  rejected, learnt or not (Algorithm 1, lines 8-13: the argmax when unique, else random).
* ``with-replacement``: after a not-OK, at random among all five actions, the rejected one
  included: eq. 2-4 taken word for word, with the argmax tried once per step.
* ``untried-first``: never repeat an action within a step until all five were tried, and rank
  the others as learnt ones by falling P (ties at random), then actions never tried in this
  state, then actions rejected in earlier steps, each group at random. The fewest actions;
  this project's first rule.

Every rule ranks the learnt actions without those tried in this step (the step's refusals in
the state, kept by :class:`pil.step_memory.StepMemory` whatever its setting); the random
draws of ``next-best``, ``avoid-last`` and ``with-replacement`` avoid at most the action just
refused. The within-step memory (``step_memory`` on, :mod:`pil.step_memory`) restricts every
draw to the actions not refused in this step, as the baselines do; ``untried-first`` already
never repeats one, so the memory does not change it.

A rule is a function of the table, the state id, the actions tried in this step (a bit mask),
the action just rejected in this state (-1: none), the learner's random generator and the
mask of the actions it may choose (all five without the memory); it returns the action index,
whether it was an exploit, and the reason.
"""

from __future__ import annotations

import random
from collections.abc import Callable

from pil.step_memory import ALL_ACTIONS
from pil.table import AssociationTable
from pil.types import ACTIONS

ALL_TRIED = ALL_ACTIONS
_INDICES = range(len(ACTIONS))
Choice = tuple[int, bool, str]
Rule = Callable[[AssociationTable, int, int, int, random.Random, int], Choice]


def _unique_best(table: AssociationTable, sid: int, tried: int) -> Choice | None:
    """eq. 4's unique best, if it was not tried in this step yet."""
    best = table.best_id(sid)
    if best >= 0 and not tried >> best & 1:
        return best, True, "unique best"
    return None


def _next_learnt(
    table: AssociationTable, sid: int, tried: int, rng: random.Random
) -> Choice | None:
    """The most probable learnt action not tried in this step (ties at random), if any."""
    row = table.row(sid)
    if row is None:
        return None
    top = max((c for i, c in enumerate(row) if c and not tried >> i & 1), default=0)
    if not top:
        return None
    tops = [i for i, c in enumerate(row) if c == top and not tried >> i & 1]
    if len(tops) == 1:
        return tops[0], False, "next best"
    return rng.choice(tops), False, "tie among learnt"


def _random_but(last: int, rng: random.Random, allowed: int = ALL_TRIED) -> Choice:
    """At random among the ``allowed`` actions but ``last`` (-1: among all of them)."""
    if allowed != ALL_TRIED:  # the within-step memory is on (it has refused ``last`` too)
        pool = [i for i in _INDICES if allowed >> i & 1 and i != last]
        pool = pool or [i for i in _INDICES if allowed >> i & 1]
        return rng.choice(pool), False, "explore, not repeating this step's refusals"
    if last < 0:
        return rng.randrange(len(ACTIONS)), False, "explore at random"
    others = [i for i in _INDICES if i != last]
    return rng.choice(others), False, "explore, avoiding the action just rejected"


def next_best(
    table: AssociationTable,
    sid: int,
    tried: int,
    last: int,
    rng: random.Random,
    allowed: int = ALL_TRIED,
) -> Choice:
    """The unique best, then learnt actions by falling P, then random but the last rejected."""
    return (
        _unique_best(table, sid, tried)
        or _next_learnt(table, sid, tried, rng)
        or _random_but(last, rng, allowed)
    )


def avoid_last(
    table: AssociationTable,
    sid: int,
    tried: int,
    last: int,
    rng: random.Random,
    allowed: int = ALL_TRIED,
) -> Choice:
    """The unique best once per step, else at random among all but the action just rejected."""
    return _unique_best(table, sid, tried) or _random_but(last, rng, allowed)


def with_replacement(
    table: AssociationTable,
    sid: int,
    tried: int,
    last: int,
    rng: random.Random,
    allowed: int = ALL_TRIED,
) -> Choice:
    """The unique best once per step, else at random among all five (the allowed ones)."""
    found = _unique_best(table, sid, tried)
    if found is not None:
        return found
    if allowed != ALL_TRIED:
        pool = [i for i in _INDICES if allowed >> i & 1]
        return rng.choice(pool), False, "explore at random, not repeating this step's refusals"
    return rng.randrange(len(ACTIONS)), False, "explore at random (with replacement)"


def untried_first(
    table: AssociationTable,
    sid: int,
    tried: int,
    last: int,
    rng: random.Random,
    allowed: int = ALL_TRIED,
) -> Choice:
    """No repeat within a step; learnt by P, then never tried, then rejected before (the
    within-step memory changes nothing: the rule already keeps to the untried actions)."""
    if tried == ALL_TRIED:  # every action was rejected in this step: start over
        tried = 0
    found = _unique_best(table, sid, tried) or _next_learnt(table, sid, tried, rng)
    if found is not None:
        return found
    row = table.row(sid)
    learnt = 0 if row is None else sum(1 << i for i, c in enumerate(row) if c)
    fresh = [i for i in _INDICES if not (tried | table.rejected_mask(sid) | learnt) >> i & 1]
    if fresh:
        return rng.choice(fresh), False, "explore untried"
    left = [i for i in _INDICES if not (tried | learnt) >> i & 1]
    return rng.choice(left), False, "re-explore rejected"


DEFAULT_RULE = "next-best"
RULES: dict[str, Rule] = {
    DEFAULT_RULE: next_best,
    "avoid-last": avoid_last,
    "with-replacement": with_replacement,
    "untried-first": untried_first,
}
