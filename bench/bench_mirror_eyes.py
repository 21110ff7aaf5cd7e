"""How Robin's eyes read the mirrored hand: the footage's readings through the live mirror.

Each stored tracker reading of the real footage (``tests/data/hands/landmarks.npz``) is applied
(``tests/mirror_looks.py``, which ``tests/test_mirror_looks.py`` also uses) to the articulated
person's hand by :class:`robin_sim.live.mirror.HandMirror` in a fresh scene
(Robin at home, the scripted body present as in a live session, the hand raised from rest to
where signs are read once the mirror drives it, :mod:`robin_sim.live.show_hand`), then both
eyes look at the palm and the shipped eye-camera model reads it
(:class:`robin_sim.live.eye_watch.EyeWatch`, the session's own reader). Prints a table per
footage sequence: readings, the share read as the sequence's gesture, and the classes
read. ``python bench/bench_mirror_eyes.py [--every N] [--at-palm]`` (every Nth reading;
default 1; ``--smoke``: every 15th; ``--at-palm``: the body first holds the palm out at the
handover point, as after a give me, and the readings are applied there).
"""

from __future__ import annotations

import argparse
import sys
from collections import Counter
from pathlib import Path

from robin_sim.render.gl_backend import ensure_gl_backend

ensure_gl_backend()  # before mujoco is imported

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests"))
import smoke  # noqa: E402  (bench/smoke.py: --smoke)
from mirror_looks import MEANT, mirror_looks  # noqa: E402


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--every", type=int, default=1)
    parser.add_argument("--at-palm", action="store_true", help="the palm held out first")
    args = smoke.parse_args(parser, every=15)
    looks = mirror_looks(args.every, args.at_palm)
    print("| sequence | readings | read as meant | classes read |")
    print("|---|---|---|---|")
    for sequence, meant in MEANT.items():
        labels = looks[sequence]
        share = sum(label == meant for label in labels) / max(len(labels), 1)
        counts = ", ".join(f"{k} {v}" for k, v in Counter(labels).most_common())
        print(f"| {sequence} ({meant}) | {len(labels)} | {share:.2f} | {counts} |")


if __name__ == "__main__":
    main()
