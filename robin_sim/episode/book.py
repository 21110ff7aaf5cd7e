"""What every physical run keeps of its steps: :class:`StepBook` (log, counts, the hand check)
and :func:`run_summary` (the summary fields) — shared by the episode and the live session."""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

from pil.task.assemble import Run
from pil.task.parts import PERSON_PARAMS
from pil.task.records import StepRecord
from pil.task.spec import RunSpec
from pil.task.systems import SYSTEMS
from pil.types import Hand, hand_after
from robin_sim.episode.config import EpisodeError
from robin_sim.episode.log import StepLog
from robin_sim.episode.render_checks import RenderChecks
from robin_sim.episode.summary import EpisodeTotals
from robin_sim.person.body import PhysicalBody
from robin_sim.robot.world import PhysicalWorld

if TYPE_CHECKING:
    from robin_sim.vision.detector import VisionDetector


def vision_of(run: Run) -> VisionDetector | None:
    """The run's detector if it reads with the eye cameras (``--detector vision``)."""
    from robin_sim.vision.detector import VisionDetector

    return run.detector if isinstance(run.detector, VisionDetector) else None


def _expected_hand(before: Hand, record: StepRecord, physical: Hand) -> Hand:
    """The hand state the learner's approved actions imply after ``record``; after an action
    that was not approved, what physics shows (a drop, a leg caught by a rejected close)."""
    if record.action is None:
        return before
    if record.feedback is None or not record.feedback.approves:
        return physical
    return hand_after(record.action, before)


class StepBook:
    """Logs and counts each step of a physical run and checks the learner's hand state against
    physics (shared by the episode and the live session)."""

    def __init__(
        self,
        run: Run,
        world: PhysicalWorld,
        log: StepLog,
        totals: EpisodeTotals,
        checks: RenderChecks | None = None,
        *,
        strict: bool = True,
    ) -> None:
        self.run, self.world, self.log, self.totals, self.checks = run, world, log, totals, checks
        self.strict = strict  # False: a mismatch is logged and physics taken as it is
        self.hand = Hand.FREE  # what the learner's approved actions imply
        self._readings = getattr(run.detector, "records", None)  # the eyes' readings, if any
        self._logged = 0

    def add(self, record: StepRecord) -> dict[str, Any]:
        """Log and count ``record``; its log entry. :class:`EpisodeError` when the learner's
        hand state and physics disagree (not ``strict``: ``hand_mismatch`` in the entry)."""
        world = self.world
        physical = world.hand()
        self.hand = _expected_hand(self.hand, record, physical)
        check = None if self.checks is None else self.checks.take()
        entry = _log_entry(record, world, check, physical)
        if physical is not self.hand and not self.strict:
            entry["hand_mismatch"] = self.hand.value  # what the approvals implied
            self.hand = physical
        if self._readings is not None:
            entry["vision"] = [reading.as_dict() for reading in self._readings[self._logged :]]
            self._logged = len(self._readings)
        self.log.write(entry)
        body = self.run.person.body
        assert isinstance(body, PhysicalBody)
        ended = world.time if world.last_result is None else world.last_result.ended
        self.totals.add(record, entry, body.performed_at[record.gesture_count - 1], ended)
        if physical is not self.hand:
            raise EpisodeError(
                f"step {record.t}: the learner's hand state is {self.hand.value} but physics "
                f"reads {physical.value} ({record.detail or 'no detail'})"
            )
        return entry


def _log_entry(
    record: StepRecord, world: PhysicalWorld, check: dict[str, Any] | None, physical: Hand
) -> dict[str, Any]:
    entry = record.to_dict()
    entry["hand_physics"] = physical.value
    entry["sim_time"] = round(world.time, 4)
    entry["leg_positions"] = [[round(float(v), 4) for v in p] for p in world.legs.positions()]
    entry["palm_position"] = [round(float(v), 4) for v in world.human.palm_centre()]
    if check is not None:
        entry["render_check"] = check
    return entry


def run_summary(
    *,
    spec: RunSpec,
    run: Run,
    totals: EpisodeTotals,
    world: PhysicalWorld,
    wall: float,
    status: str,
    error: str,
) -> dict[str, Any]:
    """The summary fields of a physical run (the episode's and the live session's)."""
    scenario = spec.scenario
    summary: dict[str, Any] = {
        "status": status,
        "error": error,
        "system": spec.system,
        "system_name": SYSTEMS[spec.system],
        "rate": spec.rate,
        "seed": spec.seed,
        "scenario": scenario.name,
        "tables": scenario.tables,
        "legs_total": scenario.tables * scenario.legs_per_table,
        **totals.as_summary(world.person_contacts.events, run.person.interventions, world.time),
        "person": {name: getattr(spec.person, name) for name in PERSON_PARAMS},
        "sim_time_s": round(world.time, 3),
        "wall_time_s": round(wall, 3),
        "real_time_factor": round(world.time / wall, 3) if wall > 0 else None,
    }
    vision = vision_of(run)
    if vision is not None:
        summary["vision"] = vision.summary()
    return summary
