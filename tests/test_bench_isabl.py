"""I-SABL reads silence by the trainer's strategy it infers: after a punishment-focused trainer
(silent when right, thumb down when wrong) silence is approval, after a reward-focused one
(thumb up when right, silent when wrong) it is refusal; a TAMER-like learner that takes silence
as OK cannot tell them apart. EM never lowers the evidence, and the bench hands the agent the
thumbs as read, silence included."""

from __future__ import annotations

import itertools

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from pil.agents import TamerAgent
from pil.bench.isabl import ISablAgent, feedback_probabilities
from pil.bench.noise import make_reader
from pil.bench.suite import load_suite
from pil.bench.tracks import _scripts, play
from pil.task.seeds import sub_seeds
from pil.types import ACTIONS, Feedback, State
from pil.validity import ALL_STATES

STATES = list(ALL_STATES[:8])  # eight distinct states to teach in
PROBE = ALL_STATES[20]  # a state the history never touched


def _teach(agent, right: Feedback, wrong: Feedback) -> None:
    """In each of eight states two wrong actions get ``wrong``, then the right one ``right``."""
    for k, state in enumerate(STATES):
        wanted = ACTIONS[k % len(ACTIONS)]
        for action in [a for a in ACTIONS if a is not wanted][:2]:
            agent.feedback(state, action, wrong)
        agent.feedback(state, wanted, right)


def _choices(right: Feedback, wrong: Feedback, make=ISablAgent) -> list:
    """What agents taught this way choose in PROBE after one silence for ``ACTIONS[0]``."""
    out = []
    for seed in range(40):
        agent = make(seed)
        _teach(agent, right, wrong)
        agent.feedback(PROBE, ACTIONS[0], Feedback.NONE)
        out.append(agent.choose(PROBE))
    return out


def test_a_punishment_focused_trainer_s_silence_is_learnt_as_approval():
    agent = ISablAgent(0)
    _teach(agent, right=Feedback.NONE, wrong=Feedback.NOT_OK)
    mu_plus, mu_minus = agent.strategy()
    assert mu_plus > 0.6 and mu_minus < 0.3  # silent after right, speaks up after wrong
    assert set(_choices(Feedback.NONE, Feedback.NOT_OK)) == {ACTIONS[0]}  # silence: keep it
    for k, state in enumerate(STATES):  # every silent action is taken as the wanted one
        assert agent.policy[ALL_STATES.index(state)] == k % len(ACTIONS)


def test_a_reward_focused_trainer_s_silence_is_learnt_as_refusal():
    agent = ISablAgent(0)
    _teach(agent, right=Feedback.OK, wrong=Feedback.NONE)
    mu_plus, mu_minus = agent.strategy()
    assert mu_plus < 0.3 and mu_minus > 0.6
    assert ACTIONS[0] not in _choices(Feedback.OK, Feedback.NONE)  # silence: try another


def test_silence_as_ok_cannot_tell_the_two_trainers_apart():
    """The contrast: TAMER takes every silence as OK and keeps the silent action for both."""

    def tamer(seed: int) -> TamerAgent:
        return TamerAgent(seed, step_size=0.5)

    for right, wrong in ((Feedback.NONE, Feedback.NOT_OK), (Feedback.OK, Feedback.NONE)):
        assert set(_choices(right, wrong, tamer)) == {ACTIONS[0]}


def test_the_trainer_model_is_a_distribution_that_flips_with_epsilon():
    probs = feedback_probabilities(0.1, 0.3, 0.7)
    assert probs.sum(axis=1) == pytest.approx([1.0, 1.0])
    assert probs[0, 0] == pytest.approx(0.9 * 0.7) and probs[1, 0] == pytest.approx(0.1 * 0.7)
    assert probs[1, 2] == pytest.approx(0.9 * 0.7 + 0.1 * 0.3)


history = st.lists(
    st.tuples(
        st.integers(0, len(ALL_STATES) - 1),
        st.integers(0, len(ACTIONS) - 1),
        st.sampled_from([Feedback.OK, Feedback.NOT_OK, Feedback.NONE]),
    ),
    min_size=1,
    max_size=60,
)


@settings(max_examples=60, deadline=None)
@given(history, st.sampled_from([0.01, 0.1, 0.3]))
def test_em_never_lowers_the_evidence_and_acts_within_the_step(events, epsilon):
    agent = ISablAgent(3, epsilon=epsilon)
    for sid, index, kind in events:
        agent.feedback(ALL_STATES[sid], ACTIONS[index], kind)
        steps = agent.evidence[1:]  # from the first posterior on, EM is monotone
        assert all(b >= a - 1e-9 for a, b in itertools.pairwise(steps))
        assert agent.weights.sum() == pytest.approx(1.0) and (agent.weights >= 0).all()
    state: State = ALL_STATES[events[-1][0]]
    agent.restart()  # a new step: the history's refusals are not this step's
    refused = set()
    for _ in range(len(ACTIONS) - 1):  # within a step a refused action is not tried again
        action = agent.choose(state)
        assert action not in refused
        refused.add(action)
        agent.feedback(state, action, Feedback.NOT_OK)


def test_the_bench_hands_the_agent_the_thumbs_as_read():
    """Under the teacher's noise the agent counts silences; with right thumbs it sees none,
    and the same seed gives the same decisions."""
    suite = load_suite()
    seeds = sub_seeds(suite.seeds("dev")[0]).phase("test")
    script = _scripts(suite.track("assembly"), True, seeds.draw)["script"]
    silences, actions = {}, {}
    for condition in ("d80", "teacher", "teacher"):
        agent = ISablAgent(seeds.learner)
        reader = make_reader(suite.conditions[condition], seeds.detector, len(script))
        played = play(agent, script, reader, seeds.person, suite.cap, stall_after=20)
        silences[condition] = agent.counts[:, :, 2].sum()
        actions.setdefault(condition, set()).add(played.actions)
    assert silences["d80"] == 0 and silences["teacher"] > 0
    assert len(actions["teacher"]) == 1
