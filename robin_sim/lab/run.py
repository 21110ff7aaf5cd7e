"""One participant's run of a study (``robin-pil live --study DIR``): registered, assigned,
planned, and everything that happens written to the registry and the study's log.

:func:`prepare` loads the study, takes the next id (or checks the one given: never one in the
registry), assigns its group and condition order (:mod:`robin_sim.lab.assignment`), builds its
sessions (:mod:`robin_sim.lab.plan`) and registers it, all under the registry's lock and only
when every check has passed. :meth:`StudyRun.journal` is the live run's journal
(:attr:`robin_sim.live.conductor.Conductor.journal`): each event goes to the study's log, and
the registry follows (``running`` at consent or the first block, ``declined``, and at the end
``completed`` or ``unfinished``).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from pil.errors import RobinPilError, quote
from robin_sim.lab.assignment import assign
from robin_sim.lab.plan import participant_configs, sessions_dir
from robin_sim.lab.registry import Registry, RegistryError, check_new, next_number, utc_now
from robin_sim.lab.study_file import Study, load_study
from robin_sim.lab.study_log import StudyLog
from robin_sim.live.config import NAME_PATTERN, LiveConfig

# how a run that reached its end ended (else it is unfinished)
COMPLETE_OUTCOMES = ("finished", "ended", "capped")


@dataclass
class StudyRun:
    """A registered participant's run (see the module doc)."""

    study: Study
    participant: str
    group: str
    order: tuple[str, ...]
    configs: list[LiveConfig]
    registry: Registry
    log: StudyLog
    ended_blocks: int = 0
    sessions: list[str] = field(default_factory=list)

    def journal(self, kind: str, fields: dict[str, Any]) -> None:
        """One event of the live run: logged, and the registry updated."""
        entry = self.log.write(self.participant, kind, **fields)
        if kind == "consent":
            agreed = fields.get("value") == "agree"
            self.registry.update(
                self.participant,
                status="running" if agreed else "declined",
                **({"started_utc": entry["utc"]} if agreed else {"ended_utc": entry["utc"]}),
            )
        elif kind == "block_started":
            self.sessions.append(entry["session"])
            changes: dict[str, Any] = {"sessions": list(self.sessions)}
            if self.registry.entry(self.participant)["status"] == "assigned":
                changes.update(status="running", started_utc=entry["utc"])
            self.registry.update(self.participant, **changes)
        elif kind == "block_ended":
            self.ended_blocks += 1
        elif kind == "run_over":
            self.finish(str(fields.get("outcome")), entry["utc"])

    def finish(self, outcome: str, utc: str) -> None:
        """The registry's last word on the run: completed, unfinished or declined."""
        if outcome == "declined":
            return  # set at the consent already
        done = outcome in COMPLETE_OUTCOMES and self.ended_blocks == len(self.configs)
        self.registry.update(
            self.participant,
            status="completed" if done else "unfinished",
            outcome=outcome,
            ended_utc=utc,
        )

    def release(self, why: str) -> None:
        """The run could not start (the port was taken, ...): the id, never shown to anyone,
        is taken out of the registry again, and the log says so."""
        with self.registry.changing() as entries:
            entries[:] = [e for e in entries if e["id"] != self.participant]
        self.log.write(self.participant, "released", why=why)


def prepare(folder: Path, participant: str | None, base: LiveConfig) -> StudyRun:
    """Load the study in ``folder``, register the next participant (or ``participant``) and
    plan its sessions; :class:`RobinPilError` (exit 2) before anything is registered."""
    study = load_study(folder)
    registry = Registry(study.folder, study.name)
    log = StudyLog(study.folder)
    with registry.changing() as entries:
        next_id = study.participant_id(next_number(entries, study.id_prefix))
        chosen = next_id if participant is None else study.canonical_id(_checked_id(participant))
        check_new(entries, chosen, next_id)
        folder_of = sessions_dir(study) / chosen
        if folder_of.exists():
            raise RegistryError(
                f"{folder_of} exists but {quote(chosen)} is not in the registry; an id is "
                f"never reused: leave out --participant for the next one ({next_id})"
            )
        group, order = assign(study, entries)
        configs = participant_configs(study, chosen, order, base)
        entries.append(
            {
                "id": chosen,
                "group": group,
                "order": list(order),
                "status": "assigned",
                "assigned_utc": utc_now(),
                "sessions": [],
            }
        )
    log.write(chosen, "assigned", group=group, order=list(order), seed=study.seed)
    return StudyRun(study, chosen, group, order, configs, registry, log)


def _checked_id(participant: str) -> str:
    if not isinstance(participant, str) or not NAME_PATTERN.fullmatch(participant):
        raise RobinPilError(
            f"--participant {quote(participant)} is not a valid id; use 1-32 letters, "
            "digits, '_' or '-'"
        )
    return participant


def refuse_options(given: Sequence[str]) -> None:
    """Options that a study file decides: refused with ``--study``, naming where it is set."""
    if given:
        raise RobinPilError(
            f"{', '.join(given)} with --study: the study file decides these (its protocol, "
            "seed and folder); leave them out, or edit study.yaml"
        )
