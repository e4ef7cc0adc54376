"""Figure of single-image deblurring (notebook 02): the deblurring process of Fig. 3."""

from __future__ import annotations

import matplotlib.pyplot as plt
import numpy as np

from .style import image_axis, styled


@styled
def plot_deblurring_process(rows: list[dict]) -> plt.Figure:
    """Fig. 3, the image deblurring process, one row per example: the blurred image, its log
    spectrum with the estimated motion direction, the estimated PSF, the restored image and the
    sharp truth.

    Parameters
    ----------
    rows : list of dict
        Each with ``blurred``, ``restored``, ``sharp`` (images, float [0, 1] or uint8),
        ``spectrum`` (N, N), ``angle_deg`` (degrees), ``kernel`` (k, k), ``length_px`` (pixels)
        and ``title``.

    Returns
    -------
    matplotlib.figure.Figure

    References
    ----------
    Fig. 3 and eq. 4 of the paper.
    """
    figure, axes = plt.subplots(len(rows), 5, figsize=(13, 2.7 * len(rows)), squeeze=False)
    for row, item in zip(axes, rows, strict=True):
        image_axis(row[0], item["blurred"], f"{item['title']}: blurred")
        size = item["spectrum"].shape[0]
        row[1].imshow(item["spectrum"], cmap="viridis",
                      extent=(-size / 2, size / 2, -size / 2, size / 2))  # fmt: skip
        theta = np.radians(item["angle_deg"])
        ends = np.array([-1, 1]) * size / 2
        row[1].plot(ends * np.cos(theta), ends * np.sin(theta), "w-", lw=0.8)
        row[1].set_title(f"spectrum, motion at {item['angle_deg']:.1f}°")
        row[1].axis("off")
        row[2].imshow(item["kernel"], cmap="magma", interpolation="nearest")
        row[2].set_title(f"estimated PSF, L = {item['length_px']:.1f} px")
        row[2].axis("off")
        image_axis(row[3], item["restored"], "restored (Wiener)")
        image_axis(row[4], item["sharp"], "sharp (truth)")
    figure.suptitle("Fig. 3 · The image deblurring process (this package)")
    return figure
