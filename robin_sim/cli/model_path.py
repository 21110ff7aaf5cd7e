"""``robin-pil model-path``: where the MJCF files are, in a checkout or an installed package.

``python -m mujoco.viewer --mjcf "$(robin-pil model-path)"`` opens the scene either way (the
files ship inside the package: ``robin_sim/model/mjcf``).
"""

from __future__ import annotations

import argparse
from pathlib import Path

from robin_sim.model import names

MODELS: dict[str, Path] = {
    "scene": names.SCENE_XML,
    "robot": names.ROBOT_XML,
    "hand-test": names.HAND_TEST_SCENE_XML,
}


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """One optional argument: which model."""
    parser.add_argument(
        "model",
        nargs="?",
        default="scene",
        choices=tuple(MODELS),
        help="scene (the default: Robin, the table, legs and the person), robot, or hand-test",
    )


def run(args: argparse.Namespace) -> int:
    """Print the model file's absolute path."""
    print(MODELS[args.model].resolve())
    return 0
