"""Image retrieval as a pose estimate: the descriptor, the search, the baseline on real frames."""

from __future__ import annotations

import shutil

import numpy as np
import pytest

from blurloc.data.real import POSED_SCENE, RECORDING_SCENE, posed_root, recording_root
from blurloc.experiments.pose import mean_pose_baseline
from blurloc.experiments.retrieval import (
    global_descriptor,
    nearest_frames,
    retrieval_baseline,
)

needs_recording = pytest.mark.skipif(
    not (recording_root() / RECORDING_SCENE).is_dir(), reason="the real recording is not present"
)
needs_posed = pytest.mark.skipif(
    not (posed_root() / POSED_SCENE / "seq-01").is_dir(),
    reason="the real posed frames are not present",
)


def test_descriptor_is_normalised_and_ignores_brightness_and_contrast():
    image = np.random.default_rng(0).integers(0, 200, (48, 64, 3)).astype(np.float32)
    descriptor = global_descriptor(image)
    assert descriptor.shape == (16 * 12,)
    assert abs(descriptor.mean()) < 1e-9 and np.linalg.norm(descriptor) == pytest.approx(1.0)
    assert np.allclose(global_descriptor(0.5 * image + 30), descriptor, atol=1e-6)
    assert not np.allclose(global_descriptor(image[:, ::-1]), descriptor, atol=0.1)
    assert np.all(global_descriptor(np.full((48, 64), 7.0)) == 0)


def test_nearest_frames_finds_each_query_in_the_database():
    database = np.stack([global_descriptor(np.random.default_rng(k).random((24, 32)))
                         for k in range(5)])  # fmt: skip
    assert nearest_frames(database[[3, 0, 4]], database).tolist() == [3, 0, 4]


@needs_posed
def test_retrieving_the_training_frames_themselves_gives_their_poses(tmp_path):
    scene = tmp_path / POSED_SCENE
    for copy in ("seq-01", "seq-02"):  # the test sequence: the training frames again
        shutil.copytree(posed_root() / POSED_SCENE / "seq-01", scene / copy)
    (scene / "TrainSplit.txt").write_text("sequence1\n")
    (scene / "TestSplit.txt").write_text("sequence2\n")
    summary = retrieval_baseline(tmp_path, POSED_SCENE)
    assert summary["position_m"]["mean"] == 0 and summary["orientation_deg"]["mean"] < 1e-4


@needs_recording
def test_retrieval_on_the_real_recording_beats_the_mean_pose_in_orientation():
    retrieved = retrieval_baseline(recording_root(), RECORDING_SCENE)
    mean = mean_pose_baseline(recording_root(), RECORDING_SCENE)
    assert retrieved["frames"] == mean["frames"] > 100
    assert retrieved["orientation_deg"]["median"] < 0.5 * mean["orientation_deg"]["median"]
