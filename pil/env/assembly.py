"""The assembly task as a ``dm_env.Environment``: observe a reading, pick one of five actions,
get the person's verdict as the reward.

* Observation: a dict of ``gesture`` (the detected gesture's index in
  :data:`pil.types.GESTURES`; :data:`DISCARDED` = 4 when the detector discarded it),
  ``previous_action`` (the last approved action's index in :data:`pil.types.ACTIONS`) and
  ``hand`` (0 free, 1 occupied), each an ``int64`` scalar; with ``one_hot=True`` each is a
  ``float32`` one-hot vector instead.
* Action: an index into :data:`pil.types.ACTIONS` (``DiscreteArray(5)``).
* Reward: the person's feedback, +1.0 for OK (or no feedback) and -1.0 for not-OK, so the
  return is the approvals minus the rejections. The discount is 1.
* Episode: one assembly (the scenario's test tables, handover order drawn from the episode's
  seed). After an OK the next instruction gesture is read; after a not-OK the same reading
  stays. It ends when the script is done, or is truncated after ``max_actions_per_gesture``
  actions on one gesture.

The world is anything with the :class:`pil.task.world.World` protocol: the
:class:`~pil.task.world.SymbolicWorld` by default, or a factory that builds another (a
physical one) for each episode. The person, detector and seeds are the study's
(:func:`pil.task.assemble.assemble` of the environment's
:class:`~pil.task.spec.RunSpec`), so the same ``seed`` gives the same episode.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, replace
from pathlib import Path
from typing import Any

import dm_env
import numpy as np
from dm_env import specs

from pil.errors import RobinPilError, quote
from pil.task.assemble import assemble
from pil.task.params import MAX_SEED, STEP_RATE
from pil.task.person import PersonBody
from pil.task.runner import MAX_PERFORMANCES
from pil.task.scenario import Scenario
from pil.task.script import ScriptStep
from pil.task.spec import parse_run_spec
from pil.task.world import WORLD_METHODS, SymbolicWorld, World
from pil.types import ACTIONS, GESTURES, START_ACTION, Action, Feedback, Hand, State

DISCARDED = len(GESTURES)  # the gesture index of a discarded reading
_HANDS: tuple[Hand, ...] = (Hand.FREE, Hand.OCCUPIED)
_SIZES = {"gesture": len(GESTURES) + 1, "previous_action": len(ACTIONS), "hand": len(_HANDS)}


@dataclass(slots=True)
class EnvStats:
    """What the current episode cost so far (the study's counting)."""

    gestures: int = 0  # instruction gestures performed, repeats included
    actions: int = 0  # robot actions executed
    rejected: int = 0
    approved: int = 0  # instructions completed (an approved action each)


def observation_state(observation: dict[str, Any]) -> State | None:
    """The PIL state of an integer observation (None for a discarded reading)."""
    gesture = int(observation["gesture"])
    if gesture == DISCARDED:
        return None
    previous = ACTIONS[int(observation["previous_action"])]
    return State(GESTURES[gesture], previous, _HANDS[int(observation["hand"])])


class AssemblyEnv(dm_env.Environment):
    """The learner-only assembly (or any :class:`World`) behind ``dm_env`` (module docstring).

    ``rate``: detection rate; ``seed``: episode ``k`` uses run seed ``seed + k``; ``world``:
    a factory called once per episode (default :class:`SymbolicWorld`); ``body``: a factory of
    the person's body in that world (a physical world needs one: it gestures, holds out the
    palm and watches the robot; ``robin_sim.person.body.PhysicalBody``); ``repeat_discarded``
    (default True, the study's): a discarded reading makes the person repeat the gesture
    inside the environment, so observations are never :data:`DISCARDED`; ``params``: any of
    :data:`pil.task.params.PARAMS` (``tables``, ``discard``, ``silent_ok``...).
    """

    def __init__(
        self,
        rate: float = 1.0,
        seed: int = 0,
        *,
        scenario: Scenario | str | Path | None = None,
        world: Callable[[], World] = SymbolicWorld,
        body: Callable[[Any], PersonBody] | None = None,
        one_hot: bool = False,
        **params: Any,
    ) -> None:
        self.rate = STEP_RATE.parse(rate, "detection rate")
        if isinstance(seed, bool) or not isinstance(seed, int) or not 0 <= seed <= MAX_SEED:
            raise RobinPilError(f"seed must be a whole number from 0 to {MAX_SEED}, got {seed!r}")
        if not callable(world):
            raise RobinPilError(
                f"world must be a factory of worlds (e.g. SymbolicWorld), got {world!r}"
            )
        self.seed = seed
        # the parameters and the scenario parsed once, here; the rate as parsed above (the
        # environment allows 0), the seed of each episode set by reset()
        self._spec = replace(parse_run_spec(scenario=scenario, params=params), rate=self.rate)
        self._make_world = world
        self._make_body = body
        if not isinstance(one_hot, bool):  # "no" would be truthy: one-hot on by mistake
            raise RobinPilError(f"one_hot must be True or False, got {quote(one_hot)}")
        self.one_hot = one_hot
        self.episode = -1
        self.stats = EnvStats()
        self.world: World | None = None
        self._done = True
        self._state: State | None = None
        self._started = False

    # -- specs ------------------------------------------------------------------------------
    def observation_spec(self) -> dict[str, specs.Array]:
        """Three scalars (int64) or, with ``one_hot``, three one-hot float32 vectors."""
        if self.one_hot:
            return {
                k: specs.BoundedArray((n,), np.float32, 0.0, 1.0, name=k) for k, n in _SIZES.items()
            }
        return {k: specs.BoundedArray((), np.int64, 0, n - 1, name=k) for k, n in _SIZES.items()}

    def action_spec(self) -> specs.DiscreteArray:
        """One of the five actions, as its index in :data:`pil.types.ACTIONS`."""
        return specs.DiscreteArray(len(ACTIONS), dtype=np.int64, name="action")

    def reward_spec(self) -> specs.Array:
        """+1.0 (OK) or -1.0 (not-OK)."""
        return specs.BoundedArray((), np.float64, -1.0, 1.0, name="reward")

    # -- episode ----------------------------------------------------------------------------
    def reset(self) -> dm_env.TimeStep:
        """Start the next assembly: a new handover order, detector deck and world."""
        self.episode += 1
        world = self._make_world()
        if not all(callable(getattr(world, name, None)) for name in WORLD_METHODS):
            raise TypeError(
                f"world() must return a World (an object with the methods "
                f"{', '.join(WORLD_METHODS)}, e.g. SymbolicWorld()), got {quote(world)}"
            )
        self.world = world
        body = None if self._make_body is None else self._make_body(self.world)
        spec = self._spec.for_run("pil", self.rate, self.run_seed(self.episode))
        parts = assemble(spec, body=body)
        self._started = True
        self._person, self._detector = parts.person, parts.detector
        self._repeat_discarded = bool(parts.options["repeat_discarded"])
        self._limit = int(parts.options["max_actions_per_gesture"])
        self.stats = EnvStats()
        self._item: ScriptStep | None = None
        self._laid: set[int] = set()
        self._previous: Action = START_ACTION
        self._done = False
        self._next_instruction()
        return dm_env.restart(self._observation())

    def step(self, action: int | np.integer | np.ndarray | Action) -> dm_env.TimeStep:
        """Execute ``action`` for the current reading; the reward is the person's verdict."""
        if self._done:
            return self.reset()
        chosen = self._action(action)
        item, person = self._item, self._person
        assert self.world is not None and item is not None
        outcome = self.world.execute(chosen, item.intent.target, person.watch(item.intent))
        self.stats.actions += 1
        self._spent += 1
        feedback = person.judge(item.intent, chosen, outcome)
        person.show_feedback(feedback)
        feedback = self._detector.read_feedback(feedback)
        person.after_feedback(feedback)
        ok = feedback is not Feedback.NOT_OK
        if ok:
            self._previous = chosen
            self.stats.approved += 1
            person.completed(item, chosen)
            if not self._next_instruction():
                self._done = True
                return dm_env.termination(1.0, self._observation())
            return dm_env.transition(1.0, self._observation())
        self.stats.rejected += 1
        if self._spent >= self._limit:
            self._done = True
            return dm_env.truncation(-1.0, self._observation())
        return dm_env.transition(-1.0, self._observation())

    def state(self) -> State | None:
        """The current observation as a PIL state (None: discarded), for our agents."""
        if not self._started:
            raise RobinPilError("no observation yet: call reset() before state()")
        return self._state

    def run_seed(self, episode: int) -> int:
        """The run seed of episode ``episode``: ``seed + episode``, wrapped to stay a valid
        seed (so that ``seed=2**63 - 1`` runs many episodes too)."""
        return (self.seed + episode) % (MAX_SEED + 1)

    # -- internals --------------------------------------------------------------------------
    def _action(self, action: int | np.integer | np.ndarray | Action) -> Action:
        if isinstance(action, Action):
            return action
        if isinstance(action, np.ndarray) and action.shape == ():  # as action_spec() makes them
            action = action[()]
        if isinstance(action, (bool, np.bool_)) or not isinstance(action, (int, np.integer)):
            raise RobinPilError(
                f"action must be an index 0-{len(ACTIONS) - 1} or an Action, got {action!r}"
            )
        if not 0 <= int(action) < len(ACTIONS):
            names = ", ".join(f"{i} {a.value}" for i, a in enumerate(ACTIONS))
            raise RobinPilError(f"action index {int(action)} out of range; valid: {names}")
        return ACTIONS[int(action)]

    def _next_instruction(self) -> bool:
        """Move to the person's next gesture and read it (repeating discarded readings);
        False when the script is done."""
        assert self.world is not None
        item = self._person.next_step(self.world.hand())
        if item is None:
            return False
        self._item = item
        if item.first_of_table and item.intent.table not in self._laid:
            self._laid.add(item.intent.table)
            self._person.start_table(item.intent.table)
            self.world.start_table(item.intent.table)
        self._spent = 0
        for _ in range(MAX_PERFORMANCES):
            self.stats.gestures += 1
            self._person.perform(item.intent)
            detected = self._detector.detect(item.intent.gesture)
            if detected is not None or not self._repeat_discarded:
                break
        else:
            raise RobinPilError(
                f"gesture {item.intent.gesture.value!r} was discarded {MAX_PERFORMANCES} times "
                f"in a row (detection rate {self.rate}); use a higher rate or "
                "repeat_discarded=False"
            )
        assert self.world is not None
        hand = self.world.hand()
        self._state = None if detected is None else State(detected, self._previous, hand)
        self._codes = {
            "gesture": DISCARDED if detected is None else GESTURES.index(detected),
            "previous_action": ACTIONS.index(self._previous),
            "hand": _HANDS.index(hand),
        }
        return True

    def _observation(self) -> dict[str, np.ndarray]:
        if not self.one_hot:
            return {k: np.asarray(v, dtype=np.int64) for k, v in self._codes.items()}
        out = {}
        for k, v in self._codes.items():
            vector = np.zeros(_SIZES[k], dtype=np.float32)
            vector[v] = 1.0
            out[k] = vector
        return out
