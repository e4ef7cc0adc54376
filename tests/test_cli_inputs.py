"""Bad input to the commands that read and write files: an exit status of 1, a message naming
the file or option, and inputs left byte for byte as they were."""

from __future__ import annotations

import json
import os
import shutil
import signal
import subprocess
import sys
import time
from pathlib import Path

import cv2
import nbformat
import numpy as np
import psutil
import pytest

from blurloc.blur import blur_image, motion_kernel
from blurloc.cli import main
from blurloc.data import DataError, check_data, load_split, read_split
from blurloc.data.synth import LOCK_FILE, SynthConfig, synthesize
from blurloc.files import atomic_path, check_output_not_input

TINY = {"frames_per_sequence": 2, "width": 16, "height": 12}


def snapshot(folder: Path) -> dict[str, bytes]:
    """Every file under ``folder`` with its bytes."""
    return {str(p.relative_to(folder)): p.read_bytes() for p in folder.rglob("*") if p.is_file()}


def run(argv: list[str], capsys: pytest.CaptureFixture) -> tuple[int, str]:
    status = main(argv)
    return status, capsys.readouterr().err


@pytest.fixture()
def photo(tmp_path: Path) -> Path:
    """A blurred 48x40 RGB photo (PNG) in its own folder, with a second one beside it."""
    folder = tmp_path / "in"
    folder.mkdir()
    rng = np.random.default_rng(0)
    sharp = cv2.resize(rng.uniform(0, 1, (10, 12, 3)), (48, 40), interpolation=cv2.INTER_CUBIC)
    blurred = blur_image(np.clip(sharp, 0, 1), motion_kernel(5, 30), 0.002, rng=rng)
    image = np.round(np.clip(blurred, 0, 1) * 255).astype(np.uint8)
    cv2.imwrite(str(folder / "a.png"), image)
    cv2.imwrite(str(folder / "b.png"), image[::-1])
    return folder / "a.png"


# ---- outputs never overwrite inputs --------------------------------------------------------


def test_deblur_refuses_to_write_over_its_input(
    photo: Path, tmp_path: Path, capsys: pytest.CaptureFixture
) -> None:
    folder = photo.parent
    before = snapshot(folder)
    link = tmp_path / "link.png"
    link.symlink_to(photo)
    cases = [
        ([str(photo), str(photo)], "is the input"),
        ([str(photo), str(link)], "is the input"),
        ([str(folder), str(folder)], "is the input"),
        ([str(folder), str(folder / "out")], "inside the input folder"),
    ]
    for paths, reason in cases:
        status, err = run(["deblur", *paths, "--length", "5", "--angle", "30"], capsys)
        assert status == 1, paths
        assert paths[1] in err and paths[0] in err and reason in err, err
    assert snapshot(folder) == before and not (folder / "out").exists()


def test_deblur_video_and_eval_pose_refuse_an_output_that_is_an_input(
    photo: Path, tmp_path: Path, capsys: pytest.CaptureFixture
) -> None:
    folder = photo.parent
    before = snapshot(folder)
    status, err = run(["deblur-video", str(folder), str(folder)], capsys)
    assert status == 1 and f"{folder}: output is the input {folder}" in err
    model = tmp_path / "m" / "best.pt"
    model.parent.mkdir()
    model.write_bytes(b"a checkpoint")
    status, err = run(["eval-pose", "--data", str(tmp_path), "--scene", "chess",
                       "--model", str(model), "--out", str(model)], capsys)  # fmt: skip
    assert status == 1 and f"{model}: output is the input {model}" in err
    assert model.read_bytes() == b"a checkpoint" and snapshot(folder) == before


def test_check_output_not_input_allows_a_separate_output(tmp_path: Path) -> None:
    (tmp_path / "in").mkdir()
    check_output_not_input(tmp_path / "out", tmp_path / "in", None)
    check_output_not_input(tmp_path / "in.png", tmp_path / "in")  # a sibling, not inside
    with pytest.raises(ValueError, match="inside the input folder"):
        check_output_not_input(tmp_path / "in" / ".." / "in" / "x" / "y.png", tmp_path / "in")


def test_atomic_path_replaces_only_on_success(tmp_path: Path) -> None:
    target = tmp_path / "table.csv"
    target.write_text("old")
    with pytest.raises(RuntimeError), atomic_path(target) as temporary:
        assert temporary.suffix == ".csv" and temporary.parent == tmp_path
        temporary.write_text("half")
        raise RuntimeError("killed mid-write")
    assert target.read_text() == "old" and sorted(os.listdir(tmp_path)) == ["table.csv"]
    with atomic_path(target) as temporary:
        temporary.write_text("new")
    assert target.read_text() == "new" and sorted(os.listdir(tmp_path)) == ["table.csv"]
    (tmp_path / "plain.csv").write_text("")  # the mode a plain new file gets
    assert target.stat().st_mode == (tmp_path / "plain.csv").stat().st_mode


# ---- deblur: messages instead of tracebacks -----------------------------------------------


def test_deblur_bad_output_and_blur_options(
    photo: Path, tmp_path: Path, capsys: pytest.CaptureFixture
) -> None:
    before = photo.read_bytes()
    (tmp_path / "existing").mkdir()
    length = ["--length", "5", "--angle", "30"]
    cases = [
        ([str(tmp_path / "out.txt"), *length], ["out.txt", ".png"]),
        ([str(tmp_path / "out"), *length], ["out", ".png"]),
        ([str(tmp_path / "existing"), *length], ["existing", "folder"]),
        ([str(tmp_path / "o.png"), "--length", "5", "--angle", "nan"], ["--angle", "nan"]),
        ([str(tmp_path / "o.png"), "--length", "inf", "--angle", "3"], ["--length"]),
        ([str(tmp_path / "o.png"), "--length", "1e9", "--angle", "3"], ["a.png", "at most 36"]),
        ([str(tmp_path / "o.png"), "--length", "40000", "--angle", "3"], ["at most 36 px"]),
        ([str(tmp_path / "o.png"), "--nsr", "nan"], ["--nsr"]),
    ]
    for argv, names in cases:
        start = time.perf_counter()
        status, err = run(["deblur", str(photo), *argv], capsys)
        assert status == 1, argv
        assert all(name in err for name in names), (argv, err)
        assert time.perf_counter() - start < 2.0, argv
    assert photo.read_bytes() == before and not (tmp_path / "o.png").exists()
    assert sorted(p.name for p in tmp_path.iterdir()) == ["existing", "in"]  # no temporaries


@pytest.mark.parametrize(
    ("content", "message"),
    [
        (b"", "not a numeric NumPy kernel"),
        (np.array([{"a": 1}], dtype=object), "Python objects"),
        (np.ones((3, 3, 3)), "2-D"),
        (np.array([["a", "b"]]), "real numbers"),
    ],
)
def test_deblur_bad_npy_kernels_are_named(
    photo: Path, tmp_path: Path, capsys: pytest.CaptureFixture, content, message: str
) -> None:
    kernel = tmp_path / "kernel.npy"
    if isinstance(content, bytes):
        kernel.write_bytes(content)
    else:
        np.save(kernel, content, allow_pickle=True)
    status, err = run(["deblur", str(photo), str(tmp_path / "o.png"), "--kernel", str(kernel)],
                      capsys)  # fmt: skip
    assert status == 1 and f"{kernel}:" in err and message in err, err
    assert not (tmp_path / "o.png").exists()


def test_deblur_kernel_larger_than_the_image(
    photo: Path, tmp_path: Path, capsys: pytest.CaptureFixture
) -> None:
    kernel = tmp_path / "big.npy"
    np.save(kernel, np.ones((61, 61)))
    status, err = run(["deblur", str(photo), str(tmp_path / "o.png"), "--kernel", str(kernel)],
                      capsys)  # fmt: skip
    assert status == 1 and str(kernel) in err and str(photo) in err and "larger" in err


def test_deblur_keeps_16_bit_depth_and_alpha(
    photo: Path, tmp_path: Path, capsys: pytest.CaptureFixture
) -> None:
    image = cv2.imread(str(photo)).astype(np.uint16) * 257
    alpha = np.tile(np.linspace(0, 65535, 48).astype(np.uint16), (40, 1))
    deep = tmp_path / "deep.png"
    cv2.imwrite(str(deep), np.dstack([image, alpha]))
    gray = tmp_path / "gray.tif"
    cv2.imwrite(str(gray), image[..., 1])
    length = ["--length", "5", "--angle", "30"]
    assert main(["deblur", str(deep), str(tmp_path / "o.png"), *length]) == 0
    out = cv2.imread(str(tmp_path / "o.png"), cv2.IMREAD_UNCHANGED)
    assert out.dtype == np.uint16 and out.shape == (40, 48, 4)
    np.testing.assert_array_equal(out[..., 3], alpha)
    assert len(np.unique(out[..., :3])) > 256  # finer than 8-bit steps
    assert main(["deblur", str(gray), str(tmp_path / "g.tif"), *length]) == 0
    out = cv2.imread(str(tmp_path / "g.tif"), cv2.IMREAD_UNCHANGED)
    assert out.dtype == np.uint16 and out.shape == (40, 48)
    capsys.readouterr()
    assert main(["deblur", str(deep), str(tmp_path / "o.jpg"), *length]) == 0
    err = capsys.readouterr().err
    assert "warning" in err and "o.jpg" in err and str(deep) in err
    assert "16-bit depth and alpha" in err
    assert cv2.imread(str(tmp_path / "o.jpg"), cv2.IMREAD_UNCHANGED).dtype == np.uint8


# ---- synth -------------------------------------------------------------------------------


@pytest.mark.parametrize(
    "argv",
    [
        ["--frames", "1"],
        ["--width", "4"],
        ["--height", "100000"],
        ["--blur-strength", "-1"],
        ["--blur-strength", "nan"],
        ["--blur-strength", "inf"],
        ["--blur-strength", "1000"],
        ["--noise", "-1"],
        ["--noise", "nan"],
        ["--route-share", "-0.1"],
        ["--route-share", "1.5"],
        ["--exposure-gain", "0"],
        ["--optics-blur", "-0.5"],
        ["--shot-noise", "nan"],
        ["--read-noise", "2"],
        ["--jpeg-quality", "101"],
        ["--seed", "-1"],
        ["--workers", "-1"],
        ["--workers", "0"],
        ["--scenes", "kitchen"],
    ],
)
def test_synth_bad_settings_exit_1_before_writing(
    tmp_path: Path, capsys: pytest.CaptureFixture, argv: list[str]
) -> None:
    out = tmp_path / "standin"
    status, err = run(["synth", "--out", str(out), "--quick", "--quiet", *argv], capsys)
    assert status == 1 and argv[0] in err, err  # the message names the option
    assert not out.exists()


def test_synth_never_writes_into_a_foreign_folder(
    tmp_path: Path, capsys: pytest.CaptureFixture
) -> None:
    (tmp_path / "mine.txt").write_text("keep")
    status, err = run(["synth", "--out", str(tmp_path), "--quick", "--scenes", "heads",
                       "--overwrite", "--quiet"], capsys)  # fmt: skip
    assert status == 1 and "not a stand-in" in err and str(tmp_path) in err
    assert sorted(os.listdir(tmp_path)) == ["mine.txt"]


def test_rerender_with_other_settings_leaves_no_stale_frames(tmp_path: Path) -> None:
    root = tmp_path / "standin"
    first = SynthConfig.quick(frames_per_sequence=3, width=24, height=18)
    synthesize(root, ["heads", "fire"], first, workers=1, progress=False)
    (root / "deblurred").mkdir()  # something of the user's beside the scenes
    synthesize(root, ["heads"], SynthConfig.quick(**TINY), seed=1, workers=1, progress=False)
    assert not (root / "fire").exists() and (root / "deblurred").is_dir()
    assert check_data(root)["scenes"] == {
        "heads": {split: {"sequences": 1, "frames": 2} for split in ("train", "test")}
    }
    colours = list(root.rglob("*.color.png"))
    assert len(colours) == 4 and {cv2.imread(str(p)).shape for p in colours} == {(12, 16, 3)}
    assert not (root / LOCK_FILE).exists()


@pytest.fixture()
def tiny_root(tmp_path: Path) -> Path:
    return synthesize(tmp_path / "tiny", ["heads"], SynthConfig.quick(**TINY), workers=1,
                      progress=False)  # fmt: skip


def test_check_data_rejects_a_mixed_or_unfinished_stand_in(
    tiny_root: Path, capsys: pytest.CaptureFixture
) -> None:
    sequence = tiny_root / "heads" / "seq-01"
    manifest = tiny_root / "standin.json"
    original = manifest.read_text()

    # a stale frame of another render: one frame too many
    for kind in ("color.png", "pose.txt"):
        shutil.copy(sequence / f"frame-000000.{kind}", sequence / f"frame-000002.{kind}")
    status, err = run(["check-data", str(tiny_root)], capsys)
    assert status == 1 and str(sequence) in err and "records 2" in err and "standin.json" in err
    with pytest.raises(DataError, match="records 2"):
        load_split(tiny_root, "heads", "train")
    for kind in ("color.png", "pose.txt"):
        (sequence / f"frame-000002.{kind}").unlink()

    # a frame of another size
    frame = sequence / "frame-000001.color.png"
    cv2.imwrite(str(frame), np.zeros((24, 32, 3), np.uint8))
    status, err = run(["check-data", str(tiny_root)], capsys)
    assert status == 1 and str(frame) in err and "32x24" in err and "16x12" in err

    # the same without a manifest (a real-layout root): frames of one scene must agree
    manifest.unlink()
    status, err = run(["check-data", str(tiny_root)], capsys)
    assert status == 1 and str(frame) in err and "32x24" in err

    manifest.write_text('{"incomplete": true}')
    status, err = run(["check-data", str(tiny_root)], capsys)
    assert status == 1 and str(manifest) in err and "did not finish" in err
    with pytest.raises(DataError, match="did not finish"):  # what the trainers read
        load_split(tiny_root, "heads", "train")
    manifest.write_text(original)


def test_a_held_lock_is_refused_and_a_stale_one_taken_over(
    tiny_root: Path, capsys: pytest.CaptureFixture
) -> None:
    lock = tiny_root / LOCK_FILE
    lock.write_text(f"{os.getpid()}\n")  # a live process holds it
    before = snapshot(tiny_root)
    argv = ["synth", "--out", str(tiny_root), "--quick", "--scenes", "heads", "--frames", "3",
            "--width", "16", "--height", "12", "--workers", "1", "--quiet"]  # fmt: skip
    status, err = run(argv, capsys)
    assert status == 1 and str(lock) in err and f"PID {os.getpid()}" in err
    assert snapshot(tiny_root) == before
    dead = subprocess.Popen([sys.executable, "-c", "pass"])
    dead.wait()
    lock.write_text(f"{dead.pid}\n")
    assert main(argv) == 0
    assert not lock.exists()
    assert check_data(tiny_root)["scenes"]["heads"]["test"]["frames"] == 3


def test_workers_stop_when_the_parent_is_killed(tmp_path: Path) -> None:
    """kill -9 of ``blurloc synth`` ends its worker processes within a second or two."""
    out = tmp_path / "standin"
    argv = ["synth", "--out", str(out), "--quick", "--scenes", "heads", "--frames", "300",
            "--width", "16", "--height", "12", "--workers", "2", "--quiet"]  # fmt: skip
    code = f"from blurloc.cli import main; main({argv!r})"
    env = {**os.environ, "PYTHONPATH": os.pathsep.join(sys.path)}
    parent = subprocess.Popen([sys.executable, "-c", code], env=env)
    workers: list[psutil.Process] = []
    try:
        deadline = time.monotonic() + 60
        while time.monotonic() < deadline and not list(out.glob("heads/seq-0*/*.color.png")):
            time.sleep(0.1)
        assert list(out.glob("heads/seq-0*/*.color.png")), "the render did not start"
        workers = psutil.Process(parent.pid).children(recursive=True)
        assert len(workers) >= 2
        parent.send_signal(signal.SIGKILL)
        parent.wait()
        _, alive = psutil.wait_procs(workers, timeout=3)
        assert alive == []
        count = len(list(out.rglob("*.color.png")))
        time.sleep(0.5)
        assert len(list(out.rglob("*.color.png"))) == count  # nothing writes any more
    finally:
        for process in [*workers, psutil.Process(parent.pid) if parent.poll() is None else None]:
            if process is not None and process.is_running():
                process.kill()
    assert json.loads((out / "standin.json").read_text()) == {"incomplete": True}
    assert (out / LOCK_FILE).read_text().strip() == str(parent.pid)  # left by the dead render
    synthesize(out, ["heads"], SynthConfig.quick(**TINY), workers=1, progress=False)
    assert check_data(out)["scenes"]["heads"]["test"]["frames"] == 2
    assert not (out / LOCK_FILE).exists()


# ---- split files --------------------------------------------------------------------------


def test_split_files_list_each_sequence_once(
    tiny_root: Path, capsys: pytest.CaptureFixture
) -> None:
    scene = tiny_root / "heads"
    train, test = scene / "TrainSplit.txt", scene / "TestSplit.txt"
    train.write_text("sequence1\nsequence1\n")
    with pytest.raises(DataError, match=r"TrainSplit\.txt:2: sequence1 is listed twice"):
        read_split(scene, "train")
    train.write_text("sequence1\nsequence2\n")
    with pytest.raises(DataError, match=r"TrainSplit\.txt: sequence\(s\) \[2\] are listed in "
                                        r"TestSplit\.txt too"):  # fmt: skip
        read_split(scene, "train")
    status, err = run(["check-data", str(tiny_root)], capsys)
    assert status == 1 and str(train) in err and "TestSplit.txt" in err
    assert test.read_text() == "sequence2\n"


# ---- run-notebooks ------------------------------------------------------------------------


def test_a_failing_notebook_is_named_with_its_cell(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture
) -> None:
    notebooks = tmp_path / "notebooks"
    notebooks.mkdir()
    notebook = nbformat.v4.new_notebook()
    notebook.cells = [nbformat.v4.new_code_cell("x = 1"),
                      nbformat.v4.new_code_cell("raise KeyError('no such scene')")]  # fmt: skip
    notebook.metadata["kernelspec"] = {"name": "python3", "display_name": "Python 3",
                                       "language": "python"}  # fmt: skip
    nbformat.write(notebook, notebooks / "99_fails.ipynb")
    monkeypatch.setenv("BLURLOC_ROOT", str(tmp_path))
    status, err = run(["run-notebooks", "--quick", "99_fails"], capsys)
    assert status == 1
    assert "99_fails.ipynb" in err and "KeyError: 'no such scene'" in err
    assert "In [3]" in err and "raise KeyError" in err  # In [1] is papermill's parameters
    assert "Traceback" not in err and len(err.strip().splitlines()) == 1
