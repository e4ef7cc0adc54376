"""Every command that reads a checkpoint refuses a bad one with exit status 1 and a one-line
message naming the file, and never runs code hidden in a crafted pickle."""

from __future__ import annotations

import pickle
import shutil
from pathlib import Path

import pytest
import torch

from blurloc.checkpoints import CHECKPOINT_FORMATS
from blurloc.cli import main
from blurloc.inference import DEFAULT_CHECKPOINT
from blurloc.models.pose import PoseConfig, PoseRegressor
from blurloc.train.config import PoseTrainConfig

BAD = ("crafted", "crafted_legacy", "crafted_inside", "junk", "empty", "truncated")


class Payload:
    """Unpickling this object opens (creates) ``marker``: code run by loading a file."""

    def __init__(self, marker: Path) -> None:
        self.marker = marker

    def __reduce__(self) -> tuple:
        return open, (str(self.marker), "w")


def _pose_checkpoint(path: Path) -> Path:
    torch.save({"format": CHECKPOINT_FORMATS["pose"], "scene": "chess",
                "train_config": PoseTrainConfig().settings(),
                "model": PoseRegressor(PoseConfig()).state_dict()}, path)  # fmt: skip
    return path


def _bad_files(folder: Path, marker: Path) -> dict[str, Path]:
    """One file per kind of bad checkpoint; the pose checkpoint is bad only where a video one
    is expected (and the other way round), so both are returned and chosen per command."""
    folder.mkdir()
    files = {name: folder / f"{name}.pt" for name in BAD}
    torch.save(Payload(marker), files["crafted"])
    files["crafted_legacy"].write_bytes(pickle.dumps(Payload(marker)))
    torch.save({"format": CHECKPOINT_FORMATS["pose"], "model": {"w": Payload(marker)}},
               files["crafted_inside"])  # fmt: skip
    files["junk"].write_bytes(b"\x00junk\xffnot a checkpoint" * 10)
    files["empty"].write_bytes(b"")
    data = DEFAULT_CHECKPOINT.read_bytes()
    files["truncated"].write_bytes(data[: len(data) // 2])
    files["video"] = DEFAULT_CHECKPOINT
    files["pose"] = _pose_checkpoint(folder / "pose_model.pt")
    return files


def test_the_crafted_files_do_run_code_when_loaded_unsafely(tmp_path: Path) -> None:
    marker = tmp_path / "ran"
    files = _bad_files(tmp_path / "files", marker)
    for name in ("crafted", "crafted_legacy", "crafted_inside"):
        try:  # what a careless loader would do (a bare pickle runs before torch objects)
            torch.load(files[name], weights_only=False)
        except RuntimeError:
            pass
        assert marker.is_file(), name
        marker.unlink()


@pytest.mark.parametrize("command", ["eval-pose", "deblur-video", "train-pose",
                                     "train-video-deblur"])  # fmt: skip
def test_bad_checkpoints_exit_1_naming_the_file(
    command: str, quick_root: Path, tmp_path: Path, capsys: pytest.CaptureFixture
) -> None:
    marker = tmp_path / "ran"
    files = _bad_files(tmp_path / "files", marker)
    wrong_kind = files["pose"] if command in ("deblur-video", "train-video-deblur") \
        else files["video"]  # fmt: skip
    cases = [(name, files[name]) for name in BAD] + [("wrong kind", wrong_kind)]
    for label, bad in cases:
        out = tmp_path / "run"
        shutil.rmtree(out, ignore_errors=True)
        named = bad
        if command == "eval-pose":
            argv = ["eval-pose", "--data", str(quick_root), "--scene", "chess", "--model",
                    str(bad), "--out", str(tmp_path / "pred.txt")]  # fmt: skip
        elif command == "deblur-video":
            argv = ["deblur-video", str(load_folder(quick_root)), str(out / "frames"),
                    "--checkpoint", str(bad)]  # fmt: skip
        else:  # resuming a run whose last.pt is the bad file
            out.mkdir()
            named = out / "last.pt"
            shutil.copyfile(bad, named)
            argv = ([command, "--data", str(quick_root), "--out", str(out), "--quiet"]
                    + (["--scene", "chess", "--epochs", "1"] if command == "train-pose"
                       else ["--steps", "1", "--batch", "1", "--crop", "16"]))  # fmt: skip
        assert main(argv) == 1, (command, label)
        captured = capsys.readouterr()
        message = captured.err.strip()
        assert str(named) in message, (command, label, message)
        assert "\n" not in message and "Traceback" not in message, (command, label, message)
        assert not marker.exists(), (command, label)
        if label.startswith("crafted"):
            assert "could run code" in message, (command, label, message)
        assert not (tmp_path / "pred.txt").exists(), (command, label)


def load_folder(root: Path) -> Path:
    """A sequence folder of the quick stand-in (a video to deblur)."""
    return next((root / "chess").glob("seq-*"))
