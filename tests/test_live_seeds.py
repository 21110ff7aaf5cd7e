"""Each live block gets a seed of its own, derived from the study seed, the participant and the
block (pil.task.seeds.block_seed); a protocol's ``seeds: shared`` gives every block the study
seed. Fast: configs and protocols only, nothing is run."""

from __future__ import annotations

from pathlib import Path

import pytest

from pil.task.params import MAX_SEED
from pil.task.seeds import block_seed
from robin_sim.cli.live import session_configs
from robin_sim.cli.main import build_parser
from robin_sim.live.protocol import ProtocolError, load_protocol

PROTOCOL = Path(__file__).resolve().parents[1] / "scenarios/protocols/reactive_vs_proactive.yaml"


def configs(*argv: str) -> list:
    return session_configs(build_parser("live").parse_args(["live", *argv]))


def test_block_seeds_differ_by_participant_block_and_study_and_are_stable() -> None:
    seeds = {
        (study, who, block): block_seed(study, who, block)
        for study in (0, 1)
        for who in ("P01", "P02", "P10")
        for block in range(4)
    }
    assert len(set(seeds.values())) == len(seeds)  # no two share a sequence
    assert all(0 <= seed <= MAX_SEED for seed in seeds.values())
    assert block_seed(0, "P01", 0) == seeds[(0, "P01", 0)]  # the same three, the same seed


def test_a_protocols_blocks_are_seeded_each_their_own(tmp_path: Path) -> None:
    blocks = configs("--protocol", "reactive_vs_proactive", "--participant", "P02", "--seed", "7")
    assert len(blocks) == 4
    assert [c.seed for c in blocks] == [block_seed(7, "P02", k) for k in range(4)]
    assert len({c.seed for c in blocks}) == 4 and {c.study_seed for c in blocks} == {7}
    learners = {c.run_spec().seeds.phase("test").learner for c in blocks}
    assert len(learners) == 4  # and so are the learners' draws
    free = configs("--participant", "P02", "--seed", "7")  # a session without a protocol
    assert free[0].seed == block_seed(7, "P02", 0)


def test_seeds_shared_gives_every_block_the_study_seed(tmp_path: Path) -> None:
    shared = tmp_path / "shared.yaml"
    shared.write_text(PROTOCOL.read_text() + "seeds: shared\n")
    assert load_protocol(shared).seeds == "shared"
    blocks = configs("--protocol", str(shared), "--participant", "P03", "--seed", "5")
    assert {c.seed for c in blocks} == {5}


def test_an_unknown_seeding_is_refused_naming_the_choices(tmp_path: Path) -> None:
    bad = tmp_path / "bad.yaml"
    bad.write_text(PROTOCOL.read_text() + "seeds: sometimes\n")
    refused = r"seeds: unknown seeding 'sometimes'.*per-block, shared"
    with pytest.raises(ProtocolError, match=refused):
        load_protocol(bad)
    with pytest.raises(Exception, match="--seed"):
        configs("--seed", "-1")


def test_a_session_without_a_participant_is_seeded_as_the_one_it_records() -> None:
    """No --participant: the session records P01, and its seed derives from P01 (it derived
    from the text "None" before)."""
    (config,) = configs("--seed", "7")
    assert config.participant == "P01" and config.seed == block_seed(7, "P01", 0)
