"""The eyes' fusion: one reading from the class probabilities of the eyes that found a hand."""

from __future__ import annotations

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st
from hypothesis.extra.numpy import arrays

from robin_sim.vision.reader import fuse

EYE_ROWS = arrays(
    np.float64,
    st.tuples(st.integers(1, 2), st.just(7)),
    elements=st.floats(1e-6, 1.0, allow_nan=False, allow_infinity=False),
).map(lambda a: a / a.sum(axis=1, keepdims=True))


@settings(max_examples=200, deadline=None)
@given(EYE_ROWS)
def test_a_fused_reading_is_a_distribution_and_one_eye_reads_as_itself(rows: np.ndarray) -> None:
    fused = fuse(rows)
    assert fused.shape == (7,) and np.all(fused >= 0) and np.isclose(fused.sum(), 1.0)
    if len(rows) == 1:
        np.testing.assert_allclose(fused, rows[0], rtol=1e-9, atol=1e-12)
    else:  # symmetric in the eyes, and the class both eyes favour stays first
        np.testing.assert_allclose(fused, fuse(rows[::-1]), rtol=1e-9, atol=1e-12)
        if int(np.argmax(rows[0])) == int(np.argmax(rows[1])):
            assert int(np.argmax(fused)) == int(np.argmax(rows[0]))


def test_a_class_one_eye_rules_out_stays_unlikely() -> None:
    """The mean of (0.9 A, 0.1 B) and (0.0 A, 0.5 B, 0.5 C) reads A at 0.45; the geometric mean
    takes the eye that rules A out at its word."""
    left = np.array([0.9, 0.1, 0.0, 0, 0, 0, 0]) + 1e-9
    right = np.array([1e-9, 0.5, 0.5, 0, 0, 0, 0]) + 1e-9
    fused = fuse(np.stack([left, right]))
    assert np.argmax(fused) == 1 and fused[0] < 0.01
    assert np.stack([left, right]).mean(axis=0).argmax() == 0  # the mean would read A
