"""The training loop's guarantees: checked options, run folders that are never silently
replaced, the same numbers whatever the thread count, frames decoded once per run, a warning
for a model used on another scene, and video inference in bounded memory."""

from __future__ import annotations

import json
import os
import subprocess
import sys
import time
from dataclasses import replace
from pathlib import Path

import cv2
import numpy as np
import psutil
import pytest
import torch

import blurloc.data.sevenscenes
import blurloc.train.datasets
from blurloc.cli import main
from blurloc.data import load_split
from blurloc.models.pose import PoseConfig
from blurloc.train.config import PoseTrainConfig
from blurloc.train.datasets import FrameCache
from blurloc.train.loop import choose_device, validation_cut
from blurloc.train.pose import train_pose

TINY = PoseTrainConfig(epochs=2, windows_per_epoch=None, resize=32, crop=28, batch=4, window=2,
                       model=PoseConfig(hidden=8))  # fmt: skip


def _train_pose_argv(root: Path, out: Path, *extra: str, epochs: int = 1) -> list[str]:
    return ["train-pose", "--data", str(root), "--scene", "stairs", "--out", str(out),
            "--epochs", str(epochs), "--resize", "32", "--crop", "28", "--window", "2",
            "--quiet", *extra]  # fmt: skip


def test_the_data_package_does_not_import_torch() -> None:
    code = "import sys, blurloc.data, blurloc.data.frames; print('torch' in sys.modules)"
    result = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                            check=True)  # fmt: skip
    assert result.stdout.strip() == "False"


def test_validation_cut_holds_at_least_two_frames() -> None:
    assert [validation_cut(n) for n in (3, 8, 20, 100, 1000)] == [2, 2, 3, 15, 150]
    with pytest.raises(ValueError, match="too short"):
        validation_cut(2)


def test_devices_are_checked() -> None:
    assert choose_device("cpu") == torch.device("cpu")
    with pytest.raises(ValueError, match="--device 'gpu0'"):
        choose_device("gpu0")
    if not torch.cuda.is_available():
        with pytest.raises(ValueError, match="CUDA is not available"):
            choose_device("cuda")


@pytest.mark.parametrize(
    ("argv", "option"),
    [
        (["train-pose", "--epochs", "0"], "--epochs"),
        (["train-pose", "--batch", "0"], "--batch"),
        (["train-pose", "--crop", "0"], "--crop"),
        (["train-pose", "--crop", "80", "--resize", "64"], "--crop"),
        (["train-pose", "--device", "gpu0"], "--device"),
        (["train-video-deblur", "--steps", "0"], "--steps"),
        (["train-video-deblur", "--batch", "0"], "--batch"),
        (["train-video-deblur", "--crop", "0"], "--crop"),
        (["train-video-deblur", "--device", "gpu0"], "--device"),
        (["train-video-deblur", "--validation-per-scene", "-1"], "--validation-per-scene"),
        (["train-video-deblur", "--photo-videos", "-1"], "--photo-videos"),
        (["train-video-deblur", "--photo-noise", "-0.1"], "--photo-noise"),
        (["train-video-deblur", "--workers", "0"], "--workers"),
    ],
)
def test_bad_training_options_exit_1_naming_the_option(
    argv: list[str], option: str, tmp_path: Path, capsys: pytest.CaptureFixture
) -> None:
    required = ["--data", str(tmp_path / "none"), "--out", str(tmp_path / "out")]
    if argv[0] == "train-pose":
        required += ["--scene", "chess"]
    assert main([*argv, *required]) == 1
    message = capsys.readouterr().err.strip()
    assert option in message and "\n" not in message, message
    assert not (tmp_path / "out").exists()


def test_a_run_folder_is_never_silently_replaced(
    quick_root: Path, tmp_path: Path, capsys: pytest.CaptureFixture
) -> None:
    out = tmp_path / "model"
    assert main(_train_pose_argv(quick_root, out)) == 0
    best = (out / "best.pt").read_bytes()
    # another setting (more epochs, another learning rate): refused, naming --restart
    for argv in (_train_pose_argv(quick_root, out, epochs=2),
                 _train_pose_argv(quick_root, out, "--lr", "0.01")):  # fmt: skip
        assert main(argv) == 1
        message = capsys.readouterr().err
        assert "--restart" in message and str(out / "last.pt") in message, message
        assert (out / "best.pt").read_bytes() == best
    # the same settings: the finished run is kept (nothing left to train)
    capsys.readouterr()
    assert main(_train_pose_argv(quick_root, out)) == 0
    assert json.loads(capsys.readouterr().out)["epochs"] == 1
    assert (out / "best.pt").read_bytes() == best
    # another model kind into the folder: refused, even with --restart
    video = ["train-video-deblur", "--data", str(quick_root), "--out", str(out), "--steps", "1",
             "--batch", "1", "--crop", "16", "--quiet"]  # fmt: skip
    for argv in (video, [*video, "--restart"]):
        assert main(argv) == 1
        assert "holds a pose model" in capsys.readouterr().err
    # --restart starts afresh with the new settings
    assert main(_train_pose_argv(quick_root, out, "--lr", "0.01", "--restart")) == 0
    stored = torch.load(out / "last.pt", weights_only=True)["train_config"]
    assert stored["lr"] == 0.01


def test_a_model_used_on_another_scene_warns(
    quick_root: Path, tmp_path: Path, capsys: pytest.CaptureFixture
) -> None:
    assert main(_train_pose_argv(quick_root, tmp_path / "m")) == 0
    capsys.readouterr()
    evaluate = ["eval-pose", "--data", str(quick_root), "--model", str(tmp_path / "m"), "--out"]
    assert main([*evaluate, str(tmp_path / "a.txt"), "--scene", "stairs"]) == 0
    assert "warning" not in capsys.readouterr().err
    assert main([*evaluate, str(tmp_path / "b.txt"), "--scene", "chess"]) == 0
    err = capsys.readouterr().err
    assert "warning" in err and "'stairs'" in err and "'chess'" in err, err


def _weights(path: Path) -> dict[str, torch.Tensor]:
    return torch.load(path, weights_only=True)["model"]


def test_one_seed_gives_the_same_numbers_whatever_the_thread_count(
    quick_root: Path, tmp_path: Path
) -> None:
    previous = torch.get_num_threads()
    runs = []
    try:
        for threads in (1, 3):
            torch.set_num_threads(threads)
            history = train_pose(quick_root, "chess", tmp_path / str(threads), TINY,
                                 progress=False)  # fmt: skip
            runs.append((history, _weights(tmp_path / str(threads) / "last.pt")))
            assert torch.get_num_threads() == threads  # restored after training
    finally:
        torch.set_num_threads(previous)
    (first, weights_1), (second, weights_3) = runs
    for key in ("train_loss", "val_position_m", "val_orientation_deg"):
        assert first[key] == second[key], key
    for name, tensor in weights_1.items():
        assert torch.equal(tensor, weights_3[name]), name


def test_training_decodes_each_frame_once(
    quick_root: Path, tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    decoded: list[Path] = []
    read_image = blurloc.train.datasets.read_image

    def counting(path):
        decoded.append(Path(path))
        return read_image(path)

    pose_reads: list[Path] = []
    read_pose = blurloc.data.sevenscenes.read_pose
    monkeypatch.setattr(blurloc.train.datasets, "read_image", counting)
    monkeypatch.setattr(blurloc.data.sevenscenes, "read_pose",
                        lambda path: pose_reads.append(Path(path)) or read_pose(path))  # fmt: skip
    train_pose(quick_root, "chess", tmp_path / "m", replace(TINY, epochs=3), progress=False)
    frames = sum(len(s) for s in load_split(quick_root, "chess", "train"))
    assert len(decoded) == len(set(decoded)) == frames  # three epochs, one decode per frame
    assert len(pose_reads) == len(set(pose_reads)) == frames  # and one read per pose file


def test_frame_cache_is_bounded(quick_root: Path) -> None:
    paths = [s.path(f) for s in load_split(quick_root, "chess", "train") for f in s.frame_ids]
    one = FrameCache().get(paths[0], 32).nbytes
    cache = FrameCache(max_bytes=3 * one)
    first = [cache.get(p, 32) for p in paths]
    assert len(cache) == 3 and cache.bytes == 3 * one
    again = [cache.get(p, 32) for p in paths]
    for a, b in zip(first, again, strict=True):
        np.testing.assert_array_equal(a, b)


def test_deblur_video_network_streams_its_frames(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture
) -> None:
    import blurloc.data.frames
    import blurloc.inference

    folder = tmp_path / "video"
    folder.mkdir()
    rng = np.random.default_rng(0)
    for index in range(40):
        frame = (rng.random((24, 32, 3)) * 255).astype(np.uint8)
        cv2.imwrite(str(folder / f"frame-{index:06d}.color.png"), frame)
    events: list[str] = []
    read_image, imwrite = blurloc.data.frames.read_image, cv2.imwrite
    monkeypatch.setattr(blurloc.data.frames, "read_image",
                        lambda path: events.append("read") or read_image(path))  # fmt: skip
    monkeypatch.setattr(cv2, "imwrite", lambda *a: events.append("write") or imwrite(*a))
    monkeypatch.setattr(blurloc.inference, "CHUNK_PIXELS", 8 * 24 * 32)  # chunks of 8 frames
    assert main(["deblur-video", str(folder), str(tmp_path / "out"), "--method", "network"]) == 0
    assert json.loads(capsys.readouterr().out)["frames"] == 40
    held = np.cumsum([1 if e == "read" else -1 for e in events])
    assert events.count("write") == 40 and held.max() <= 8  # never more than one chunk held


@pytest.mark.parametrize("head", ["lstm", "none"])
def test_a_pose_epoch_is_a_fixed_number_of_windows(
    quick_root: Path, tmp_path: Path, head: str
) -> None:
    """8 windows of 2 frames per epoch in batches of 4: 2 optimiser steps, whatever the scene's
    size; the single-frame head takes the same 16 frames in the same 2 steps (batches of 8
    frames), so the two heads differ only in the head."""
    config = replace(TINY, windows_per_epoch=8, model=PoseConfig(head=head, hidden=8))
    train_pose(quick_root, "chess", tmp_path / head, config, progress=False)
    state = torch.load(tmp_path / head / "last.pt", weights_only=True)
    assert state["schedule"]["last_epoch"] == config.epochs * 2
    with pytest.raises(ValueError, match="--windows-per-epoch"):
        replace(TINY, windows_per_epoch=0)


def test_parallel_map_keeps_the_order_in_worker_processes() -> None:
    """Results come back in the order of the jobs, from two spawned processes as from one."""
    from blurloc.train.loop import parallel_map

    numbers = [7, 12, 5, 9, 30]
    assert list(parallel_map(abs, [-n for n in numbers], 2)) == numbers
    assert list(parallel_map(abs, [-n for n in numbers], 1)) == numbers
    with pytest.raises(ValueError, match="workers must be >= 1"):
        parallel_map(abs, numbers, 0)
    with pytest.raises(ValueError, match="chunksize must be >= 1"):
        parallel_map(abs, numbers, 2, chunksize=0)


def _process_id(_job: int) -> int:
    return os.getpid()


def test_parallel_map_hands_a_chunk_to_one_process() -> None:
    """With chunksize 3, the jobs of one chunk (e.g. the seeds of one pose run, which read the
    same frames) run in the same worker process."""
    from blurloc.train.loop import parallel_map

    processes = list(parallel_map(_process_id, range(6), 2, chunksize=3))
    assert len(set(processes[:3])) == len(set(processes[3:])) == 1
    assert os.getpid() not in processes


def _mark_and_wait(marker: str) -> None:
    Path(marker).touch()
    time.sleep(120)


def test_parallel_map_workers_end_with_their_parent(tmp_path: Path) -> None:
    """kill -9 of a process training in parallel_map's workers ends the workers within
    seconds, instead of letting them train on for minutes."""
    markers = [tmp_path / f"started-{n}" for n in range(2)]
    code = (f"import sys; sys.path.insert(0, {str(Path(__file__).parent)!r}); "
            f"from test_training_runs import _mark_and_wait; "
            f"from blurloc.train.loop import parallel_map; "
            f"list(parallel_map(_mark_and_wait, {[str(m) for m in markers]!r}, 2))")  # fmt: skip
    env = {**os.environ, "PYTHONPATH": os.pathsep.join(sys.path)}
    parent = subprocess.Popen([sys.executable, "-c", code], env=env)
    workers: list[psutil.Process] = []
    try:
        deadline = time.monotonic() + 120
        while time.monotonic() < deadline and not all(m.exists() for m in markers):
            time.sleep(0.1)
        assert all(m.exists() for m in markers), "the workers did not start their jobs"
        workers = [child for child in psutil.Process(parent.pid).children(recursive=True)
                   if "spawn_main" in " ".join(child.cmdline())]  # fmt: skip
        assert len(workers) == 2
        parent.kill()
        parent.wait()
        _, alive = psutil.wait_procs(workers, timeout=5)
        assert alive == []
    finally:
        for process in workers:
            if process.is_running():
                process.kill()
        if parent.poll() is None:
            parent.kill()
