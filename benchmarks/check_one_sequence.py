"""Do the pose regressor's defaults learn from one 7-Scenes-length recording at 640x480?

    python benchmarks/check_one_sequence.py [--scenes heads fire] [--sequence 1] [--seeds 3]
                                            [--work /tmp/one] [--route-share 0] [--epochs N]
                                            [--blocks 5] [--out-dir figures]

A user with one real 1000-frame 7-Scenes sequence cuts it into 800 training and 200 test frames and
runs ``blurloc train-pose`` with its defaults (blurred input, LSTM head, the reader resizing each
640x480 frame to a 64 px short side). This check does the same on stand-in sequences rendered at
640x480 (``--sequence`` of each scene, default 1; 1000 frames, stairs 500, cut 400/100): it renders
them (8-9 core-minutes per 1000 frames; kept under ``--work`` and not re-rendered), cuts them with
:func:`blurloc.data.split_one_sequence`, trains with the command line's defaults for each seed, and
prints the median test errors beside the mean-pose baseline (the mean training position and rotation
predicted for every test frame) and the nearest-view oracle (the training pose nearest to each test
pose: how far the test views lie from the training views). The bar: about half the mean-pose error
in position and clearly less in orientation.
``--route-share`` sets how much of the recording follows its scene's shared route
(:func:`blurloc.data.synth.scene_route`; default that of :class:`~blurloc.data.synth.SynthConfig`);
use a fresh ``--work`` for each value and each ``--sequence``. ``--blocks 5`` cuts the recording
into five blocks and each block 80/20 (:func:`blurloc.data.split_one_sequence`), so that the test
views lie between training views: where the regressor misses the bar with the plain cut but
meets it with the blocks, the test views' place in the recording, not the network, is what
limits it (the blocks' cut and models are kept apart from the plain cut's under ``--work``).
Not part of ``make reproduce`` (the 640x480 render alone exceeds its budget); docs/results.md
("What reproduced, in numbers", the row on one 7-Scenes-length recording) records the last run.
The table goes to ``<out-dir>/check_one_sequence-seq<sequence>-<scenes>[-<blocks>-blocks].md``/
``.csv`` (one file per sequence, scenes and cut, so runs with other settings do not overwrite it).
"""

from __future__ import annotations

import argparse
import subprocess
import sys
import time
from pathlib import Path

import numpy as np

from blurloc.data import split_one_sequence
from blurloc.data.synth import SynthConfig, render_sequence
from blurloc.experiments.pose import (
    mean_pose_baseline,
    nearest_view_baseline,
    predict_test_frames,
)
from blurloc.tables import add_out_dir_argument, save_benchmark_tables
from blurloc.train.loop import parallel_map

RENDER_SEED = 0
BLURLOC = Path(sys.executable).with_name("blurloc")  # the command line, as a user runs it


def _render(job: tuple[Path, str, int, SynthConfig]) -> str:
    """Render one sequence of one scene unless its blur.csv (written last) is already there."""
    root, scene, number, config = job
    if not (root / scene / f"seq-{number:02d}" / "blur.csv").is_file():
        render_sequence(root, scene, number, config, RENDER_SEED)
    return scene


def main() -> None:
    """Render, cut, train and print the table."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--scenes", nargs="+", default=["heads", "fire"])
    parser.add_argument("--sequence", type=int, default=1, help="sequence number rendered")
    parser.add_argument("--seeds", type=int, default=3)
    parser.add_argument("--epochs", type=int, help="passed to train-pose (default: its own)")
    parser.add_argument("--work", type=Path, default=Path("/tmp/one-sequence"))
    parser.add_argument("--blocks", type=int, default=1, help="blocks, each cut 80/20")
    parser.add_argument("--route-share", type=float, default=SynthConfig().route_share,
                        help="part of the walk on the scene's shared route")  # fmt: skip
    add_out_dir_argument(parser)
    args = parser.parse_args()
    config = SynthConfig(width=640, height=480, route_share=args.route_share)
    render_root = args.work / "render"
    start = time.perf_counter()
    jobs = [(render_root, scene, args.sequence, config) for scene in args.scenes]
    list(parallel_map(_render, jobs, workers=min(2, len(jobs))))
    print(f"rendered in {time.perf_counter() - start:.0f} s", flush=True)

    rows = []
    for scene in args.scenes:
        frames = config.frames_for(scene)
        suffix = "" if args.blocks == 1 else f"-{args.blocks}-blocks"
        cut_root, models_root = args.work / f"cut{suffix}", args.work / f"models{suffix}"
        if not (cut_root / scene).is_dir():
            split_one_sequence(render_root / scene / f"seq-{args.sequence:02d}", cut_root, scene,
                               frames * 4 // 5, blocks=args.blocks)  # fmt: skip
        baseline = mean_pose_baseline(cut_root, scene)
        nearest = nearest_view_baseline(cut_root, scene)
        base, near = baseline["position_m"]["median"], nearest["position_m"]["median"]
        print(f"{scene}: mean pose {base:.3f} m / {baseline['orientation_deg']['median']:.1f}°; "
              f"nearest training view (oracle) {near:.3f} m / "
              f"{nearest['orientation_deg']['median']:.1f}°", flush=True)  # fmt: skip
        for seed in range(args.seeds):
            out = models_root / f"{scene}-seed{seed}"
            start = time.perf_counter()
            command = [str(BLURLOC), "train-pose", "--data", str(cut_root), "--scene", scene,
                       "--out", str(out), "--seed", str(seed), "--quiet"]  # fmt: skip
            if args.epochs is not None:
                command += ["--epochs", str(args.epochs)]
            subprocess.run(command, check=True)
            seconds = time.perf_counter() - start
            predicted = predict_test_frames(out / "best.pt", cut_root, scene)
            rows.append({
                "scene": scene, "seed": seed,
                "position_m": round(float(np.median(predicted["position_error"])), 3),
                "orientation_deg": round(float(np.median(predicted["orientation_error"])), 2),
                "baseline_position_m": round(base, 3),
                "baseline_orientation_deg": round(baseline["orientation_deg"]["median"], 1),
                "nearest_position_m": round(near, 3),
                "nearest_orientation_deg": round(nearest["orientation_deg"]["median"], 1),
                "training_s": round(seconds),
            })  # fmt: skip
            print(rows[-1], flush=True)

    for row in rows:
        row["position_ratio"] = round(row["position_m"] / row["baseline_position_m"], 2)
        row["orientation_ratio"] = round(row["orientation_deg"] / row["baseline_orientation_deg"],
                                         2)  # fmt: skip
    stem = f"check_one_sequence-seq{args.sequence}-{'-'.join(args.scenes)}"
    saved = save_benchmark_tables(
        stem if args.blocks == 1 else f"{stem}-{args.blocks}-blocks",
        {"seeds": rows},
        args.out_dir,
        f"train-pose defaults on one 640x480 recording per scene (sequence {args.sequence}, cut "
        f"800/200 in {args.blocks} block(s)) against its mean-pose baseline and the nearest-view "
        "oracle",
        notes=f"Route share {args.route_share}; epochs {args.epochs or 'train-pose default'}.",
    )
    print("\n" + saved.markdown.read_text())
    for scene in args.scenes:
        mine = [r for r in rows if r["scene"] == scene]
        position = np.mean([r["position_ratio"] for r in mine])
        orientation = np.mean([r["orientation_ratio"] for r in mine])
        print(f"{scene}: mean over {len(mine)} seeds {position:.2f}x position, "
              f"{orientation:.2f}x orientation of the mean-pose baseline")  # fmt: skip


if __name__ == "__main__":
    main()
