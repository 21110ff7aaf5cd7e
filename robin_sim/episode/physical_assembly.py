"""The physical run: :func:`pil.task.assemble.assemble` in MuJoCo, with a body and eyes.

:func:`assemble_physical` builds the world of the scenario's layout, the person's
body in it (:class:`~robin_sim.person.body.PhysicalBody`, seeded by the run's sub-seeds) and
hands them to the learner side's assembly with the detector registry extended by ``vision``
(Robin's eye cameras, :class:`~robin_sim.vision.detector.VisionDetector`) — an entry like the
others. The world's layout is the scenario's (:func:`layout_of`). The
episode, a physical sweep run and a live session are assembled here::

    spec = EpisodeConfig(scenario="one_handover", video=False).spec()
    run = assemble_physical(spec)                      # run.world: a PhysicalWorld
"""

from __future__ import annotations

from collections.abc import MutableMapping
from typing import TYPE_CHECKING, Any

from pil.task.assemble import DETECTORS, DetectorContext, DetectorFactory, Run
from pil.task.assemble import assemble as assemble_learner
from pil.task.detector import CAMERAS as VISION
from pil.task.detector import GestureReader
from pil.task.spec import PHYSICAL, RunSpec
from robin_sim.episode.config import EpisodeError, EpisodeSpec
from robin_sim.vision.condition_params import VisionSettings, parse_conditions

if TYPE_CHECKING:
    from pil.task.scenario import Scenario
    from robin_sim.model.scene import SceneLayout
    from robin_sim.person.body import Tempo
    from robin_sim.robot.world import PhysicalWorld
    from robin_sim.vision.classifier import GestureModel


def vision_factory(
    conditions: VisionSettings, gesture_model: GestureModel | None = None
) -> DetectorFactory:
    """The registry entry ``vision``: Robin's eye cameras under ``conditions``, reading the
    person's hand shown by their body (seeded by the phase's detector sub-seed) with
    ``gesture_model`` (None: the shipped one)."""

    def make(context: DetectorContext) -> GestureReader:
        from robin_sim.person.body import PhysicalBody
        from robin_sim.robot.world import PhysicalWorld
        from robin_sim.vision.detector import VisionDetector

        world, body = context.world, context.body
        if not isinstance(world, PhysicalWorld) or not isinstance(body, PhysicalBody):
            raise EpisodeError("the eye cameras read a person's body in a physical world")
        return VisionDetector(  # type: ignore[return-value]  # its rate is a description
            world.sim,
            display=body.display,
            lighting=conditions.lighting,
            camera_noise=conditions.camera_noise,
            seed=context.seed,
            skin=conditions.skin,
            pose_jitter=conditions.pose_jitter,
            adapt=conditions.adapt,
            discarded_thumb=conditions.discarded_thumb,
            gesture_model=gesture_model,
        )

    return make


def assemble_physical(
    spec: RunSpec | EpisodeSpec,
    *,
    world: PhysicalWorld | None = None,
    cache: MutableMapping[Any, Any] | None = None,
    tempo: Tempo | None = None,
    gesture_model: GestureModel | None = None,
) -> Run:
    """The run of ``spec``: a learner-only one as :func:`pil.task.assemble.assemble`; a
    physical one in ``world`` (default: a new world of the scenario's layout) with the person's
    body and, for ``detector=vision``, the eye cameras (default conditions for a bare
    :class:`RunSpec`, read with ``gesture_model``, default the shipped one); ``tempo``: how
    fast the body signs (default: the scripted person's)."""
    conditions = spec.conditions if isinstance(spec, EpisodeSpec) else None
    run_spec = spec.run if isinstance(spec, EpisodeSpec) else spec
    if run_spec.world != PHYSICAL:
        return assemble_learner(run_spec, cache=cache)
    from robin_sim.person.body import SCRIPTED, PhysicalBody
    from robin_sim.robot.world import PhysicalWorld

    if world is None:
        world = PhysicalWorld(layout_of(run_spec.scenario))
    body = PhysicalBody(world, seed=run_spec.seeds.body, tempo=tempo or SCRIPTED)
    settings = conditions or parse_conditions({})
    detectors = {**DETECTORS, VISION: vision_factory(settings, gesture_model)}
    return assemble_learner(run_spec, world=world, body=body, detectors=detectors, cache=cache)


def layout_of(scenario: Scenario) -> SceneLayout:
    """The scene layout of ``scenario`` (its ``layout`` section, else the default), refused when
    it lacks the legs and spots the person will point at."""
    from robin_sim.model.scene import SceneLayout  # imports MuJoCo

    layout = SceneLayout.of(scenario.layout)
    if scenario.spots > len(layout.spots) or scenario.legs_per_table > len(layout.legs):
        raise EpisodeError(
            f"scenario {scenario.name!r} needs {scenario.spots} table spots and "
            f"{scenario.legs_per_table} legs per table, but its layout has "
            f"{len(layout.spots)} spots and {len(layout.legs)} legs; add them to its "
            "layout section or lower spots / legs_per_table"
        )
    return layout
