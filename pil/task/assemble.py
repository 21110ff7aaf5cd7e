"""One function builds every run: :func:`assemble` (learner, person, detector, world).

The study, a sweep's run, the physical episode and a live session all get their pieces here
(``robin_sim.assemble_physical`` adds the physical world, the person's body and the eye cameras'
detector, then calls this). A system pre-trained (c1-c4, :mod:`pil.task.systems`) starts
from the table of a learner-only training run (:func:`training`); the sub-seeds come from
:attr:`pil.task.spec.RunSpec.seeds`. The detector is found in a registry (:data:`DETECTORS`):
a name (or ``measured:FILE``) -> a factory, which ``robin_sim`` extends with ``vision``::

    run = assemble(parse_run_spec(system="c1", rate=0.6, seed=3))
    stats = run.run()                         # learner-only: the symbolic world
"""

from __future__ import annotations

from collections.abc import Callable, Iterator, Mapping, MutableMapping, Sequence
from dataclasses import asdict, dataclass, replace
from typing import Any, TypeVar

from pil.agents import AGENTS
from pil.errors import InvalidChoiceError, RobinPilError
from pil.learner import Learner
from pil.robust import RobustLearner
from pil.step_memory import step_memory_on
from pil.table import AssociationTable
from pil.task.counting import RunStats
from pil.task.detector import EXACT, INDEPENDENT, MEASURED_PREFIX, GestureReader, make_detector
from pil.task.person import PersonBody, ScriptedPerson
from pil.task.records import StepRecord
from pil.task.runner import ASK_AFTER_REPEATS, StepObserver, steps
from pil.task.scenario import Scenario
from pil.task.script import ScriptStep, plan_script
from pil.task.seeds import PHASES, PhaseSeeds
from pil.task.spec import SYMBOLIC, RunSpec
from pil.task.watching import ReactionTime
from pil.task.world import SymbolicWorld, World

T = TypeVar("T")
MEASURED = "measured"  # the registry's key of every measured:FILE detector


@dataclass(frozen=True, slots=True)
class Training:
    """The outcome of a pre-training run: the learnt table and what it cost."""

    table: AssociationTable
    stats: RunStats


@dataclass(frozen=True, slots=True)
class LoopOptions:
    """The step loop's options (:func:`pil.task.runner.steps`)."""

    manual: bool  # the person repeats a misread gesture (no correction)
    repeat_discarded: bool  # a discarded gesture is repeated
    max_actions_per_gesture: int
    ask_after: int = ASK_AFTER_REPEATS  # repeat requests in a row before the robot proposes


@dataclass(frozen=True, slots=True)
class DetectorContext:
    """What a detector factory may use: the spec, the phase's detector seed and rate, the
    script's length (the exact dice's deck), the world and the person's body."""

    spec: RunSpec
    rate: float
    seed: int
    deck_size: int
    world: World
    body: PersonBody | None


DetectorFactory = Callable[[DetectorContext], GestureReader]


def _dice(context: DetectorContext) -> GestureReader:
    """The study's detectors: exact / independent dice, or a measured confusion file."""
    settings = context.spec.detector
    return make_detector(
        settings.model,
        context.rate,
        context.seed,
        deck_size=context.deck_size,
        discard=settings.discard,
        confusion=settings.confusion,
    )


DETECTORS: dict[str, DetectorFactory] = {EXACT: _dice, INDEPENDENT: _dice, MEASURED: _dice}


def detector_key(model: str) -> str:
    """The registry key of a detector name (``measured:FILE`` -> ``measured``)."""
    return MEASURED if model.startswith(MEASURED_PREFIX) else model


@dataclass(frozen=True, slots=True)
class Run:
    """One assembled run: drive it with :meth:`steps` (or :meth:`run` to count it)."""

    learner: Learner
    person: ScriptedPerson
    detector: GestureReader
    loop: LoopOptions
    world: World
    spec: RunSpec | None = None
    training: Training | None = None

    @property
    def options(self) -> dict[str, Any]:
        """The loop's keyword options of :func:`pil.task.runner.steps`."""
        return asdict(self.loop)

    def steps(self, observer: StepObserver | None = None) -> Iterator[StepRecord]:
        """The step loop of this run (:func:`pil.task.runner.steps`)."""
        return steps(
            self.learner, self.person, self.detector, self.world, observer=observer, **self.options
        )

    def run(self) -> RunStats:
        """Run the loop to the end and count it."""
        stats = RunStats.for_script(self.person.script)
        for record in self.steps():
            stats.add(record)
        return stats


def cached(cache: MutableMapping[Any, Any] | None, key: Any, make: Callable[[], T]) -> T:
    """``cache[key]``, made by ``make()`` and kept the first time; without a cache, ``make()``."""
    if cache is None:
        return make()
    if key not in cache:
        cache[key] = make()
    return cache[key]


def script_of(
    scenario: Scenario,
    phase: str,
    seeds: PhaseSeeds,
    cache: MutableMapping[Any, Any] | None = None,
) -> tuple[ScriptStep, ...]:
    """The person's script for the training or the test tables (seeded handover order)."""

    def plan() -> tuple[ScriptStep, ...]:
        tables = scenario.training_tables if phase == "train" else scenario.tables
        types = scenario.draw_types(tables * scenario.legs_per_table, seeds.draw)
        return plan_script(types, scenario.legs_per_table, scenario.spots)

    return cached(cache, ("script", phase, seeds.draw), plan)


def assemble(
    spec: RunSpec,
    *,
    phase: str = "test",
    world: World | None = None,
    body: PersonBody | None = None,
    detectors: Mapping[str, DetectorFactory] = DETECTORS,
    cache: MutableMapping[Any, Any] | None = None,
    training: Training | None = None,
    table: AssociationTable | None = None,
    seeds: PhaseSeeds | None = None,
    script: Sequence[ScriptStep] | None = None,
) -> Run:
    """The ``phase`` run of ``spec``: by default its test run, its system's learner (its agent,
    pre-trained for c1-c4, its own parameters applied), the scripted person (with ``body`` in
    a physical world), the detector of ``detectors`` and ``world`` (default: the symbolic
    world; a physical one is ``robin_sim.assemble_physical``'s); ``phase="train"``: the pre-training
    run (a PIL learner with correction, the spec as it is, on the training tables).

    ``cache`` (a dict) lets a study reuse what the systems of one repetition share (training
    runs, scripts): share it only between specs that differ in system and rate. ``training``
    defaults to :func:`pretraining`'s; ``table``: start the test run from it instead (used as
    it is: a transferred table); ``seeds``: the phase's sub-seeds (default: the spec's);
    ``script``: the person's (default: the scenario's, drawn by the phase's seed; e.g. a
    changed mapping's, or the people's taking turns).
    """
    if world is None:
        if spec.world != SYMBOLIC:
            raise RobinPilError(f"a {spec.world} run is assembled by robin_sim.assemble_physical")
        world = SymbolicWorld()
    if phase not in PHASES:
        raise InvalidChoiceError("phase", phase, PHASES)
    pieces = (world, body, detectors, cache, script)
    if phase == "train":
        return _phase(spec, "train", seeds, None, False, *pieces)
    if table is None:
        if training is None:
            training = pretraining(spec, cache)
        table = None if training is None else training.table.copy()
    system = spec.system_spec
    tested = spec.effective()  # the system's own parameters applied
    run = replace(_phase(tested, "test", seeds, table, system.manual, *pieces), training=training)
    if system.agent == "pil":
        return run
    agent_seed = (spec.seeds.phase("test") if seeds is None else seeds).learner
    agent = AGENTS[system.agent](agent_seed, table, tested.learner)
    return replace(run, learner=agent)  # type: ignore[arg-type]


def training_spec(spec: RunSpec) -> RunSpec | None:
    """The spec of the pre-training ``spec``'s system starts from (None when from scratch):
    a learner-only PIL run at the test rate (c1, c3) or at 100 % (c2, c4); its "train" phase
    is the run. A detector only a physical run has (the eye cameras) is not there: the
    training reads with the exact dice at the same rate."""
    trained_at = spec.system_spec.trained_at
    if trained_at is None:
        return None
    rate = spec.rate if trained_at == "d" else 1.0
    model = spec.detector.model
    learner_only = model if detector_key(model) in DETECTORS else EXACT
    return replace(
        spec, rate=rate, detector=replace(spec.detector, model=learner_only), world=SYMBOLIC
    )


def pretraining(spec: RunSpec, cache: MutableMapping[Any, Any] | None = None) -> Training | None:
    """The pre-training ``spec``'s system starts from (None when from scratch), from ``cache``
    if there: the "train" phase of :func:`training_spec` (with correction, on the training
    tables)."""
    trained = training_spec(spec)
    if trained is None:
        return None
    rate = trained.rate

    def train() -> Training:
        run = assemble(trained, phase="train", cache=cache)
        return Training(run.learner.table, run.run())

    return cached(cache, ("training", rate, spec.seed), train)


def _phase(
    spec: RunSpec,
    phase: str,
    seeds: PhaseSeeds | None,
    table: AssociationTable | None,
    manual: bool,
    world: World,
    body: PersonBody | None,
    detectors: Mapping[str, DetectorFactory],
    cache: MutableMapping[Any, Any] | None,
    script: Sequence[ScriptStep] | None,
) -> Run:
    """A PIL learner, the scripted person and the detector for ``phase`` of ``spec`` as it is
    (no system parameters applied) on ``world``; ``table`` used as it is (not copied)."""
    seeds = spec.seeds.phase(phase) if seeds is None else seeds
    script = script_of(spec.scenario, phase, seeds, cache) if script is None else tuple(script)
    mind = spec.person
    person = ScriptedPerson(
        script,
        seeds.person,
        silent_ok=mind.silent_ok,
        patience=mind.patience,
        take_back=mind.take_back,
        take_back_delay=mind.take_back_delay,
        reaction_time=ReactionTime(mind.reaction_time, mind.reaction_spread),
        body=body,
    )
    key = detector_key(spec.detector.model)
    if key not in detectors:
        raise InvalidChoiceError("detector", spec.detector.model, detectors)
    context = DetectorContext(spec, spec.rate, seeds.detector, max(1, len(script)), world, body)
    detector = detectors[key](context)
    settings = spec.learner
    # the robust PIL rule (pil.robust) has its own feedback weighing: no exploration rule
    kind: type[Learner] = RobustLearner if settings.learner == "robust" else Learner
    rule = (
        {}
        if kind is RobustLearner
        else {
            "exploration": settings.exploration,
            "adaptation": settings.adaptation,
        }
    )
    learner = kind(
        seeds.learner,
        table=table,
        correction=not manual,
        proactive=settings.proactive,
        proactive_threshold=settings.proactive_threshold,
        proactive_min_count=settings.proactive_min_count,
        step_memory=step_memory_on(settings.step_memory, kind.STEP_MEMORY_OWN),
        **rule,
    )
    loop = LoopOptions(
        manual=manual,
        repeat_discarded=spec.detector.repeat_discarded,
        max_actions_per_gesture=settings.max_actions_per_gesture,
    )
    return Run(learner, person, detector, loop, world, spec)
