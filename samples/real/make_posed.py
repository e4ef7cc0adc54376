"""Write the development set's posed frames from a TUM RGB-D recording's folder.

The colour frames are byte copies; each frame's 4x4 camera-to-world pose is the ground truth
at the frame's stamp (position interpolated linearly, rotation by slerp between the two
nearest ground-truth samples: ``blurloc.data.tum.pose_at``); ``frames.csv`` records each
frame's stamp, source file, the nearest depth image's stamp and its median valid depth
(metres, ``depth / 5000``). The first ``--frames`` frames from ``--start`` go to ``seq-01``
(training split), the next as many to ``seq-02`` (test split). Run once by whoever rebuilds
the set; the manifest's sha256 column then records the written files::

    python samples/real/make_posed.py SOURCE/data samples/real/posed/fr1_rpy \\
        --start 1305031230.865523 --frames 40
"""

from __future__ import annotations

import argparse
import csv
import shutil
from pathlib import Path

import cv2
import numpy as np

from blurloc.data.tum import pose_at, read_groundtruth, read_stamped, write_pose

FR1_INTRINSICS = (
    "# fx fy cx cy\n517.3 516.5 318.6 255.3\n"
    "# k1 k2 p1 p2 k3\n0.2624 -0.9531 -0.0054 0.0026 1.1633\n"
)


def main() -> None:
    """Write ``seq-01``, ``seq-02``, the split files, ``frames.csv`` and ``intrinsics.txt``."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument(
        "source", type=Path, help="the recording's folder (rgb.txt, depth.txt, groundtruth.txt)"
    )
    parser.add_argument("out", type=Path)
    parser.add_argument("--start", type=float, required=True, help="TUM stamp of the first frame")
    parser.add_argument("--frames", type=int, default=40, help="frames per sequence")
    args = parser.parse_args()
    stamps, rows = read_groundtruth(args.source / "groundtruth.txt")
    depth = [(float(s), f) for s, f in read_stamped(args.source / "depth.txt")]
    depth_stamps = np.array([s for s, _ in depth])
    colour = [
        (s, f) for s, f in read_stamped(args.source / "rgb.txt") if float(s) >= args.start - 1e-6
    ]
    table = []
    for index, (stamp, name) in enumerate(colour[: 2 * args.frames]):
        sequence = f"seq-0{1 + index // args.frames}"
        frame = f"frame-{index % args.frames:06d}"
        folder = args.out / sequence
        folder.mkdir(parents=True, exist_ok=True)
        shutil.copyfile(args.source / name, folder / f"{frame}.color.png")
        write_pose(folder / f"{frame}.pose.txt", pose_at(stamps, rows, float(stamp)))
        nearest = int(np.argmin(np.abs(depth_stamps - float(stamp))))
        image = cv2.imread(str(args.source / depth[nearest][1]), cv2.IMREAD_UNCHANGED)
        median = float(np.median(image[image > 0])) / 5000.0
        table.append(
            [
                f"{sequence}/{frame}.color.png",
                sequence,
                stamp,
                name,
                f"{depth_stamps[nearest]:.6f}",
                f"{median:.4f}",
            ]
        )
    with (args.out / "frames.csv").open("w", newline="") as handle:
        writer = csv.writer(handle, lineterminator="\n")
        writer.writerow(["frame", "sequence", "stamp", "source", "depth_stamp", "depth_median_m"])
        writer.writerows(table)
    (args.out / "TrainSplit.txt").write_text("sequence1\n")
    (args.out / "TestSplit.txt").write_text("sequence2\n")
    (args.out / "intrinsics.txt").write_text(FR1_INTRINSICS)


if __name__ == "__main__":
    main()
