"""No command writes over or into its inputs, a dataset or a training run; bad input (huge or
truncated images, sparse trajectory matches, interruptions, out-of-range options) ends in one
line naming the file or option, or a warning where the result stays valid."""

from __future__ import annotations

import json
import os
import signal
import struct
import subprocess
import sys
import time
import zlib
from pathlib import Path

import cv2
import numpy as np
import pytest
import torch

import blurloc.cli
import blurloc.files
import blurloc.train.pose
from blurloc.cli import main
from blurloc.experiments.video import write_deblurred_root
from blurloc.image_headers import MAX_PIXELS_VARIABLE
from blurloc.models.pose import ResNetEncoder, load_encoder_weights
from blurloc.trajectory import write_tum

LENGTH = ["--length", "3", "--angle", "0"]


def snapshot(folder: Path) -> dict[str, bytes]:
    """Every file under ``folder`` with its bytes."""
    return {str(p.relative_to(folder)): p.read_bytes() for p in folder.rglob("*") if p.is_file()}


def run(argv: list[str], capsys: pytest.CaptureFixture) -> tuple[int, str]:
    status = main(argv)
    return status, capsys.readouterr().err


def _frame(seed: int, shape: tuple[int, ...] = (24, 32, 3), dtype: type = np.uint8) -> np.ndarray:
    top = np.iinfo(dtype).max
    return (np.random.default_rng(seed).random(shape) * top).astype(dtype)


@pytest.fixture()
def dataset(tmp_path: Path) -> Path:
    """A 7-Scenes-layout root ``data`` with scene chess: seq-01 (train) and seq-02 (test), three
    frames each with colour, the stand-in's sharp frame, 16-bit depth and pose."""
    root = tmp_path / "data"
    scene = root / "chess"
    for number in (1, 2):
        folder = scene / f"seq-{number:02d}"
        folder.mkdir(parents=True)
        for index in range(3):
            stem = folder / f"frame-{index:06d}"
            cv2.imwrite(f"{stem}.color.png", _frame(10 * number + index))
            cv2.imwrite(f"{stem}.sharp.png", _frame(100 + index))
            cv2.imwrite(f"{stem}.depth.png", _frame(index, (24, 32), np.uint16))
            np.savetxt(f"{stem}.pose.txt", np.eye(4))
    (scene / "TrainSplit.txt").write_text("sequence1\n")
    (scene / "TestSplit.txt").write_text("sequence2\n")
    return root


@pytest.fixture()
def run_folder(tmp_path: Path) -> Path:
    """A training run folder with its two checkpoints and history (placeholder bytes)."""
    folder = tmp_path / "run"
    folder.mkdir()
    for name in ("best.pt", "last.pt", "history.json"):
        (folder / name).write_bytes(f"the run's {name}".encode())
    return folder


def _refused(argv: list[str], named: Path | str, reason: str, capsys) -> None:
    status, err = run(argv, capsys)
    assert status == 1, argv
    assert str(named) in err and reason in err, (argv, err)
    assert len(err.strip().splitlines()) == 1 and "Traceback" not in err, err


# ---- no command writes over or into an input ---------------------------------------------


def test_eval_pose_writes_neither_into_the_data_nor_over_the_run(
    dataset: Path, run_folder: Path, tmp_path: Path, capsys: pytest.CaptureFixture
) -> None:
    before = snapshot(tmp_path)
    evaluate = ["eval-pose", "--scene", "chess", "--model", str(run_folder / "best.pt")]
    split, pose = (
        dataset / "chess" / "TestSplit.txt",
        dataset / "chess/seq-01/frame-000000.pose.txt",
    )
    cases = [
        (["--data", str(dataset), "--out", str(split)], split, "inside the input folder"),
        (["--data", str(dataset), "--out", str(pose)], pose, "inside the input folder"),
        (["--data", str(tmp_path / "other"), "--out", str(split)], split, "lies in the dataset"),
        (["--data", str(dataset), "--out", str(run_folder / "last.pt")], "last.pt", "training run"),
        (["--data", str(dataset), "--out", str(run_folder / "history.json")], "history.json",
         "training run"),
    ]  # fmt: skip
    for argv, named, reason in cases:
        _refused([*evaluate, *argv, "--overwrite"], named, reason, capsys)
    assert snapshot(tmp_path) == before


def test_deblurring_never_writes_over_another_sequence_or_into_the_dataset(
    dataset: Path, tmp_path: Path, capsys: pytest.CaptureFixture
) -> None:
    before = snapshot(dataset)
    first, second = dataset / "chess" / "seq-01", dataset / "chess" / "seq-02"
    cases = [
        (["deblur-video", str(second), str(first), "--overwrite"], first),
        (["deblur", str(second), str(first), *LENGTH, "--overwrite"], first),
        (["deblur-video", str(first), str(dataset / "chess")], dataset / "chess"),
        (["deblur-video", str(first), str(dataset / "deblurred")], dataset / "deblurred"),
        (["deblur", str(first / "frame-000000.color.png"), str(second / "x.png"), *LENGTH],
         second / "x.png"),
    ]  # fmt: skip
    for argv, named in cases:
        _refused(argv, named, "", capsys)
    assert snapshot(dataset) == before and not (dataset / "deblurred").exists()


def test_a_deblurred_copy_of_a_root_is_written_whole_and_never_inside_it(
    dataset: Path, tmp_path: Path
) -> None:
    before = snapshot(dataset)
    with pytest.raises(ValueError, match="inside the input folder"):
        write_deblurred_root(dataset, dataset / "deblurred", lambda frames: 255 - frames)
    copy = write_deblurred_root(dataset, tmp_path / "copy", lambda frames: 255 - frames)
    assert snapshot(dataset) == before
    carried = sorted(name for name in before if not name.endswith(".depth.png"))
    assert sorted(snapshot(copy)) == carried  # colour, sharp, pose, splits; no temporary files
    frame = "chess/seq-02/frame-000001.color.png"
    assert np.array_equal(cv2.imread(str(copy / frame)), 255 - cv2.imread(str(dataset / frame)))


def test_written_images_keep_their_samples_where_the_suffix_allows(tmp_path: Path) -> None:
    depth = _frame(5, (24, 32), np.uint16)
    assert blurloc.files.write_image_file(tmp_path / "depth.png", depth) == []
    assert np.array_equal(cv2.imread(str(tmp_path / "depth.png"), cv2.IMREAD_UNCHANGED), depth)
    assert blurloc.files.write_image_file(tmp_path / "depth.jpg", depth) == ["16-bit depth"]
    stored = cv2.imread(str(tmp_path / "depth.jpg"), cv2.IMREAD_GRAYSCALE).astype(float)
    assert np.abs(stored - depth / 257.0).mean() < 3.0  # reduced to 8-bit, then JPEG-coded


def test_trainers_refuse_an_out_folder_inside_a_dataset(
    dataset: Path, tmp_path: Path, capsys: pytest.CaptureFixture
) -> None:
    before = snapshot(dataset)
    other = tmp_path / "elsewhere"
    cases = [
        (["train-pose", "--data", str(dataset), "--scene", "chess", "--out",
          str(dataset / "chess")], "inside the input folder"),
        (["train-pose", "--data", str(other), "--scene", "chess", "--out",
          str(dataset / "chess" / "run")], "lies in the dataset"),
        (["train-video-deblur", "--data", str(dataset), "--out", str(dataset)], "is the input"),
        (["train-video-deblur", "--data", str(other), "--out", str(dataset / "run")],
         "lies in the dataset"),
    ]  # fmt: skip
    for argv, reason in cases:
        _refused([*argv, "--quiet"], argv[argv.index("--out") + 1], reason, capsys)
    assert snapshot(dataset) == before


def test_existing_outputs_are_replaced_only_with_overwrite(
    dataset: Path, tmp_path: Path, capsys: pytest.CaptureFixture
) -> None:
    sequence = dataset / "chess" / "seq-01"
    frame = sequence / "frame-000000.color.png"
    outputs = {
        "deblur-folder": (["deblur", str(sequence), str(tmp_path / "folder"), *LENGTH],
                          tmp_path / "folder"),
        "deblur-file": (["deblur", str(frame), str(tmp_path / "one.png"), *LENGTH],
                        tmp_path / "one.png"),
        "deblur-video": (["deblur-video", str(sequence), str(tmp_path / "video")],
                         tmp_path / "video"),
    }  # fmt: skip
    for argv, out in outputs.values():
        assert main(argv) == 0, argv
        capsys.readouterr()
        written = snapshot(out.parent)
        _refused(argv, out, "give --overwrite", capsys)
        assert snapshot(out.parent) == written
        assert main([*argv, "--overwrite"]) == 0, argv
    capsys.readouterr()
    prediction = tmp_path / "prediction.txt"
    prediction.write_text("kept")
    _refused(["eval-pose", "--data", str(dataset), "--scene", "chess", "--model",
              str(tmp_path / "none.pt"), "--out", str(prediction)], prediction, "exists",
             capsys)  # fmt: skip
    assert prediction.read_text() == "kept"


def test_a_sequence_folder_is_read_for_its_colour_frames_only(
    dataset: Path, tmp_path: Path, capsys: pytest.CaptureFixture
) -> None:
    sequence = dataset / "chess" / "seq-01"
    colour = sorted(p.name for p in sequence.glob("frame-*.color.png"))
    assert main(["deblur", str(sequence), str(tmp_path / "folder"), *LENGTH]) == 0
    assert main(["deblur-video", str(sequence), str(tmp_path / "video")]) == 0
    for out in ("folder", "video"):
        assert sorted(p.name for p in (tmp_path / out).iterdir()) == colour


def test_deblur_video_writes_each_frame_then_renames_it(
    dataset: Path, tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    renamed = []
    replace = os.replace

    def recording_replace(source: str | os.PathLike, target: str | os.PathLike) -> None:
        renamed.append((Path(source), Path(target)))
        replace(source, target)

    monkeypatch.setattr(blurloc.files.os, "replace", recording_replace)
    out = tmp_path / "video"
    assert main(["deblur-video", str(dataset / "chess" / "seq-01"), str(out)]) == 0
    frames = sorted(out.iterdir())
    assert len(frames) == 3
    assert sorted(target for _, target in renamed) == frames
    assert all(s.parent == out and s.name.startswith(".") for s, _ in renamed)


# ---- bad images -----------------------------------------------------------------------------


def _png_header_only(path: Path, width: int, height: int) -> Path:
    """A complete PNG file that claims ``width`` x ``height`` 8-bit RGB pixels and holds none
    (what a 415 KB PNG of a huge flat image looks like before it is decoded)."""

    def chunk(kind: bytes, data: bytes) -> bytes:
        return (
            struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data))
        )

    header = struct.pack(">IIBBBBB", width, height, 8, 2, 0, 0, 0)
    path.write_bytes(b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", header) + chunk(b"IEND", b""))
    return path


def test_the_pixel_cap_is_checked_before_decoding(
    tmp_path: Path, capsys: pytest.CaptureFixture, monkeypatch: pytest.MonkeyPatch
) -> None:
    huge = _png_header_only(tmp_path / "huge.png", 30_000, 30_000)
    started = time.perf_counter()
    _refused(["blur-estimate", str(huge)], huge, MAX_PIXELS_VARIABLE, capsys)
    _refused(["deblur", str(huge), str(tmp_path / "o.png"), *LENGTH], "cap of 50,000,000", "",
             capsys)  # fmt: skip
    assert time.perf_counter() - started < 5  # decoding it would take minutes and 2.7 GB
    small = tmp_path / "small.png"
    cv2.imwrite(str(small), _frame(0, (64, 64, 3)))
    monkeypatch.setenv(MAX_PIXELS_VARIABLE, "4000")
    _refused(["blur-estimate", str(small)], small, "64x64 pixels is more than the cap of 4,000",
             capsys)  # fmt: skip
    monkeypatch.setenv(MAX_PIXELS_VARIABLE, "4096")
    assert main(["blur-estimate", str(small)]) == 0
    monkeypatch.setenv(MAX_PIXELS_VARIABLE, "lots")
    _refused(["blur-estimate", str(small)], MAX_PIXELS_VARIABLE, "positive whole number", capsys)


@pytest.mark.parametrize("suffix", [".jpg", ".png", ".bmp", ".tif"])
def test_truncated_images_are_refused(
    suffix: str, tmp_path: Path, capsys: pytest.CaptureFixture
) -> None:
    whole = tmp_path / f"whole{suffix}"
    cv2.imwrite(str(whole), _frame(1, (96, 128, 3)))
    cut = tmp_path / f"cut{suffix}"
    data = whole.read_bytes()
    cut.write_bytes(data[: int(len(data) * 0.8)] if suffix != ".tif" else data[:-4000])
    assert main(["blur-estimate", str(whole)]) == 0
    capsys.readouterr()
    _refused(["blur-estimate", str(cut)], cut, "truncated" if suffix != ".tif" else "", capsys)
    _refused(["deblur", str(cut), str(tmp_path / "o.png"), *LENGTH], cut, "", capsys)
    assert not (tmp_path / "o.png").exists()


@pytest.mark.parametrize(
    ("frame", "described"),
    [(_frame(2, (24, 32, 3), np.uint16), "16-bit RGB"), (_frame(2, (24, 32)), "8-bit gray"),
     (_frame(2, (24, 32, 4)), "8-bit RGBA")],
)  # fmt: skip
def test_deblur_video_refuses_frames_whose_depth_or_channels_it_would_change(
    frame: np.ndarray, described: str, tmp_path: Path, capsys: pytest.CaptureFixture
) -> None:
    folder = tmp_path / "frames"
    folder.mkdir()
    for index in range(2):
        cv2.imwrite(str(folder / f"{index}.png"), frame)
    _refused(["deblur-video", str(folder), str(tmp_path / "out")], folder / "0.png", described,
             capsys)  # fmt: skip
    assert not (tmp_path / "out").exists()


# ---- trajectories ---------------------------------------------------------------------------


def test_pose_error_warns_when_few_poses_are_matched(
    tmp_path: Path, capsys: pytest.CaptureFixture
) -> None:
    truth = write_tum(tmp_path / "truth.txt", np.arange(8.0), np.tile(np.eye(4), (8, 1, 1)))
    estimate = write_tum(tmp_path / "estimate.txt", np.array([3.0]), np.eye(4)[None])
    assert main(["pose-error", str(truth), str(estimate)]) == 0
    assert json.loads(capsys.readouterr().out)["frames"] == 1
    assert main(["pose-error", str(truth), str(estimate)]) == 0
    warned = capsys.readouterr().err.strip().splitlines()
    assert len(warned) == 1 and warned[0].startswith(f"warning: {truth}: only 1 of its 8"), warned
    assert main(["pose-error", str(truth), str(truth)]) == 0
    assert capsys.readouterr().err == ""


# ---- interruptions ------------------------------------------------------------------------


@pytest.fixture
def default_interrupt():
    """Python's own Ctrl-C handler in this process while the test runs, as a new ``blurloc``
    process has it, whatever handler an earlier test or library left behind (an ignored
    SIGINT would also pass to the subprocesses the test starts)."""
    previous = signal.signal(signal.SIGINT, signal.default_int_handler)
    yield
    signal.signal(signal.SIGINT, previous)


@pytest.mark.parametrize("signal_number", [signal.SIGINT, signal.SIGTERM])
def test_an_interrupted_training_ends_in_one_line_and_keeps_its_history(
    signal_number: int, quick_root: Path, tmp_path: Path, capsys: pytest.CaptureFixture,
    monkeypatch: pytest.MonkeyPatch, default_interrupt: None,
) -> None:  # fmt: skip
    validate = blurloc.train.pose.predict_poses
    calls = []

    def validate_then_interrupt(*args, **kwargs):
        calls.append(1)
        result = validate(*args, **kwargs)
        if len(calls) == 2:  # during the second epoch, before its checkpoint
            os.kill(os.getpid(), signal_number)
        return result

    monkeypatch.setattr(blurloc.train.pose, "predict_poses", validate_then_interrupt)
    out = tmp_path / "run"
    argv = ["train-pose", "--data", str(quick_root), "--scene", "chess", "--out", str(out),
            "--epochs", "3", "--resize", "32", "--crop", "28", "--window", "2",
            "--windows-per-epoch", "16", "--batch", "4", "--quiet"]  # fmt: skip
    status, err = run(argv, capsys)
    assert status == 130
    assert err.strip().splitlines() == [f"interrupted; {blurloc.cli.RESUME_TRAINING}"], err
    history = json.loads((out / "history.json").read_text())
    assert history["epoch"] == [1]  # what last.pt holds
    assert torch.load(out / "last.pt", weights_only=True)["history"] == history
    monkeypatch.setattr(blurloc.train.pose, "predict_poses", validate)
    assert main(argv) == 0  # resumed
    assert json.loads((out / "history.json").read_text())["epoch"] == [1, 2, 3]


def test_ctrl_c_in_synth_prints_one_line_from_the_whole_process_group(
    tmp_path: Path, default_interrupt: None
) -> None:
    out = tmp_path / "standin"
    command = [sys.executable, "-m", "blurloc.cli", "synth", "--out", str(out), "--quick",
               "--frames", "400", "--workers", "2", "--quiet"]  # fmt: skip
    process = subprocess.Popen(command, stderr=subprocess.PIPE, text=True,
                               start_new_session=True)  # fmt: skip
    deadline = time.monotonic() + 60
    while not list(out.glob("*/seq-*/frame-*.color.png")) and time.monotonic() < deadline:
        time.sleep(0.2)
    assert process.poll() is None, "the render ended before it could be interrupted"
    os.killpg(process.pid, signal.SIGINT)  # what Ctrl-C in a terminal does
    _, err = process.communicate(timeout=180)
    assert process.returncode == 130, err
    assert err.strip().splitlines() == [
        "interrupted; run the same command again to render it in full"
    ], err


def test_a_crop_larger_than_the_frames_is_clamped_and_recorded_clamped(
    quick_root: Path, tmp_path: Path, capsys: pytest.CaptureFixture
) -> None:
    out = tmp_path / "run"
    argv = ["train-video-deblur", "--data", str(quick_root), "--scenes", "chess", "--out",
            str(out), "--steps", "1", "--batch", "1", "--crop", "100000", "--quiet"]  # fmt: skip
    status, err = run(argv, capsys)
    assert status == 0, err
    longest = max(cv2.imread(str(next(quick_root.glob("chess/seq-*/frame-*.color.png")))).shape)
    assert err.strip() == (f"warning: --crop 100000 is larger than the training frames "
                           f"({longest} px at most); {longest} is used and recorded")  # fmt: skip
    for name in ("best.pt", "last.pt"):
        assert torch.load(out / name, weights_only=True)["train_config"]["crop"] == longest
    assert main(argv) == 0  # the same command resumes the run it recorded


# ---- one-line messages naming the option or file --------------------------------------------


def test_bad_options_and_paths_are_named_in_one_line(
    dataset: Path, tmp_path: Path, capsys: pytest.CaptureFixture
) -> None:
    sequence = dataset / "chess" / "seq-01"
    _refused(["train-pose", "--data", str(dataset), "--scene", "chess", "--out",
              str(tmp_path / "run"), "--seed", str(10**20)], "--seed", "from 0 to",
             capsys)  # fmt: skip
    with pytest.raises(SystemExit):  # not a whole number: argparse names the option
        main(["synth", "--out", str(tmp_path / "s"), "--seed", "1e20"])
    assert "argument --seed" in capsys.readouterr().err
    _refused(["blur-estimate", str(sequence)], sequence, "is a folder, not an image file", capsys)
    existing = tmp_path / "existing.png"
    existing.write_bytes(b"")
    _refused(["deblur-video", str(sequence), str(existing)], existing, "is not a folder", capsys)


def test_load_encoder_weights_names_the_file(tmp_path: Path) -> None:
    encoder = ResNetEncoder("small")
    junk = tmp_path / "junk.pt"
    junk.write_bytes(b"not a state dict")
    listed = tmp_path / "list.pt"
    torch.save([torch.zeros(1)], listed)
    cases = [(tmp_path / "none.pt", "encoder weights file is missing"),
             (junk, "not a state dict"), (listed, "not a state dict")]  # fmt: skip
    for path, reason in cases:
        with pytest.raises(ValueError, match=rf"^{path}: {reason}"):
            load_encoder_weights(encoder, path)


def test_synth_refuses_to_render_inside_a_dataset(
    dataset: Path, capsys: pytest.CaptureFixture
) -> None:
    before = snapshot(dataset)
    for out in (dataset / "chess" / "standin", dataset / "standin"):
        _refused(["synth", "--out", str(out), "--quick"], str(out), "lies inside the dataset",
                 capsys)  # fmt: skip
    assert snapshot(dataset) == before
