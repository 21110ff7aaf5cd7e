"""The benchmark's slow track: the physical episode in MuJoCo, read by Robin's eye cameras.

:func:`run_physical_track` is a :data:`pil.bench.run.Runner`: one run of an entrant on the
``physical`` track. The episode of the track's scenario is assembled as ``robin-pil episode
--detector vision --no-video`` assembles it
(:func:`robin_sim.episode.physical_assembly.assemble_physical`: the physical world, the person's
body, the eye cameras reading every gesture and thumb), the entrant's agent takes the learner's
place, and the step loop's records are counted as on the learner-only tracks
(:func:`pil.bench.tracks.count`). No oracle runs here (regret is empty).
"""

from __future__ import annotations

from dataclasses import replace
from typing import Any

from pil.bench.entrants import Factory, as_agent
from pil.bench.suite import Suite, Track
from pil.bench.tracks import count, curve_area, curve_of


def run_physical_track(
    suite: Suite, track: Track, condition: str, seed: int, factory: Factory, quick: bool
) -> dict[str, Any]:
    """One physical run of ``factory``'s agent (module docstring)."""
    from pil.task.spec import PHYSICAL, build_run_spec
    from robin_sim.episode.physical_assembly import assemble_physical  # MuJoCo from here on

    model = suite.conditions[condition].gestures["model"]
    spec = build_run_spec(
        system="pil",
        rate=1.0,
        seed=seed,
        scenario=str(track.options.get("scenario", "one_handover")),
        values={"detector": model},
        world=PHYSICAL,
    )
    parts = assemble_physical(spec)
    learner_seed = spec.seeds.phase("test").learner
    agent = as_agent(factory(learner_seed), learner_seed, "the agent factory")
    run = replace(parts, learner=agent)  # type: ignore[arg-type]
    script = run.person.script
    played = count(run.steps(), suite.cap_of(track.name) * len(script))
    tables = 1 + max((i.intent.table for i in script), default=0)
    curve = curve_of(played, tables)
    nan = float("nan")
    return {
        "actions": nan if played.failed else played.actions,
        "gestures": nan if played.failed else played.gestures,
        "rejected": nan if played.failed else played.rejected,
        "curve": curve,
        "curve_area": nan if played.failed else curve_area(curve),
        "failed": played.failed,
        "scripted": len(script),
        "sim_time_s": round(float(getattr(run.world, "time", nan)), 3),
    }
