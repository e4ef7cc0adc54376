"""Pose regression (Sec. III.B-E): the model, the loss of eq. 14, training and the pose CLI."""

from __future__ import annotations

import json
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest
import torch

from blurloc.cli import main
from blurloc.data import load_split
from blurloc.inference import load_pose_model, predict_poses
from blurloc.models.pose import (
    LearnedWeighting,
    PoseConfig,
    PoseRegressor,
    ResNetEncoder,
    load_encoder_weights,
    pose_loss,
)
from blurloc.train.config import PoseTrainConfig
from blurloc.train.pose import train_pose
from blurloc.trajectory import write_tum


@pytest.mark.parametrize("head", ["lstm", "bilstm", "gru", "none"])
def test_model_outputs_unit_quaternions_and_the_right_causality(head: str) -> None:
    torch.manual_seed(0)
    model = PoseRegressor(PoseConfig(head=head, hidden=16)).eval()
    frames = torch.rand(2, 4, 3, 40, 48) * 2 - 1
    with torch.no_grad():
        position, quaternion = model(frames)
        changed = frames.clone()
        changed[:, 3] = -changed[:, 3]  # only the last frame differs
        _, quaternion_changed = model(changed)
    assert position.shape == (2, 4, 3) and quaternion.shape == (2, 4, 4)
    torch.testing.assert_close(quaternion.norm(dim=-1), torch.ones(2, 4))
    assert (quaternion[..., 0] >= 0).all()
    first_changed = not torch.allclose(quaternion[:, 0], quaternion_changed[:, 0], atol=1e-6)
    assert first_changed is (head == "bilstm")  # only the bidirectional head looks ahead


def test_loss_of_eq_14_and_learned_weighting() -> None:
    position = torch.tensor([[[3.0, 4.0, 0.0]]])
    quaternion = torch.tensor([[[2.0, 0.0, 0.0, 0.0]]])  # normalised inside the loss
    truth_q = torch.tensor([[[0.0, 1.0, 0.0, 0.0]]])
    loss = pose_loss(position, quaternion, torch.zeros(1, 1, 3), truth_q, beta=0.8)
    assert loss.item() == pytest.approx(5.0 + 0.8 * np.sqrt(2.0))
    weighting = LearnedWeighting()
    value = weighting(position, quaternion, torch.zeros(1, 1, 3), truth_q)
    assert value.item() == pytest.approx(5.0 + np.exp(3.0) * np.sqrt(2.0) - 3.0, rel=1e-5)


def test_encoder_weights_load_from_a_local_file(tmp_path: Path) -> None:
    source = ResNetEncoder("resnet18")
    state = {**source.state_dict(), "fc.weight": torch.zeros(10, 512), "fc.bias": torch.zeros(10)}
    torch.save(state, tmp_path / "resnet18.pth")
    target = ResNetEncoder("resnet18")
    assert load_encoder_weights(target, tmp_path / "resnet18.pth") == []
    torch.testing.assert_close(target.conv1.weight, source.conv1.weight)
    with pytest.raises(ValueError, match="do not fit"):
        load_encoder_weights(ResNetEncoder("small"), tmp_path / "resnet18.pth")


SMALL = PoseTrainConfig(epochs=3, windows_per_epoch=None, resize=32, crop=28, batch=4, window=3,
                        model=PoseConfig(hidden=16))  # fmt: skip


def test_training_resumes_identically_and_refuses_another_head(
    quick_root: Path, tmp_path: Path
) -> None:
    history = train_pose(quick_root, "chess", tmp_path / "lstm", SMALL, progress=False)
    assert history["epoch"] == [1, 2, 3]
    # interrupted after one epoch, then resumed: the same run, epoch for epoch
    first = train_pose(quick_root, "chess", tmp_path / "b", SMALL, progress=False, stop_after=1)
    assert first["epoch"] == [1]
    resumed = train_pose(quick_root, "chess", tmp_path / "b", SMALL, progress=False)
    for key in ("train_loss", "val_position_m", "val_orientation_deg"):
        np.testing.assert_allclose(resumed[key], history[key], rtol=1e-5)
    with pytest.raises(ValueError, match=r"head: 'lstm' -> 'gru'.*--restart"):
        gru = replace(SMALL, model=PoseConfig(head="gru", hidden=16))
        train_pose(quick_root, "chess", tmp_path / "lstm", gru, progress=False)
    model, config = load_pose_model(tmp_path / "lstm" / "best.pt")
    test = load_split(quick_root, "chess", "test")
    pair = predict_poses(model, test, config)
    assert np.allclose(np.linalg.norm(pair.estimate_quaternions, axis=1), 1.0, atol=1e-5)
    assert pair.estimate_positions.shape == (sum(len(s) for s in test), 3)
    truth = np.concatenate([s.poses() for s in test])
    np.testing.assert_allclose(pair.reference_positions, truth[:, :3, 3], atol=1e-6)
    with pytest.raises(ValueError, match="shorter than the window"):
        predict_poses(model, test, replace(config, window=100))


def test_pose_cli(quick_root: Path, tmp_path: Path, capsys: pytest.CaptureFixture) -> None:
    argv = ["train-pose", "--data", str(quick_root), "--scene", "stairs", "--out",
            str(tmp_path / "m"), "--epochs", "2", "--resize", "32", "--crop", "28", "--window",
            "2", "--quiet"]  # fmt: skip
    assert main(argv) == 0
    assert json.loads(capsys.readouterr().out)["epochs"] == 2
    assert main(["eval-pose", "--data", str(quick_root), "--scene", "stairs", "--model",
                 str(tmp_path / "m"), "--out", str(tmp_path / "pred.txt")]) == 0  # fmt: skip
    printed = json.loads(capsys.readouterr().out)
    test = load_split(quick_root, "stairs", "test")
    assert printed["frames"] == sum(len(s) for s in test)
    lines = (tmp_path / "pred.txt").read_text().splitlines()
    assert len(lines) == printed["frames"] and lines[0].split()[0] == "0"
    # the printed errors agree with pose-error between the ground truth and the TUM file
    truth = tmp_path / "truth.txt"
    write_tum(truth, np.arange(len(lines)), np.concatenate([s.poses() for s in test]))
    assert main(["pose-error", str(truth), str(tmp_path / "pred.txt")]) == 0
    compared = json.loads(capsys.readouterr().out)
    assert compared["position_m"]["median"] == pytest.approx(printed["position_m"]["median"],
                                                             abs=1e-5)  # fmt: skip
    # bad input: a scene without test frames, a missing checkpoint
    (tmp_path / "empty" / "chess").mkdir(parents=True)
    (tmp_path / "empty" / "chess" / "TestSplit.txt").write_text("")
    (tmp_path / "empty" / "chess" / "TrainSplit.txt").write_text("")
    assert main(["eval-pose", "--data", str(tmp_path / "empty"), "--scene", "chess", "--model",
                 str(tmp_path / "m"), "--out", str(tmp_path / "x.txt")]) == 1  # fmt: skip
    assert "no TestSplit sequences" in capsys.readouterr().err
    assert main(["eval-pose", "--data", str(quick_root), "--scene", "chess", "--model",
                 str(tmp_path / "none.pt"), "--out", str(tmp_path / "x.txt")]) == 1  # fmt: skip
    assert "missing" in capsys.readouterr().err


def test_a_run_made_before_fixed_crop_resumes_with_random_crops_only(
    quick_root: Path, tmp_path: Path
) -> None:
    old = replace(SMALL, epochs=2, model=PoseConfig(hidden=8))
    train_pose(quick_root, "chess", tmp_path / "old", old, progress=False, stop_after=1)
    for name in ("best.pt", "last.pt"):  # as stored before the setting existed
        payload = torch.load(tmp_path / "old" / name, weights_only=False)
        assert payload["train_config"].pop("fixed_crop") is False
        torch.save(payload, tmp_path / "old" / name)
    with pytest.raises(ValueError, match=r"fixed_crop: None -> True"):
        on = replace(old, fixed_crop=True)
        train_pose(quick_root, "chess", tmp_path / "old", on, progress=False)
    assert load_pose_model(tmp_path / "old" / "best.pt")[1].fixed_crop is False
    resumed = train_pose(quick_root, "chess", tmp_path / "old", old, progress=False)
    assert resumed["epoch"] == [1, 2]
