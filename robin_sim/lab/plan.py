"""A study participant's sessions: the practice block, then the protocol's blocks in the order
assigned, each a checked :class:`~robin_sim.live.config.LiveConfig` under the study folder.

The sessions go to ``<study>/sessions/<participant>/``: ``practice`` and ``block<N>-<condition>``.
Every block gets the study's limits and a seed derived from the study seed, the participant and
the block (:func:`pil.task.seeds.block_seed`; the practice block's from block
:data:`PRACTICE_BLOCK`), or the study seed with the protocol's ``seeds: shared``.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import replace
from pathlib import Path

from pil.experiments.study_export import SESSIONS_DIR
from pil.task.seeds import block_seed
from robin_sim.lab.study_file import Study
from robin_sim.live.config import LiveConfig
from robin_sim.live.files import block_folder

PRACTICE_FOLDER = "practice"
PRACTICE_BLOCK = 10_000  # the block number the practice block's seed derives from


def sessions_dir(study: Study) -> Path:
    """Where the study's sessions go."""
    return study.folder / SESSIONS_DIR


def participant_configs(
    study: Study, participant: str, order: Sequence[str], base: LiveConfig
) -> list[LiveConfig]:
    """``participant``'s sessions (checked), practice first; ``base`` gives the rest (speed,
    video, webcam, ...)."""
    protocol, limits = study.protocol, study.limits
    common = replace(
        base,
        participant=participant,
        scenario=protocol.scenario,
        out_root=sessions_dir(study),
        protocol=study.protocol_ref,  # as the study file names it: relative to the folder
        study_seed=study.seed,
        inactivity_seconds=limits.inactivity,
    ).checked()  # the options the participant's sessions share, checked once
    configs = []
    practice = study.practice
    if practice is not None:
        configs.append(
            common.for_block(
                system=practice.system or order[0],
                handover_types=practice.types,
                block=None,
                instructions=practice.instructions,
                session=PRACTICE_FOLDER,
                seed=block_seed(study.seed, participant, PRACTICE_BLOCK),
                practice=True,
                block_seconds=practice.limits.seconds,
                block_actions=practice.limits.actions,
            )
        )
    for block in protocol.blocks_in(order):
        shared = protocol.seeds == "shared"
        configs.append(
            common.for_block(
                system=block.condition,
                handover_types=tuple(block.handover_types),
                block=block.index,
                instructions=block.instructions,
                session=block_folder(None, block.index, block.condition),
                seed=study.seed if shared else None,  # None: derived from the study's seed
                block_seconds=limits.seconds,
                block_actions=limits.actions,
            )
        )
    return configs
