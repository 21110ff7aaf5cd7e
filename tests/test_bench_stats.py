"""The benchmark's noise models and statistics do what docs/bench.md says: bursty readings
are correlated and hit their stationary rate, the teacher's noise has its rates, the measured
thumbs their confusion, Holm equals statsmodels', TOST and the mixed model find what is there,
the reference agents learn, and tuning extends a grid whose optimum sits on its edge."""

from __future__ import annotations

import json
import math
import random
import statistics

import numpy as np
import pytest

from pil.bench.agents import PolicyShapingAgent
from pil.bench.equivalence import tost_paired
from pil.bench.mixed import agent_effect
from pil.bench.noise import FeedbackChannel, MarkovReader
from pil.bench.suite import Axis, SuiteError, load_suite
from pil.bench.tuning import _extend, check_block, where_optimum
from pil.experiments.stats import holm
from pil.types import Feedback, Gesture


def test_bursty_readings_are_correlated_and_hit_the_stationary_rate():
    params = {"good": 0.95, "bad": 0.30, "enter_bad": 0.05, "leave_bad": 0.20}
    reader = MarkovReader(params, seed=3)
    right = [reader.detect(Gesture.POINTING) is Gesture.POINTING for _ in range(40_000)]
    assert reader.rate == pytest.approx(0.8 * 0.95 + 0.2 * 0.30)
    assert statistics.fmean(right) == pytest.approx(reader.rate, abs=0.01)
    errors = np.array([not r for r in right], dtype=float)
    lag1 = np.corrcoef(errors[:-1], errors[1:])[0, 1]
    assert lag1 > 0.15  # bursts: an error makes the next one likelier (independent: ~0)
    reader.set_person(1)  # a second person starts in the good state, with a chain of their own
    assert reader._bad.get(1) is None


class _Thumbs:
    rate = 1.0

    def detect(self, gesture):
        return gesture

    def read_feedback(self, feedback):
        return feedback


def test_the_teacher_noise_has_its_rates():
    channel = FeedbackChannel(_Thumbs(), {"silence": 0.3, "misread": 0.05}, seed=1)
    got = [channel.read_feedback(Feedback.NOT_OK) for _ in range(20_000)]
    assert got.count(Feedback.NONE) / len(got) == pytest.approx(0.30, abs=0.015)
    assert got.count(Feedback.OK) / len(got) == pytest.approx(0.7 * 0.05, abs=0.006)
    late = FeedbackChannel(_Thumbs(), {"late": 1.0}, seed=1)
    # a late thumb is silence now and lands on the next action instead of its own
    assert late.read_feedback(Feedback.NOT_OK) is Feedback.NONE
    assert late.read_feedback(Feedback.OK) is Feedback.NOT_OK


def test_measured_thumbs_follow_the_eye_cameras_confusion():
    suite = load_suite()
    path = suite.conditions["eyes"].feedback["measured"]
    with open(path, encoding="utf-8") as handle:
        data = json.load(handle)
    row = data["feedback_confusion"][data["feedback"].index("not OK")]
    channel = FeedbackChannel(_Thumbs(), {"measured": path}, seed=2)
    got = [channel.read_feedback(Feedback.NOT_OK) for _ in range(20_000)]
    assert got.count(Feedback.OK) / len(got) == pytest.approx(row[0], abs=0.006)
    assert got.count(Feedback.NONE) / len(got) == pytest.approx(row[2], abs=0.008)
    # the stop of a wrong action passes through the same confusion
    stops = [channel.read_stop() for _ in range(5000)]
    channel.read_feedback(Feedback.NOT_OK)
    assert Feedback.NONE in stops and stops.count(Feedback.NOT_OK) / 5000 > 0.8


def test_holm_equals_statsmodels():
    from statsmodels.stats.multitest import multipletests

    rng = random.Random(0)
    ps = [rng.random() ** 3 for _ in range(15)]  # one call: statsmodels' is slow
    assert np.allclose(holm(ps), multipletests(ps, method="holm")[1], atol=1e-12)
    # by hand: sorted .005 x 4, .01 x 3, .03 x 2, .04 x 1, each at least the one before
    assert holm([0.01, 0.04, 0.03, 0.005]) == pytest.approx([0.03, 0.06, 0.06, 0.02])
    assert math.isnan(holm([0.01, math.nan])[1]) and holm([0.01, math.nan])[0] == 0.01


def test_tost_finds_equivalence_only_inside_the_margin():
    rng = np.random.default_rng(4)
    base = rng.normal(300, 30, 40)
    close = base + rng.normal(0.5, 2.0, 40)
    far = base + rng.normal(8.0, 2.0, 40)
    assert tost_paired(close, base, 5.0)["tost_p"] < 0.01
    assert tost_paired(far, base, 5.0)["tost_p"] > 0.5
    assert tost_paired(far, base, 5.0)["noninferior_p"] > 0.5
    assert tost_paired(base - 8.0, base, 5.0)["noninferior_p"] == 0.0  # constant: certain


def test_the_mixed_model_recovers_an_agent_effect():
    rng = np.random.default_rng(5)
    rows = []
    for seed in range(12):
        level = rng.normal(0, 20)  # the seed's random intercept, shared by both agents
        for k, condition in enumerate(("d40", "d80")):
            for agent, shift in (("x", -6.0), ("a", 0.0)):
                y = 300 - 40 * k + level + shift + rng.normal(0, 2)
                rows.append({"agent": agent, "condition": condition, "seed": seed, "y": y})
    fit = agent_effect(rows, "x", "a", "y")
    assert fit["ci_low"] < -6.0 < fit["ci_high"] and fit["p"] < 0.001
    assert "fewer" in agent_effect(rows[:8], "x", "a", "y")["note"]


def test_policy_shaping_turns_consistent_feedback_into_certainty():
    agent = PolicyShapingAgent(0, consistency=0.8)
    assert agent.optimal(0, 1) == 0.5
    agent._learn(0, 1, 1.0)
    agent._learn(0, 1, 1.0)
    agent._learn(0, 2, -1.0)
    assert agent.optimal(0, 1) == pytest.approx(0.64 / (0.64 + 0.04))
    assert agent.optimal(0, 2) == pytest.approx(0.2)


def test_tuning_extends_past_an_edge_and_stops_at_a_bound():
    log = Axis("step", (0.1, 0.5, 1.0), (0.0, 1.0), "log")
    assert _extend(log, [0.1, 0.5, 1.0], 0.1) == 0.05  # halved below the low edge
    assert _extend(log, [0.1, 0.5, 1.0], 1.0) is None  # the hard bound: nothing beyond
    assert where_optimum(log, [0.1, 0.5, 1.0], 1.0) == "at bound"
    linear = Axis("eps", (0.0, 0.1, 0.2), (0.0, 1.0), "linear")
    assert _extend(linear, [0.0, 0.1, 0.2], 0.2) == pytest.approx(0.3)
    assert where_optimum(linear, [0.0, 0.1, 0.2, 0.3], 0.2) == "inside"
    with pytest.raises(SuiteError, match="frozen"):
        check_block("eval")


def test_the_seed_blocks_are_disjoint_and_fixed():
    suite = load_suite()
    dev, evaluation = suite.seeds("dev"), suite.seeds("eval")
    assert not set(dev) & set(evaluation)
    assert suite.seeds("dev", quick=True) == dev[: suite.quick_count]
    assert len(evaluation) == suite.counts["eval"] and evaluation == load_suite().seeds("eval")
