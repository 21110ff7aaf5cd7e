"""An entrant's code run under watch: a time limit on every call, and one error for any fault.

``--agent`` runs code the benchmark did not write. Every call into it (building the agent,
``select_action``, ``observe``, or the agent protocol's ``decide``, ``choose``, ``feedback``,
``correct``, ``save`` and any optional hook) goes through :meth:`TimeLimit.call`: whatever the
call does wrong (raises, calls ``sys.exit``, takes longer than the limit) becomes one
:class:`pil.bench.entrants.EntrantError` saying what it did; :mod:`pil.bench.run` adds the run
(agent, track, condition, seed). ``KeyboardInterrupt`` passes through untouched (Ctrl-C and
SIGTERM stop the bench as always).

The limit is a ``SIGALRM`` timer (``setitimer``) armed for each call and disarmed after it:
two system calls per decision, no thread. It works in the main thread of a process, which is
where the bench runs its entrants (the command itself, or each worker process of the pool);
elsewhere the call is timed afterwards instead (a call that never returns cannot be stopped
there). The timer rings again every second while the call goes on; a call that swallowed the
first stop (``except BaseException``, a bare ``except:``) is then stopped at its next line
through the trace hook. A single call into C code that never returns to Python (a blocking
read in an extension) is stopped only when it does.
"""

from __future__ import annotations

import signal
import sys
import threading
import time
from collections.abc import Callable
from types import FrameType, TracebackType
from typing import Any

from pil.agents import Agent
from pil.bench.entrants import EntrantError, Factory, as_agent
from pil.errors import quote
from pil.learner import Decision
from pil.types import Action

DECISION_TIMEOUT = 10.0  # seconds: a reference agent decides in well under a millisecond
MAX_DECISION_TIMEOUT = 3600.0
_RING_AGAIN = 1.0  # seconds between the rings of a call that goes on after its stop


class _Stop(BaseException):
    """The limit ran out (a BaseException: ``except Exception`` in an entrant does not catch
    it)."""


class TimeLimit:
    """Calls into an entrant, each stopped after ``seconds`` (module docstring). Use it as a
    context (``with TimeLimit(10) as limit: limit.call(...)``): it holds ``SIGALRM`` while
    open and gives the previous handler back on leaving."""

    def __init__(self, seconds: float = DECISION_TIMEOUT) -> None:
        self.seconds = float(seconds)
        self._alarm = hasattr(signal, "setitimer")
        self._previous: Any = None
        self._outer: tuple[tuple[float, float], float] = ((0.0, 0.0), 0.0)
        self._armed = False  # a call is under way
        self._rings = 0  # how often the timer rang during this call

    def __enter__(self) -> TimeLimit:
        self._alarm = hasattr(signal, "setitimer") and (
            threading.current_thread() is threading.main_thread()
        )
        if self._alarm:  # an outer timer (a test runner's) waits, and runs on afterwards
            self._outer = (signal.getitimer(signal.ITIMER_REAL), time.monotonic())
            self._previous = signal.signal(signal.SIGALRM, self._ring)
        return self

    def __exit__(
        self,
        kind: type[BaseException] | None,
        error: BaseException | None,
        trace: TracebackType | None,
    ) -> None:
        if self._alarm:
            signal.setitimer(signal.ITIMER_REAL, 0)
            signal.signal(signal.SIGALRM, self._previous)
            (left, every), since = self._outer
            if left > 0:
                signal.setitimer(
                    signal.ITIMER_REAL, max(left - (time.monotonic() - since), 1e-3), every
                )

    def _ring(self, signum: int, frame: FrameType | None) -> None:
        if not self._armed:
            return
        self._rings += 1
        if self._rings > 1 and frame is not None:  # the first stop was swallowed
            self._stop_at_next_line(frame)
        raise _Stop

    def _stop_at_next_line(self, frame: FrameType) -> None:
        def stop(_frame: FrameType, event: str, _arg: Any) -> Any:
            if not self._armed:
                return None
            if event == "line":  # (an error in a trace function also ends the tracing)
                raise _Stop
            return stop

        here: FrameType | None = frame
        while here is not None:
            here.f_trace = stop
            here = here.f_back
        sys.settrace(stop)

    def call(self, what: str, function: Callable[..., Any], *args: Any) -> Any:
        """``function(*args)``, the entrant's ``what``, under the limit; EntrantError saying
        what it did when it raises, exits or runs past the limit."""
        self._rings = 0
        started = time.monotonic()
        tracing = sys.gettrace()
        self._armed = True
        if self._alarm:
            signal.setitimer(signal.ITIMER_REAL, self.seconds, _RING_AGAIN)
        try:
            result = function(*args)
        except _Stop:
            raise self._late(what) from None
        except EntrantError:
            raise
        except (Exception, SystemExit) as error:
            if self._rings:  # it swallowed the stop, then failed
                raise self._late(what) from None
            raise EntrantError(f"{what} raised {type(error).__name__}: {error}") from None
        finally:
            self._armed = False
            if self._alarm:
                signal.setitimer(signal.ITIMER_REAL, 0)
                if self._rings > 1:
                    sys.settrace(tracing)
        if self._rings or time.monotonic() - started > self.seconds:
            raise self._late(what)
        return result

    def _late(self, what: str) -> EntrantError:
        return EntrantError(
            f"{what} took longer than the limit of {self.seconds:g} s per call "
            "(--decision-timeout) and was stopped"
        )


class GuardedActor:
    """An actor of the environment (``select_action``, ``observe``) whose calls run under
    ``limit``."""

    def __init__(self, actor: Any, limit: TimeLimit) -> None:
        self._actor, self._limit = actor, limit

    def select_action(self, observation: Any) -> Any:
        """The actor's action (checked by :class:`pil.bench.entrants.ActorAgent`)."""
        return self._limit.call("select_action", self._actor.select_action, observation)

    def observe(self, action: int, reward: float) -> None:
        """The reward of ``action``, told to the actor."""
        self._limit.call("observe", self._actor.observe, action, reward)


class GuardedAgent:
    """An agent of the protocol (:class:`pil.agents.Agent`) whose calls run under ``limit``
    and whose answers are checked; its optional hooks (``heard``, ``restart``, ...) too."""

    def __init__(self, agent: Any, limit: TimeLimit) -> None:
        self._agent, self._limit = agent, limit

    @property
    def table(self) -> Any:
        """The agent's association table."""
        return self._agent.table

    @property
    def last_exploited(self) -> bool:
        """Whether its last choice exploited what it learnt."""
        return bool(self._agent.last_exploited)

    @property
    def last_reason(self) -> str:
        """Why it made its last choice."""
        return str(self._agent.last_reason)

    def decide(self, *args: Any) -> Decision:
        """The agent's decision, checked."""
        decision = self._limit.call("decide", self._agent.decide, *args)
        if not isinstance(decision, Decision) or not (
            decision.action is None or isinstance(decision.action, Action)
        ):
            raise EntrantError(f"decide returned {quote(decision)}, not a pil.learner.Decision")
        return decision

    def choose(self, state: Any) -> Action:
        """The agent's next action in ``state``, checked."""
        action = self._limit.call("choose", self._agent.choose, state)
        if not isinstance(action, Action):
            raise EntrantError(f"choose returned {quote(action)}, not a pil.types.Action")
        return action

    def feedback(self, *args: Any) -> None:
        """The person's verdict, told to the agent."""
        self._limit.call("feedback", self._agent.feedback, *args)

    def correct(self, *args: Any) -> Any:
        """The agent's correction of an invalid state."""
        return self._limit.call("correct", self._agent.correct, *args)

    def save(self, *args: Any) -> Any:
        """The agent's table saved."""
        return self._limit.call("save", self._agent.save, *args)

    def __getattr__(self, name: str) -> Any:
        if name.startswith("_"):
            raise AttributeError(name)
        found = getattr(self._agent, name)
        if not callable(found):
            return found
        return lambda *args: self._limit.call(name, found, *args)


def guard_factory(factory: Factory, limit: TimeLimit) -> Factory:
    """``factory`` whose agents (and whose own calls) run under ``limit``."""

    def make(seed: int) -> Any:
        made = limit.call(f"factory({seed})", factory, seed)
        if isinstance(made, Agent):
            return GuardedAgent(made, limit)
        if callable(getattr(made, "select_action", None)) and callable(
            getattr(made, "observe", None)
        ):
            return GuardedActor(made, limit)
        return made  # neither: as_agent says what it is not

    return make


def check_factory(factory: Factory, where: str, seconds: float = DECISION_TIMEOUT) -> None:
    """Build one agent of ``factory`` (before any run), under the limit, so that a broken
    entrant fails at once: :class:`EntrantError` naming ``where`` and what it did."""
    with TimeLimit(seconds) as limit:
        try:
            made = guard_factory(factory, limit)(0)
        except EntrantError as error:
            raise EntrantError(f"{where}: {error}") from None
        as_agent(made, 0, where)
