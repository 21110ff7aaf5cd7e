"""The walk of a run's config down the layers, measured (issue 18).

:func:`walk_episode` runs ``robin-pil episode`` from its command line through the assembly of
the run (the world, the person's body, the learner, the detector) and stops when the assembly
returns, before the step loop. Meanwhile a profile hook (``sys.setprofile``) sees every call
between the project's modules (``pil.*``, ``robin_sim.*``; the standard library and MuJoCo are
left out). :class:`Walk` counts, over the calls that go from one module into another (with
``data``: only the calls that take the config or a part of it, :data:`CONFIG_TYPES`, as an
argument: the config followed as data):

* ``stops``: such calls; ``modules``: the distinct modules entered;
* ``returns``: calls into a module that was entered before and left (none of its frames on the
  stack), the walk coming back to a module it had left;
* ``climbs``: calls from a lower layer into a higher one (:data:`LAYERS`).

``python tests/config_walk.py`` prints the figures and the returns.
"""

from __future__ import annotations

import sys
from collections.abc import Sequence
from dataclasses import dataclass, field
from pathlib import Path
from types import FrameType
from typing import Any

# the layers, top (0) to bottom: a module's layer is that of its longest matching prefix
LAYERS: dict[str, int] = {
    "robin_sim.cli": 0,
    "robin_sim.episode": 1,
    "robin_sim.live": 1,
    "robin_sim.robot": 2,
    "robin_sim.person": 2,
    "robin_sim.vision": 2,
    "robin_sim.render": 2,
    "robin_sim.model": 3,
    "robin_sim.control": 3,
    "robin_sim": 3,
    "pil.experiments": 4,
    "pil.env": 4,
    "pil.task": 5,
    "pil.agents": 6,
    "pil": 7,
}


def config_types() -> tuple[type, ...]:
    """The types the episode's config is made of, from the command line to the typed spec."""
    import argparse

    from pil.task.scenario import Scenario
    from pil.task.spec import DetectorSettings, LearnerSettings, PersonSettings, RunSpec
    from robin_sim.episode.config import EpisodeConfig, EpisodeSpec, VideoSpec
    from robin_sim.vision.condition_params import VisionSettings

    return (
        argparse.Namespace,
        EpisodeConfig,
        EpisodeSpec,
        VideoSpec,
        RunSpec,
        LearnerSettings,
        PersonSettings,
        DetectorSettings,
        Scenario,
        VisionSettings,
    )


def _takes(frame: FrameType, kinds: tuple[type, ...], methods: bool) -> bool:
    """Whether the called function's arguments include one of ``kinds`` (``methods`` False:
    a method of the config's own objects, reading it, is not counted for its ``self``)."""
    code = frame.f_code
    count = code.co_argcount + code.co_kwonlyargcount
    names = code.co_varnames[:count]
    if not methods:
        names = tuple(name for name in names if name != "self")
    return any(isinstance(frame.f_locals.get(name), kinds) for name in names)


def layer_of(module: str) -> int:
    """The layer of ``module`` (:data:`LAYERS`)."""
    best = max((p for p in LAYERS if module == p or module.startswith(p + ".")), key=len)
    return LAYERS[best]


def _project(module: str) -> bool:
    return module.split(".")[0] in ("pil", "robin_sim")


@dataclass
class Walk:
    """The calls between the project's modules, in order (caller, callee)."""

    crossings: list[tuple[str, str]] = field(default_factory=list)
    returns: list[tuple[str, str]] = field(default_factory=list)
    climbs: list[tuple[str, str]] = field(default_factory=list)
    entered: set[str] = field(default_factory=set)
    data: tuple[type, ...] = ()  # only calls taking one of these (empty: every call)
    methods: bool = True  # count the config objects' own methods (reading the config)
    _stack: list[str] = field(default_factory=list)

    def hook(self, frame: FrameType, event: str, arg: Any) -> None:
        """``sys.setprofile``'s hook: Python calls and returns only."""
        if event == "call":
            module = frame.f_globals.get("__name__", "")
            if not _project(module):
                return
            caller = self._stack[-1] if self._stack else None
            counted = not self.data or _takes(frame, self.data, self.methods)
            if counted and caller is not None and caller != module:
                self.crossings.append((caller, module))
                if module in self.entered and module not in self._stack:
                    self.returns.append((caller, module))
                if layer_of(caller) > layer_of(module):
                    self.climbs.append((caller, module))
            if counted:
                self.entered.add(module)
            self._stack.append(module)
        elif event == "return" and self._stack and _project(frame.f_globals.get("__name__", "")):
            self._stack.pop()

    def figures(self) -> dict[str, int]:
        """stops, modules, returns, climbs; and the distinct edges (caller -> callee) of each
        (a loop over a scenario's types calls the same helper many times: one edge)."""
        return {
            "stops": len(self.crossings),
            "modules": len(self.entered),
            "returns": len(self.returns),
            "climbs": len(self.climbs),
            "edges": len(set(self.crossings)),
            "return_edges": len(set(self.returns)),
            "climb_edges": len(set(self.climbs)),
        }


class _AssemblyDone(BaseException):
    """Raised when the run is assembled: the walk ends before the step loop."""


def walk_episode(argv: Sequence[str], *, data: bool = True, methods: bool = True) -> Walk:
    """The walk of ``robin-pil episode ARGV`` from the command line to the assembled run
    (``data``: the config followed as data, else every call between modules; ``methods``
    False: the config objects' own methods, reading them, are not stops)."""
    import robin_sim.episode.run as episode_run
    from robin_sim.cli.main import main

    real = episode_run.assemble_physical
    walk = Walk(data=config_types() if data else (), methods=methods)

    def assembled(*args: Any, **kwargs: Any) -> Any:
        real(*args, **kwargs)
        sys.setprofile(None)
        raise _AssemblyDone

    episode_run.assemble_physical = assembled  # type: ignore[assignment]
    try:
        sys.setprofile(walk.hook)
        main(["episode", *argv])
    except _AssemblyDone:
        pass
    finally:
        sys.setprofile(None)
        episode_run.assemble_physical = real  # type: ignore[assignment]
    return walk


ARGV = ("--no-video", "--no-progress", "--scenario", "one_handover", "--out")

if __name__ == "__main__":
    import tempfile

    with tempfile.TemporaryDirectory() as folder:
        every = walk_episode([*ARGV, str(Path(folder) / "every")], data=False)
        handed = walk_episode([*ARGV, str(Path(folder) / "handed")], methods=False)
        found = walk_episode([*ARGV, str(Path(folder) / "out")])
    print("every call:", every.figures())
    print("the config handed on (its own methods left out):", handed.figures())
    print("the config as data:", found.figures())
    for caller, module in dict.fromkeys(found.crossings):
        print("stop  ", caller, "->", module)
    for caller, module in dict.fromkeys(found.returns):
        print("return", caller, "->", module)
    for caller, module in found.climbs:
        print("climb ", caller, "->", module)
