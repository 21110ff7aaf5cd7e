"""Robin's eyes read the footage's hands as a live session mirrors and shows them.

Real MuJoCo physics and EGL renders of the eye cameras, the shipped eye-camera model, every
stored tracker reading of the real footage applied through the live mirror with the session's
scripted body present and the hand raised from rest (``tests/mirror_looks.py``, the same loop
as ``bench/bench_mirror_eyes.py``). The reader is deterministic (seeded), so the counts are
those of the bench; the bounds leave three looks of slack for a renderer that differs by a
few pixels.
"""

from __future__ import annotations

from robin_sim.render.gl_backend import ensure_gl_backend

ensure_gl_backend()  # before mujoco is imported

import pytest  # noqa: E402
from mirror_looks import mirror_looks  # noqa: E402

# (sequence, class): at least this many looks read as it. Measured with the shipped model:
# palm 31 of 32 give me, the palm turned up 32 of 32 release, the fist 9 of 20 grasp, the thumb
# down 24 of 27. Before the hand fit put the hand's turn back (the eyes saw the scripted
# display's turn) the same loop read 10, 10, 2 and 8; with the turn right but the hand left at
# rest by the hip, 31, 26, 2 and 23. So undoing either change fails some bound here.
AT_LEAST = {
    ("palm", "give_me"): 28,
    ("open_up", "release"): 29,
    ("fist", "grasp"): 6,
    ("thumb_down", "thumb_down"): 21,
}


@pytest.mark.slow
def test_robins_eyes_read_the_mirrored_footage_as_a_session_shows_it() -> None:
    looks = mirror_looks()
    assert {s: len(v) for s, v in looks.items()} == {
        "thumb_up": 27,
        "palm": 32,
        "fist": 20,
        "open_up": 32,
        "thumb_down": 27,
    }
    for (sequence, label), least in AT_LEAST.items():
        got = looks[sequence].count(label)
        assert got >= least, (sequence, label, got, looks[sequence])
