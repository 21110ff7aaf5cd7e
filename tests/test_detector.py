"""The simulated detector: exact decks, independent draws, discards, confusion matrices."""

from __future__ import annotations

import pytest

from pil.errors import RobinPilError
from pil.task.detector import Detector, DetectorError, check_confusion
from pil.task.spec import parse_run_spec
from pil.types import GESTURES, Gesture


@pytest.mark.parametrize(("rate", "size"), [(0.4, 110), (0.6, 14), (0.8, 55), (0.35, 7)])
def test_exact_model_reads_round_d_n_right_in_every_deck(rate: float, size: int) -> None:
    detector = Detector(rate, seed=5, deck_size=size, discard=0.5)
    for _ in range(3):  # three decks, refilled and reshuffled
        reads = [detector.detect(Gesture.GRASP) for _ in range(size)]
        assert sum(r is Gesture.GRASP for r in reads) == round(rate * size)


def test_exact_deck_positions_are_random_and_seeded() -> None:
    decks = {tuple(_deck(Detector(0.5, seed=s, deck_size=20))) for s in range(5)}
    assert len(decks) > 1
    assert _deck(Detector(0.5, seed=3, deck_size=20)) == _deck(Detector(0.5, seed=3, deck_size=20))


def _deck(detector: Detector) -> list[bool]:
    return [detector.correct_next() for _ in range(detector.deck_size)]


def test_independent_model_hits_the_rate_on_average() -> None:
    detector = Detector(0.7, seed=2, model="independent", discard=0.0)
    hits = sum(detector.detect(Gesture.POINTING) is Gesture.POINTING for _ in range(20000))
    assert abs(hits / 20000 - 0.7) < 0.015


@pytest.mark.parametrize("rate", [1.5, -0.1, 0, "high"])
def test_rate_outside_0_1_is_rejected(rate: object) -> None:
    """The rate is checked once, where it enters (the RATE spec); the Detector takes it as
    given."""
    with pytest.raises(RobinPilError, match=r"detection rate must be a number in \(0, 1\], got"):
        parse_run_spec(rate=rate)


def test_unknown_model_lists_choices() -> None:
    with pytest.raises(RobinPilError, match="'exact', 'independent'"):
        parse_run_spec(params={"detector": "perfect"})


def test_discards_and_misreads() -> None:
    all_discard = Detector(0.0, seed=0, deck_size=10, discard=1.0)
    assert all(all_discard.detect(Gesture.GIVE_ME) is None for _ in range(30))
    assert all_discard.discarded == 30
    never = Detector(0.0, seed=0, deck_size=10, discard=0.0)
    reads = [never.detect(Gesture.GIVE_ME) for _ in range(3000)]
    assert Gesture.GIVE_ME not in reads and None not in reads
    for other in GESTURES:  # uniform among the other three
        if other is not Gesture.GIVE_ME:
            assert abs(reads.count(other) / 3000 - 1 / 3) < 0.04
    half = Detector(0.0, seed=4, deck_size=10, discard=0.5)
    for _ in range(4000):
        half.detect(Gesture.RELEASE)
    assert abs(half.discarded / 4000 - 0.5) < 0.03


def test_confusion_matrix_steers_misreads() -> None:
    matrix = [
        [0.0, 1.0, 0.0, 0.0],  # pointing is misread as give me only
        [0.5, 0.5, 0.0, 0.0],
        [0.0, 0.0, 0.2, 0.8],
        [0.0, 0.0, 1.0, 0.0],
    ]
    detector = Detector(0.0, seed=1, deck_size=4, discard=0.0, confusion=matrix)
    assert {detector.detect(Gesture.POINTING) for _ in range(200)} == {Gesture.GIVE_ME}
    assert {detector.detect(Gesture.GIVE_ME) for _ in range(200)} == {Gesture.POINTING}


@pytest.mark.parametrize(
    ("matrix", "message"),
    [
        ([[1.0]], "4x4"),
        ([[0.5, 0.5, 0, 0]] * 3 + [[0.5, 0.6, 0, 0]], "sums to 1.1"),
        ([[1.0, 0, 0, 0], [0, 0, 1, 0], [1, 0, 0, 0], [1, 0, 0, 0]], "no off-diagonal mass"),
        ([[-0.5, 1.5, 0, 0]] + [[0, 0, 0, 1]] * 3, r"lie in \[0, 1\]"),
    ],
)
def test_bad_confusion_matrix_is_rejected(matrix: list[list[float]], message: str) -> None:
    with pytest.raises(DetectorError, match=message):
        check_confusion(matrix)


def test_bad_discard_and_deck_size_are_rejected() -> None:
    with pytest.raises(RobinPilError, match=r"'discard' must be a number in \[0, 1\], got 2.0"):
        parse_run_spec(params={"discard": 2.0})
    with pytest.raises(DetectorError, match="deck size"):
        Detector(0.5, seed=0, deck_size=0)


# --- measured:FILE -------------------------------------------------------------------------------
def _measured_file(tmp_path, rows=None, gestures=None):
    import json

    path = tmp_path / "measured.json"
    rows = rows or [
        [0.8, 0.05, 0.05, 0.0, 0.1],
        [0.1, 0.6, 0.1, 0.0, 0.2],
        [0.0, 0.0, 0.9, 0.1, 0.0],
        [0.0, 0.3, 0.0, 0.7, 0.0],
    ]
    gestures = gestures or ["pointing", "give me", "grasp", "release"]
    path.write_text(json.dumps({"gestures": gestures, "confusion": rows}))
    return path


def test_measured_detector_draws_each_reading_from_its_true_row(tmp_path) -> None:
    from pil.task.detector import MeasuredDetector, load_measured, make_detector

    errors = load_measured(str(_measured_file(tmp_path)))
    assert errors.rate == pytest.approx((0.8 + 0.6 + 0.9 + 0.7) / 4)
    detector = make_detector(f"measured:{_measured_file(tmp_path)}", 0.5, seed=3)
    assert isinstance(detector, MeasuredDetector)
    n = 20000
    reads = [detector.detect(Gesture.GIVE_ME) for _ in range(n)]
    share = {g: reads.count(g) / n for g in (*GESTURES, None)}
    # within 0.015 of the file's row (binomial sd at n = 20000 is at most 0.0035)
    for got, want in zip(share.values(), (0.1, 0.6, 0.1, 0.0, 0.2), strict=True):
        assert got == pytest.approx(want, abs=0.015)
    assert detector.discarded + detector.detected + detector.misread == n
    # rate 1 (the study's pre-training at 100 %) is perfect detection
    perfect = make_detector(f"measured:{_measured_file(tmp_path)}", 1.0, seed=3)
    assert all(perfect.detect(g) is g for g in GESTURES for _ in range(50))


def test_measured_file_problems_are_one_clear_error(tmp_path) -> None:
    from pil.task.detector import load_measured

    with pytest.raises(DetectorError, match="no such file"):
        load_measured(str(tmp_path / "missing.json"))
    bad_row = [[0.5, 0.5, 0.5, 0.0, 0.0]] * 4
    with pytest.raises(DetectorError, match="summing to 1"):
        load_measured(str(_measured_file(tmp_path, rows=bad_row)))
    with pytest.raises(DetectorError, match="name each of"):
        load_measured(str(_measured_file(tmp_path, gestures=["pointing"] * 4)))


def test_shipped_measured_file_loads() -> None:
    from importlib import resources

    from pil.task.detector import load_measured

    path = resources.files("robin_sim.vision") / "data" / "measured.json"
    errors = load_measured(str(path))
    assert 0.3 < errors.rate < 1.0
