"""Gesture reading speed: milliseconds to read one gesture with Robin's eye cameras.

Run: ``python bench/bench_vision.py [--reads 40] [--size 112]``.
Reads the person's hand ``--reads`` times (the seven poses in turn, each a new performance,
at the handover place and beside the table) and prints the median milliseconds of each stage:
the two eye renders (RGB and depth of each eye, ``--size`` pixels square), segmentation,
features, classification and the whole reading; and, measured in the same run as a baseline,
one 640x480 front-camera video frame (no shadows). The head's look (simulated physics) is not
part of a reading's cost here: the data-set renderer aims it kinematically.
"""

from __future__ import annotations

import argparse
import statistics
import time

import smoke  # bench/smoke.py: --smoke

from robin_sim.render.gl_backend import ensure_gl_backend

ensure_gl_backend()

import numpy as np  # noqa: E402

from robin_sim.control.gaze import pose_head  # noqa: E402
from robin_sim.render.renderer import FrameRenderer  # noqa: E402
from robin_sim.vision.classifier import load_shipped  # noqa: E402
from robin_sim.vision.dataset import SampleSpec  # noqa: E402
from robin_sim.vision.eyes import EyeCameras, EyeCondition  # noqa: E402
from robin_sim.vision.features import hand_features  # noqa: E402
from robin_sim.vision.reader import looked_at_depth, regions  # noqa: E402
from robin_sim.vision.render_set import SampleRenderer  # noqa: E402

PLACES = (np.array([0.75, 0.0, 1.0]), np.array([1.0, 0.1, 0.95]))


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--reads", type=int, default=40)
    parser.add_argument("--size", type=int, default=112, help="eye image side, pixels")
    args = smoke.parse_args(parser, reads=2)
    scene = SampleRenderer()
    eyes = EyeCameras(scene.model, size=args.size)
    model = load_shipped()
    condition = EyeCondition(camera_noise=4.0)
    rng = np.random.default_rng(0)
    names = ("render", "segment", "features", "classify", "read")
    stages: dict[str, list[float]] = {k: [] for k in names}
    right = 0
    for i in range(args.reads + 3):  # the first three warm up
        label = i % 7
        spec = SampleSpec(label, PLACES[i % 2], np.zeros(3), 1.0, 1.0, 0.0, 0.0, 0.0, 0.0, i)
        scene.render(spec)  # shows the pose (with a new performance)
        target = scene.data.site("human_palm_site").xpos.copy()
        pose_head(scene.model, scene.data, target)
        t0 = time.perf_counter()
        views = eyes.render(scene.data, condition, rng)
        depths = looked_at_depth(scene.model, scene.data, target)
        t1 = time.perf_counter()
        found = regions(views, depths)
        t2 = time.perf_counter()
        rows = [
            hand_features(v.rgb, v.depth, r, v.focal)
            for v, r in zip(views, found, strict=True)
            if r
        ]
        t3 = time.perf_counter()
        p = model.probabilities(np.stack(rows)).mean(axis=0) if rows else None
        t4 = time.perf_counter()
        if i < 3:
            continue
        right += p is not None and int(np.argmax(p)) == label
        for name, dt in zip(stages, (t1 - t0, t2 - t1, t3 - t2, t4 - t3, t4 - t0), strict=True):
            stages[name].append(dt * 1000)
    frames = []
    with FrameRenderer(scene.model, 640, 480, "front", shadows=False) as video:
        for _ in range(10):
            t = time.perf_counter()
            video.render(scene.data)
            frames.append((time.perf_counter() - t) * 1000)
    baseline = statistics.median(frames)
    print(f"gesture reading, {args.reads} reads, eyes {args.size}x{args.size} px (median ms)")
    print(f"{'stage':<12}{'ms':>8}{'x video frame':>15}")
    for name, values in stages.items():
        ms = statistics.median(values)
        print(f"{name:<12}{ms:>8.1f}{ms / baseline:>15.2f}")
    print(f"{'video frame':<12}{baseline:>8.1f}{1.0:>15.2f}   (640x480 front camera, baseline)")
    print(f"read right: {right} of {args.reads}")


if __name__ == "__main__":
    main()
