"""The association table T of the paper (eq. 2-4) plus what the learner remembers with it.

``T(s, a)`` counts how often action ``a`` got OK (or no feedback) in state ``s``; a not-OK
leaves it unchanged (eq. 2), so counts never decrease. Next to the counts the table keeps

* the *rejected* record: which actions ever got not-OK in a state (the learner re-explores
  those last), and
* the *transitions*: how often an approved state followed another approved state (``None``
  stands for the start of the task); the gesture correction of section III-B reads them.

All three are shared, merged (counts add) and saved together (:mod:`pil.table_io`, which
imports this module; this module never imports it).
Internally a state is its position in :data:`pil.validity.ALL_STATES` (its *id*) and an action
its position in :data:`pil.types.ACTIONS`, so the learner's hot path indexes lists.
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping
from types import MappingProxyType
from typing import Final

from pil.errors import RobinPilError
from pil.types import ACTIONS, Action, Feedback, State
from pil.validity import ALL_STATES

N_STATES = len(ALL_STATES)
START = N_STATES  # the id standing for "the start of the task" in the transitions
# Position of each action in ACTIONS (a StrEnum: its value text, e.g. "object", finds it too).
ACTION_INDEX: Final[Mapping[Action | str, int]] = {a: i for i, a in enumerate(ACTIONS)}
_STATE_ID: dict[State, int] = {s: i for i, s in enumerate(ALL_STATES)}
# The canonical State objects live as long as the module, so their id() never changes; looking
# them up by id() avoids the (Python-level) dataclass hash on the hot path (the learner's too).
STATE_ID_BY_OBJECT: Final[Mapping[int, int]] = {id(s): i for i, s in enumerate(ALL_STATES)}
_UNIFORM = 1.0 / len(ACTIONS)


def state_id(state: State | str) -> int:
    """Position of ``state`` in ALL_STATES; a key such as ``"pointing|open|free"`` is parsed."""
    found = STATE_ID_BY_OBJECT.get(id(state))
    if found is not None:
        return found
    if state.__class__ is State:
        return _STATE_ID[state]
    if isinstance(state, str):
        return _STATE_ID[State.from_key(state)]
    raise TypeError(f"expected a State, got {state!r}")


def canonical(state: State | str) -> State:
    """The shared State instance equal to ``state`` (keys such as ``"grasp|object|free"`` too)."""
    return ALL_STATES[state_id(state)]


def action_index(action: Action | str) -> int:
    """Position of ``action`` in :data:`pil.types.ACTIONS`; strings are parsed."""
    if action.__class__ is Action:
        return ACTION_INDEX[action]
    return ACTION_INDEX[Action.parse(action)]


def approves(ok: bool | Feedback | str) -> bool:
    """eta of eq. 1: True for OK and for no feedback; ``ok`` may be a bool or a Feedback."""
    if ok is True or ok is False:
        return ok
    if ok.__class__ is Feedback:
        return ok is not Feedback.NOT_OK
    return Feedback.parse(ok).approves


def state_sort_key(state: State | None) -> int:
    """A fixed order of states (``None``, the start of the task, first)."""
    return -1 if state is None else state_id(state)


def _source_id(previous: State | None) -> int:
    return START if previous is None else state_id(previous)


def _check_count(count: object, what: str) -> None:
    """A count must be a whole number >= 0 (not a bool, not a float such as 1.5 or 1.0)."""
    if isinstance(count, bool) or not isinstance(count, int) or count < 0:
        raise RobinPilError(
            f"{what} must be a whole number >= 0 (counts never decrease), got {count!r}"
        )


class AssociationTable:
    """Counts ``T(s, a)`` of approved state-action pairs, with rejections and transitions."""

    __slots__ = ("_best", "_counts", "_rejected", "_total", "_transitions")

    def __init__(self) -> None:
        # Per state id: counts per action (None until approved once; a tuple, so that
        # :meth:`row` can hand it out), the index of the unique best action (-1: none), and a
        # bit mask of the actions that ever got not-OK.
        self._counts: list[tuple[int, ...] | None] = [None] * N_STATES
        self._best: list[int] = [-1] * N_STATES
        self._rejected: list[int] = [0] * N_STATES
        # Per source id (START for the task start): follower id -> count.
        self._transitions: list[dict[int, int]] = [{} for _ in range(N_STATES + 1)]
        self._total = 0

    # -- writing (eq. 2) ------------------------------------------------------------------
    def update(self, state: State, action: Action | str, ok: bool | Feedback | str) -> None:
        """eq. 2: OK or no feedback adds one to ``T(state, action)``; not-OK records a rejection."""
        if approves(ok):
            self.approve_id(state_id(state), action_index(action))
        else:
            self.reject_id(state_id(state), action_index(action))

    # -- the id-level interface (the learner's hot path) ----------------------------------
    # A state is its id (:func:`state_id`, START for the task start in transitions), an action
    # its index in ACTIONS (:func:`action_index`); nothing is parsed or checked here.
    def approve_id(self, sid: int, index: int, count: int = 1) -> None:
        """Add ``count`` approvals of action ``index`` in state ``sid`` (eq. 2)."""
        row = self._counts[sid]
        values = [0] * len(ACTIONS) if row is None else list(row)
        values[index] += count
        self._counts[sid] = tuple(values)
        self._total += count
        top = max(values)
        self._best[sid] = values.index(top) if values.count(top) == 1 else -1

    def forget_id(self, sid: int, index: int, count: int = 1) -> None:
        """Remove up to ``count`` approvals of action ``index`` in ``sid`` (never below 0).

        Outside eq. 2 (where counts only grow): used only by a learner's adaptive option.
        """
        row = self._counts[sid]
        if row is None or not row[index]:
            return
        values = list(row)
        removed = min(count, values[index])
        values[index] -= removed
        self._total -= removed
        if not any(values):
            self._counts[sid], self._best[sid] = None, -1
            return
        self._counts[sid] = tuple(values)
        top = max(values)
        self._best[sid] = values.index(top) if values.count(top) == 1 else -1

    def reject_id(self, sid: int, index: int) -> None:
        """Record that action ``index`` got not-OK in state ``sid`` (counts unchanged)."""
        self._rejected[sid] |= 1 << index

    def follow_id(self, source: int, sid: int, count: int = 1) -> None:
        """Count that approved state ``sid`` followed approved ``source`` (START: task start)."""
        followers = self._transitions[source]
        followers[sid] = followers.get(sid, 0) + count

    def best_id(self, sid: int) -> int:
        """eq. 4 for state ``sid``: the index of the unique best action, -1 on a tie or unseen."""
        return self._best[sid]

    def row(self, sid: int) -> tuple[int, ...] | None:
        """The counts ``T(sid, .)`` per action index, or None for a state never approved."""
        return self._counts[sid]

    def rejected_mask(self, sid: int) -> int:
        """Bit ``i`` set when action index ``i`` ever got not-OK in state ``sid``."""
        return self._rejected[sid]

    def followers(self, source: int) -> Mapping[int, int]:
        """Follower state id -> count after approved ``source`` (START: task start), read-only."""
        return MappingProxyType(self._transitions[source])

    def add(self, state: State, action: Action | str, count: int) -> None:
        """Add ``count`` (a whole number >= 0) approvals at once (loading and merging tables)."""
        _check_count(count, f"count for {state} -> {action}")
        if count:
            self.approve_id(state_id(state), action_index(action), count)

    def reject(self, state: State, action: Action | str) -> None:
        """Record that ``action`` got not-OK in ``state`` (no change to the counts)."""
        self.reject_id(state_id(state), action_index(action))

    def record_transition(self, previous: State | None, state: State, count: int = 1) -> None:
        """Count that approved ``state`` followed approved ``previous`` (None: task start)."""
        _check_count(count, "transition count")
        if count:
            self.follow_id(_source_id(previous), state_id(state), count)

    # -- reading (eq. 3, 4) ---------------------------------------------------------------
    def count(self, state: State, action: Action | str) -> int:
        """``T(state, action)``."""
        index = action_index(action)
        row = self._counts[state_id(state)]
        return 0 if row is None else row[index]

    def counts(self, state: State) -> dict[Action, int]:
        """The row ``T(state, .)`` for every action."""
        row = self._counts[state_id(state)] or [0] * len(ACTIONS)
        return dict(zip(ACTIONS, row, strict=True))

    def probabilities(self, state: State) -> dict[Action, float]:
        """eq. 3: ``P(a | state)``; uniform over all actions for a state without approvals."""
        row = self._counts[state_id(state)]
        if row is None:
            return dict.fromkeys(ACTIONS, _UNIFORM)
        total = sum(row)
        return {a: c / total for a, c in zip(ACTIONS, row, strict=True)}

    def best(self, state: State) -> Action | None:
        """eq. 4: the unique most probable action, or None on a tie or for an unseen state."""
        index = self._best[state_id(state)]
        return None if index < 0 else ACTIONS[index]

    def rejected(self, state: State) -> frozenset[Action]:
        """The actions that ever got not-OK in ``state``."""
        mask = self._rejected[state_id(state)]
        return frozenset(a for i, a in enumerate(ACTIONS) if mask >> i & 1)

    def transitions(self, previous: State | None) -> dict[State, int]:
        """How often each approved state followed approved ``previous`` (None: task start)."""
        followers = self._transitions[_source_id(previous)]
        return {ALL_STATES[sid]: followers[sid] for sid in sorted(followers)}

    def is_empty(self) -> bool:
        """True while no association has been approved (T = empty set in Algorithm 1)."""
        return self._total == 0

    def total(self) -> int:
        """Sum of all counts."""
        return self._total

    def states(self) -> list[State]:
        """The states with at least one approved action, in a fixed order."""
        return [ALL_STATES[i] for i, row in enumerate(self._counts) if row is not None]

    def rejected_states(self) -> list[State]:
        """The states with at least one rejected action, in a fixed order."""
        return [ALL_STATES[i] for i, mask in enumerate(self._rejected) if mask]

    def transition_sources(self) -> list[State | None]:
        """The states (None: task start) with recorded followers, start first."""
        sources: list[State | None] = [None] if self._transitions[START] else []
        sources += [ALL_STATES[i] for i in range(N_STATES) if self._transitions[i]]
        return sources

    # -- combining ------------------------------------------------------------------------
    def copy(self) -> AssociationTable:
        """An independent copy."""
        return merge_all((self,))

    def merge(self, other: AssociationTable) -> AssociationTable:
        """A new table holding both: counts and transitions add, rejections unite."""
        return merge_all((self, other))

    def __eq__(self, other: object) -> bool:
        if not isinstance(other, AssociationTable):
            return NotImplemented
        return (
            self._counts == other._counts
            and self._rejected == other._rejected
            and self._transitions == other._transitions
        )

    __hash__ = None  # type: ignore[assignment]  # mutable

    def __repr__(self) -> str:
        return (
            f"AssociationTable({len(self.states())} states, {self._total} approvals, "
            f"{len(self.rejected_states())} states with rejections)"
        )


def merge_all(tables: Iterable[AssociationTable]) -> AssociationTable:
    """One new table holding all of ``tables`` (counts and transitions add, rejections unite)."""
    merged = AssociationTable()
    for table in tables:
        for sid, row in enumerate(table._counts):
            if row is not None:
                for index, count in enumerate(row):
                    if count:
                        merged.approve_id(sid, index, count)
            merged._rejected[sid] |= table._rejected[sid]
        for source, followers in enumerate(table._transitions):
            for sid, count in followers.items():
                merged.follow_id(source, sid, count)
    return merged
