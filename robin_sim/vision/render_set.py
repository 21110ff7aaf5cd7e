"""Render data-set chunks (one process renders with one scene and one pair of eyes).

:func:`render_chunk` is the worker's job: it builds the scene once per process, renders each
sample of the chunk (kinematics only: Robin's arm set to the sample's state by ``qpos``, at home
or holding a leg above the palm as physics left it (:func:`~robin_sim.vision.arm_states.
held_leg_qpos`, reached once per process), the hand's mocap pose, the head aimed by ``qpos``),
finds the hand in each eye and stores its crops (:mod:`robin_sim.vision.crops`: the features
are computed from them when the split is loaded), and writes the chunk file. Where the
segmentation renderer's ground truth is available it records the left eye's overlap (IoU) of
the found region with the true hand pixels, for the report only.
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping
from dataclasses import replace
from pathlib import Path
from typing import Any

import numpy as np

from robin_sim.render.gl_backend import ensure_gl_backend

ensure_gl_backend()

import mujoco  # noqa: E402

from robin_sim.figure.hand_poses import Performance  # noqa: E402
from robin_sim.figure.posture import Posture  # noqa: E402
from robin_sim.model import names  # noqa: E402
from robin_sim.model.scene import build_model  # noqa: E402
from robin_sim.person.gestures import GestureDisplay  # noqa: E402
from robin_sim.render.renderer import open_renderer  # noqa: E402
from robin_sim.vision.arm_states import away_qpos, held_leg_qpos  # noqa: E402
from robin_sim.vision.classifier import CLASSES, NO_GESTURE  # noqa: E402
from robin_sim.vision.crops import CROP_SIDE, HandCrops, hand_crops  # noqa: E402
from robin_sim.vision.dataset import (  # noqa: E402
    ARMS,
    CHUNK,
    SampleSpec,
    chunk_path,
    sample_spec,
    save_chunk,
)
from robin_sim.vision.eyes import EyeCameras, EyeCondition  # noqa: E402
from robin_sim.vision.reader import aim_and_see, regions  # noqa: E402

POSE_OF = {c: ("neutral" if c == NO_GESTURE else c) for c in CLASSES}


class SampleRenderer:
    """A scene with the person's hand, Robin at home, and the eye cameras."""

    def __init__(self) -> None:
        self.model = build_model()
        self.data = mujoco.MjData(self.model)
        mujoco.mj_resetDataKeyframe(self.model, self.data, self.model.key(names.HOME_KEY).id)
        mujoco.mj_forward(self.model, self.data)
        self.display = GestureDisplay(self.model, self.data)
        self.posture = Posture(self.model, self.data)
        self.mocap = int(self.model.body_mocapid[self.model.body(names.HUMAN_MOCAP_BODY).id])
        self.arm_qpos = {"home": self.data.qpos.copy()}  # "held_leg" reached when first drawn
        self.eyes = EyeCameras(self.model)
        self._truth = open_renderer(self.model, self.eyes.size, self.eyes.size)

    def render(self, spec: SampleSpec) -> tuple[list[HandCrops | None], float]:
        """Per-eye hand crops (None: no hand found) and the left eye's IoU with the truth."""
        rng = np.random.default_rng(spec.seed)
        pose = POSE_OF[CLASSES[spec.label]]
        performance = Performance.draw(rng, jitter=spec.jitter, skin_range=(spec.skin, spec.skin))
        self.set_arm(spec.arm)
        self.data.mocap_pos[self.mocap] = spec.held_at
        self.display.show(pose, performance)
        self.posture.update()  # the arm and body follow the hand
        mujoco.mj_kinematics(self.model, self.data)
        target = self.data.site(names.HUMAN_PALM_SITE).xpos + spec.aim_error
        condition = EyeCondition(
            lighting=spec.lighting,
            light_turn=spec.light_turn,
            light_tilt=spec.light_tilt,
            camera_noise=spec.camera_noise,
            blur=spec.blur,
        )
        views, depths = aim_and_see(self.eyes, self.data, target, condition, rng)
        found = regions(views, depths)
        truth = self.truth_mask(pose)
        left = found[0]
        if left is None:
            iou = 0.0 if truth.any() else 1.0
        else:
            iou = float((left.mask & truth).sum() / max((left.mask | truth).sum(), 1))
        crops = [
            None if r is None else hand_crops(v.rgb, v.depth, r, v.focal)
            for v, r in zip(views, found, strict=True)
        ]
        return crops, iou

    def set_arm(self, arm: str) -> None:
        """Robin's joints and the legs as in state ``arm`` (:data:`~robin_sim.vision.dataset.
        ARMS`); every sample starts from it, so a sample never depends on the one before."""
        if arm not in ARMS:
            raise ValueError(f"unknown arm state {arm!r}; the choices: {', '.join(ARMS)}")
        if arm == "away" and arm not in self.arm_qpos:  # a what-if, set by qpos
            self.arm_qpos[arm] = away_qpos(self.model, self.arm_qpos["home"])
        if arm not in self.arm_qpos:  # "held_leg": reached by acting, once per process
            self.arm_qpos[arm] = held_leg_qpos(self.model)
        self.data.qpos[:] = self.arm_qpos[arm]
        mujoco.mj_kinematics(self.model, self.data)

    def truth_mask(self, pose: str, eye: int = 0) -> np.ndarray:
        """True hand pixels of eye ``eye`` (0 left, 1 right; segmentation render; labels,
        benches and tests only)."""
        return self.geom_mask(self.display.geoms(pose), eye)

    def geom_mask(self, geoms: Iterable[int], eye: int = 0) -> np.ndarray:
        """Pixels of eye ``eye`` that show one of ``geoms`` (ids; segmentation render)."""
        model, camera = self.model, self.eyes.cameras[eye]
        saved = float(model.cam_fovy[camera])
        model.cam_fovy[camera] = self.eyes.fovy
        try:
            self._truth.update_scene(self.data, camera)
            self._truth.enable_segmentation_rendering()
            seg = self._truth.render()
            self._truth.disable_segmentation_rendering()
        finally:
            model.cam_fovy[camera] = saved
        return (seg[..., 1] == mujoco.mjtObj.mjOBJ_GEOM) & np.isin(seg[..., 0], list(geoms))


_RENDERER: SampleRenderer | None = None


def render_chunk(
    folder: Path,
    seed: int,
    split: str,
    chunk: int,
    overrides: Mapping[str, float] | None = None,
    name: str | None = None,
) -> int:
    """Render chunk ``chunk`` of ``split`` into its file; returns the samples rendered.

    ``overrides`` replace fields of each sample's spec (e.g. a fixed ``lighting``); ``name``
    names the chunk files instead of ``split``.
    """
    global _RENDERER  # one scene per worker process, built on its first chunk
    if _RENDERER is None:
        _RENDERER = SampleRenderer()
    images: dict[str, list[np.ndarray]] = {key: [] for key in ("mask", "shading", "relief")}
    sizes, labels, samples, eyes, found, ious, conditions = [], [], [], [], [], [], []
    blank = np.zeros((CROP_SIDE, CROP_SIDE), np.uint8)
    changes: dict[str, Any] = dict(overrides or {})  # float fields; replace() checks the names
    for index in range(chunk * CHUNK, (chunk + 1) * CHUNK):
        spec = replace(sample_spec(seed, split, index), **changes)
        crops, iou = _RENDERER.render(spec)
        ious.append(iou)
        conditions.append(
            [spec.skin, spec.lighting, spec.light_tilt, spec.camera_noise, spec.jitter, spec.lift]
        )
        for eye, c in enumerate(crops):
            for key, frames in images.items():
                frames.append(blank if c is None else getattr(c, key))
            sizes.append(np.zeros(3, np.float32) if c is None else c.size)
            found.append(c is not None)
            labels.append(spec.label)
            samples.append(index)
            eyes.append(eye)
    save_chunk(
        chunk_path(folder, name or split, chunk),
        {
            **{key: np.stack(frames) for key, frames in images.items()},
            "size": np.stack(sizes),
            "label": np.array(labels, np.int64),
            "sample": np.array(samples, np.int64),
            "eye": np.array(eyes, np.int64),
            "found": np.array(found, bool),
            "iou": np.repeat(np.array(ious), 2),
            "condition": np.repeat(np.array(conditions), 2, axis=0),
            "seed": np.int64(seed),  # a run with another seed does not reuse this chunk
        },
    )
    return CHUNK
