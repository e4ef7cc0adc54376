"""Figures: what each draws (axes, lines, reference values), the style applied per figure only,
and the tables beside them."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np
import pytest

from blurloc import plots
from blurloc.data import load_split
from blurloc.data.samples import blur_range_frames, camera_paths, first_test_frames
from blurloc.plots.style import STYLE
from blurloc.tables import save_table


@pytest.fixture(autouse=True)
def _close_figures():
    yield
    plt.close("all")


def test_importing_plots_leaves_matplotlib_settings_alone() -> None:
    code = ("import matplotlib, copy; before = copy.deepcopy(dict(matplotlib.rcParams)); "
            "import blurloc.plots; assert dict(matplotlib.rcParams) == before")  # fmt: skip
    subprocess.run([sys.executable, "-c", code], check=True)


def test_the_style_holds_inside_a_figure_only() -> None:
    records = [{"mean_px": float(v)} for v in np.linspace(0.5, 12.0, 40)]
    figure = plots.plot_blur_histogram(records, thresholds=(3.0, 8.0))
    axis = figure.axes[0]
    assert not axis.spines["top"].get_visible() and axis.xaxis.get_gridlines()[0].get_visible()
    assert plt.rcParams["axes.spines.top"]  # the global default is back
    assert figure.dpi == STYLE["figure.dpi"]
    extent = np.array([r["mean_px"] for r in records])
    verticals = sorted(line.get_xdata()[0] for line in axis.lines)
    expected = sorted([np.median(extent), np.percentile(extent, 90), 3.0, 8.0])
    np.testing.assert_allclose(verticals, expected)
    assert sum(patch.get_height() for patch in axis.patches) == len(records)


def test_save_figure_writes_png_and_a_reproducible_pdf(tmp_path: Path) -> None:
    figure = plots.plot_kernels({"a": np.eye(5), "b": np.ones((5, 5)) / 25, "c": np.eye(5)})
    assert len(figure.axes) == 3 and [a.get_title() for a in figure.axes] == ["a", "b", "c"]
    png, pdf, alt = plots.save_figure(figure, tmp_path / "one", "kernels")
    plots.save_figure(figure, tmp_path / "two", "kernels", alt="three kernels")
    assert png.read_bytes()[:4] == b"\x89PNG"
    assert pdf.read_bytes() == (tmp_path / "two" / "kernels.pdf").read_bytes()
    assert alt == "Panels: a; b; c."
    assert plt.fignum_exists(figure.number)  # outside a notebook the figure stays open


def test_describe_figure_reads_the_titles_and_labels() -> None:
    figure, axes = plt.subplots(1, 2)
    axes[0].set(title="length", xlabel="recorded (px)", ylabel="estimated (px)")
    axes[1].set(title="angle")
    figure.suptitle("Blind estimation\non frames")
    assert plots.describe_figure(figure) == (
        "Blind estimation on frames. Panels: length (x: recorded (px), y: estimated (px)); angle."
    )
    assert plots.describe_figure(plt.figure()) == "A figure."
    plt.close("all")


def test_reference_lines_are_at_the_given_values() -> None:
    history = {"step": [1, 2, 3], "train_loss": [0.3, 0.2, 0.1], "val_psnr": [25, 26, 27]}
    figure = plots.plot_training_curves({"net": history, "other": history}, reference_db=24.5)
    loss_axis, psnr_axis = figure.axes
    assert len(loss_axis.lines) == 2
    assert list(psnr_axis.lines[-1].get_ydata()) == [24.5, 24.5]
    figure = plots.plot_ratios({"fig6": [0.9, 1.1], "table1": [2.0, 0.5, 1.0]}, "ratios")
    axis = figure.axes[0]
    assert axis.get_yscale() == "log"
    assert list(axis.lines[-1].get_ydata()) == [1.0, 1.0]
    assert [len(line.get_xdata()) for line in axis.lines[:-1]] == [2, 3]
    rng = np.random.default_rng(0)
    scores = {"train": (rng.normal(size=50), rng.random(50) > 0.5)}
    figure = plots.plot_detection(scores, threshold=0.25)
    assert figure.axes[0].lines[-1].get_xdata()[0] == 0.25


def test_motion_agreement_titles_carry_each_measures_rank_correlation() -> None:
    motion = np.array([1.0, 4.0, 2.0, 8.0])
    measures = {"length": motion**2, "sharpness": -motion}
    figure = plots.plot_motion_agreement(measures, motion, "frames")
    titles = [axis.get_title() for axis in figure.axes]
    assert titles == ["length: ρ = 1.00", "sharpness: ρ = -1.00"]
    assert [len(axis.collections[0].get_offsets()) for axis in figure.axes] == [4, 4]
    plt.close(figure)


def test_estimation_accuracy_plots_medians_per_sweep_value() -> None:
    rows = [
        {
            "length_px": length,
            "noise_sigma": sigma,
            "angle_error_deg": float(i % 3),
            "length_error_px": 0.5,
        }
        for i, (length, sigma) in enumerate(
            (L, s) for L in (7, 15, 27) for s in (0.0, 0.005) for _ in range(3)
        )
    ]
    figure = plots.plot_estimation_accuracy(rows, noise_for_length=0.005)
    assert _overlapping_texts(figure) == []
    against_length, against_noise = figure.axes
    median_angle = against_length.lines[0]
    assert list(median_angle.get_xdata()) == [7, 15, 27]
    assert list(against_noise.lines[1].get_ydata()) == [0.5, 0.5]  # median length error
    assert {tuple(line.get_ydata()) for line in against_length.lines[2:]} == {
        (1.5, 1.5),
        (1.0, 1.0),
    }


def test_per_scene_bars_and_error_distributions() -> None:
    paper = {"chess": 30.0, "fire": 29.0}
    measured = {"blind_wiener": {"chess": 28.0, "fire": 27.5},
                "blurred": {"chess": 26.0, "fire": 25.0}}  # fmt: skip
    figure = plots.plot_per_scene_metric(measured, paper, "PSNR (dB)", "title")
    axis = figure.axes[0]
    assert len(axis.containers) == 3
    printed = axis.containers[-1]
    assert [bar.get_height() for bar in printed] == [30.0, 29.0]
    assert all(bar.get_hatch() == "//" for bar in printed)
    errors = {"chess": {"blurred": np.arange(5.0), "rnn": np.arange(5.0) / 2},
              "fire": {"blurred": np.ones(4), "rnn": np.ones(4)}}  # fmt: skip
    figure = plots.plot_error_distributions(errors, title="Fig. 10")
    assert len(figure.axes) == 1 and figure.get_suptitle() == "Fig. 10"
    figure = plots.plot_error_distributions(errors, {"paper LSTM": {"chess": 30.0, "fire": 29.5}})
    assert len(figure.axes) == 2
    assert [axis.get_ylim()[0] for axis in figure.axes] == [0, 0]  # bars compared from zero
    assert [bar.get_height() for bar in figure.axes[1].containers[0]] == [30.0, 29.5]


def test_pose_training_curves_and_predicted_paths() -> None:
    histories = {"lstm": {"epoch": [1, 2, 3], "train_loss": [3.0, 2.0, 1.5],
                          "val_position_m": [0.9, 0.7, 0.6]},
                 "none": {"epoch": [1, 2, 3], "train_loss": [3.1, 2.5, 2.2],
                          "val_position_m": [1.0, 0.95, 0.9]}}  # fmt: skip
    figure = plots.plot_pose_training_curves(histories)
    loss, position = figure.axes
    assert [line.get_label() for line in position.get_lines()] == ["lstm", "none"]
    assert list(loss.get_lines()[1].get_ydata()) == [3.1, 2.5, 2.2]
    assert list(position.get_lines()[0].get_ydata()) == [0.9, 0.7, 0.6]
    truth = np.cumsum(np.ones((5, 3)), axis=0)
    paths = {"lstm": truth + 0.1, "none": truth - 0.2}
    figure = plots.plot_predicted_paths(truth, paths, {"lstm": "a", "none": "b"})
    assert [axis.get_title() for axis in figure.axes] == ["a", "b"]
    for axis in figure.axes:
        assert (axis.get_xlabel(), axis.get_ylabel(), axis.get_zlabel()) == (
            "x (m)",
            "y (m)",
            "z (m)",
        )
    true_line, predicted = figure.axes[1].get_lines()
    assert np.allclose(true_line.get_data_3d(), truth.T)
    assert np.allclose(predicted.get_data_3d(), paths["none"].T)


def test_standin_figures_draw_the_frames_they_are_given(quick_root: Path) -> None:
    frames = first_test_frames(quick_root)
    figure = plots.plot_scene_gallery(frames)
    shown = [axis for axis in figure.axes if axis.images]
    assert [axis.get_title() for axis in shown] == list(frames) == ["chess", "stairs"]
    assert np.array_equal(shown[0].images[0].get_array(), frames["chess"])
    paths = camera_paths(quick_root)
    figure = plots.plot_trajectories(paths)
    assert len(figure.axes) == 2
    assert [axis.get_zlabel() for axis in figure.axes] == ["z (m)", "z (m)"]
    first_path = figure.axes[0].lines[0].get_data_3d()[0]
    np.testing.assert_allclose(first_path, paths["chess"]["train"][0][:, 0])
    records = [{"split": "test", "scene": "chess", "sequence": s.number, "frame": f,
                "mean_px": float(f), "angle_deg": 10.0}
               for s in load_split(quick_root, "chess", "test") for f in s.frame_ids]  # fmt: skip
    picks, sharp, blurred = blur_range_frames(quick_root, records, count=3)
    assert [p["mean_px"] for p in picks] == sorted(p["mean_px"] for p in picks)
    figure = plots.plot_blur_pairs(picks, sharp, blurred)
    assert len(figure.axes) == 6
    assert np.array_equal(figure.axes[0].images[0].get_array(), sharp[0])
    assert np.array_equal(figure.axes[3].images[0].get_array(), blurred[0])


def test_save_table_writes_markdown_and_csv(tmp_path: Path) -> None:
    rows = [{"scene": "chess", "psnr_db": 28.5, "extra": 1}, {"scene": "fire", "psnr_db": 27.0}]
    md, csv_path = save_table(rows, tmp_path, "t", columns=["scene", "psnr_db"], caption="Cap.")
    assert md.read_text() == ("Cap.\n\n| scene | psnr_db |\n|---|---|\n| chess | 28.5 |\n"
                              "| fire | 27.0 |\n")  # fmt: skip
    assert csv_path.read_text().splitlines() == ["scene,psnr_db", "chess,28.5", "fire,27.0"]


def _overlapping_texts(figure: plt.Figure) -> list[tuple[str, str]]:
    """Pairs of visible, non-empty titles, axis labels and figure texts whose drawn extents
    overlap."""
    renderer = figure.canvas.get_renderer()
    figure.draw_without_rendering()
    texts = list(figure.texts)  # the suptitle among them
    for axis in figure.axes:
        texts += [axis.title, axis._left_title, axis._right_title, axis.xaxis.label,
                  axis.yaxis.label, *axis.texts]  # fmt: skip
    shown = [t for t in texts if t.get_visible() and t.get_text().strip()]
    boxes = [t.get_window_extent(renderer) for t in shown]
    return [(shown[i].get_text(), shown[j].get_text())
            for i in range(len(shown)) for j in range(i + 1, len(shown))
            if boxes[i].overlaps(boxes[j])]  # fmt: skip


def test_paired_differences_and_dose_response_texts_do_not_overlap() -> None:
    rows = [{"comparison": c, "metric": m, "baseline_mean": 1.0, "mean_difference": d,
             "ci_low": d - 0.1, "ci_high": d + 0.1, "interval": "95% bootstrap", "verdict": ""}
            for c, d in (("rnn - blurred", -0.05), ("wiener - blurred", 0.2))
            for m in ("position_m_median", "orientation_deg_median", "combined")]  # fmt: skip
    figure = plots.plot_paired_differences(rows, "Pose error: paired differences")
    assert _overlapping_texts(figure) == []
    table = [{"frame_median_blur_px": b, "blurred_position_m": 0.3, "deblurred_position_m": 0.31,
              "position_difference_m": 0.01, "position_ci_low": -0.02, "position_ci_high": 0.04,
              "orientation_difference_deg": -0.5, "orientation_ci_low": -1.0,
              "orientation_ci_high": 0.1} for b in (0.0, 1.5, 3.0, 6.0)]  # fmt: skip
    figure = plots.plot_dose_response(
        table, "Pose error against blur strength, chess (LSTM, blurred vs network-deblurred input)"
    )
    assert _overlapping_texts(figure) == []
    assert list(figure.axes[1].lines[-1].get_ydata()) == [0, 0]


def test_attention_texts_do_not_overlap() -> None:
    frame = np.zeros((30, 40, 3))
    figure = plots.plot_attention(frame, np.full((8, 10), 0.5), frame)
    assert _overlapping_texts(figure) == []
    assert figure.axes[1].images[0].get_clim() == (0, 1)


def test_video_network_diagram_uses_math_text_and_draws_the_recurrent_inputs() -> None:
    figure = plots.plot_video_network({"blurred": [np.zeros((6, 8, 3))] * 2})
    diagram = figure.axes[0]
    texts = [text.get_text() for text in diagram.texts]
    assert not any("~" in text for text in texts)  # tildes as math text, not ASCII
    assert all("$" in text for text in texts if "_" in text)  # subscripts as math text
    for state in ("$h_{t-1}$", r"$\tilde h_{t-1}$", r"$\tilde f_{t-1}$"):
        assert state in texts  # eq. 8-10: the inputs from the previous step
    assert _overlapping_texts(figure) == []
    assert len(figure.axes) == 3 and figure.axes[2].images


def test_fig4_zooms_every_row_into_the_window_where_the_frames_differ_most() -> None:
    sharp = np.zeros((12, 16, 3))
    blurred = sharp.copy()
    blurred[7:10, 2:6] = 0.5  # the only change, inside rows 7-9, columns 2-5
    window = plots.largest_difference_window(sharp, blurred, (4, 5))
    top, left, height, width = window
    assert (height, width) == (4, 5) and top <= 7 and top + 4 >= 10 and left <= 2 and left + 5 >= 6
    with pytest.raises(ValueError, match="window"):
        plots.largest_difference_window(sharp, blurred, (13, 5))
    figure = plots.plot_video_network({"blurred": [blurred] * 2, "sharp": [sharp] * 2},
                                      windows=[window, window])  # fmt: skip
    panels = figure.axes[1:]
    assert len(panels) == 6  # whole frames, then the two zoomed rows
    assert panels[0].images[0].get_array().shape == (12, 16, 3) and panels[0].patches
    assert [p.images[0].get_array().shape for p in panels[2:]] == [(4, 5, 3)] * 4
    assert panels[2].get_ylabel() == "blurred\n(zoom)"
    plt.close(figure)


def test_pipeline_draws_the_reference_apart_from_the_chain() -> None:
    panels = [{"image": np.zeros((6, 8)), "title": name} for name in ("blurred", "Wiener")]
    path = np.cumsum(np.ones((4, 3)), axis=0)
    sharp = {"image": np.ones((6, 8)), "title": "sharp (truth)"}
    figure = plots.plot_pipeline(panels, path, path + 0.1, reference=sharp)
    chain = figure.axes[:3]
    *_, pose, shown = figure.axes
    assert pose.get_title().startswith("pose") and shown.get_title().startswith("reference")
    assert np.array_equal(shown.images[0].get_array(), sharp["image"])
    joined = [(arrow.axesA, arrow.axesB) for arrow in figure.artists]
    assert joined == [(chain[0], chain[1]), (chain[1], chain[2])]  # no arrow to the reference
    assert len(plots.plot_pipeline(panels, path, path).axes) == 3


def test_predicted_views_show_each_scene_with_its_caption_and_a_wrapped_title() -> None:
    views = {s: {"input": np.zeros((6, 8, 3)), "rendered": np.ones((6, 8, 3))} for s in "ab"}
    title = "Fig. 5 · " + "a long title of the figure " * 4
    figure = plots.plot_predicted_views(views, {"a": "0.31 m, 5.4°", "b": "x"}, title=title)
    axes = np.array(figure.axes).reshape(2, 2)
    assert [axis.get_title() for axis in axes[0]] == ["a", "b"]
    assert axes[1, 0].get_xlabel() == "0.31 m, 5.4°"
    assert figure.get_suptitle().replace("\n", " ") == title.strip()
    assert max(len(line) for line in figure.get_suptitle().split("\n")) <= 32
    assert _overlapping_texts(figure) == []


def _labelled(axis: plt.Axes) -> bool:
    return bool(axis.get_xlabel() and axis.get_ylabel() and axis.get_title())


def test_restorations_draw_one_panel_per_method_and_noise_level() -> None:
    image = np.linspace(0, 1, 64 * 64).reshape(64, 64)
    methods = ("blurred", "inverse", "Wiener")
    rows = [{"noise_sigma": s, "method": m, "image": image, "psnr_db": 30.0 + i}
            for s in (0.0, 0.01) for i, m in enumerate(methods)]  # fmt: skip
    figure = plots.plot_restorations(rows, "Restorations of a ramp")
    assert len(figure.axes) == 6
    assert figure.axes[5].get_title() == "Wiener\nσ = 0.01: 32.0 dB"
    assert figure.get_suptitle() == "Restorations of a ramp"
    without_noise = plots.plot_restorations([{k: v for k, v in r.items() if k != "noise_sigma"}
                                             for r in rows[:3]], "t")  # fmt: skip
    assert len(without_noise.axes) == 3 and without_noise.axes[0].get_title() == "blurred\n30.0 dB"
    assert not _overlapping_texts(figure)


def test_nsr_curve_marks_the_estimate_and_the_blurred_input() -> None:
    curve = {"nsr": np.logspace(-4, 0, 5), "psnr_db": np.array([20, 24, 26, 23, 21.0]),
             "estimated_nsr": 0.02, "blurred_psnr_db": 22.5}  # fmt: skip
    figure = plots.plot_nsr_curve(curve, "Wiener on a test image")
    (axis,) = figure.axes
    assert _labelled(axis) and axis.get_xscale() == "log"
    np.testing.assert_allclose(axis.lines[0].get_ydata(), curve["psnr_db"])
    assert axis.lines[1].get_xdata()[0] == 0.02 and axis.lines[2].get_ydata()[0] == 22.5
    assert not _overlapping_texts(figure)


def test_oracle_gains_draw_bars_and_frame_scatters() -> None:
    summary = [
        {"variant": v, "gain_db": g, "gain_ci95_db": 0.3, "frames": 4}
        for v, g in (("blurred", 0.0), ("blind", -1.2), ("path_linear_best", 0.8))
    ]
    points = {"blind": (np.array([1.0, 5.0]), np.array([-2.0, 0.5])),
              "path_linear_best": (np.array([1.0, 5.0]), np.array([-0.5, 2.0]))}  # fmt: skip
    figure = plots.plot_oracle_gains(summary, points)
    assert len(figure.axes) == 2 and all(_labelled(a) for a in figure.axes)
    assert [p.get_width() for p in figure.axes[0].patches] == [0.0, -1.2, 0.8]
    assert len(figure.axes[1].collections) == 2
    assert not _overlapping_texts(figure)


def test_skimage_comparison_draws_rule_and_oracle_gains_per_kernel_kind() -> None:
    rows = [{"kernel": k, "noise_sigma": 0.01, "blurred_db": b, "ours_db": b + 2,
             "best_nsr_db": b + 2.5, "skimage_best_balance_db": b + 1,
             "skimage_padded_db": b + 3} for k in ("line", "camera shake")
            for b in (20.0, 38.0)]  # fmt: skip
    figure = plots.plot_skimage_comparison(rows)
    assert len(figure.axes) == 2 and _labelled(figure.axes[0])
    rule, oracle, padded = figure.axes[1].collections
    np.testing.assert_allclose(rule.get_offsets(), [[20.0, 1.0], [38.0, 1.0]])
    np.testing.assert_allclose(oracle.get_offsets()[:, 1], [1.5, 1.5])
    np.testing.assert_allclose(padded.get_offsets()[:, 1], [-1.0, -1.0])
    assert "σ = 0.01" in figure.get_suptitle()
    assert not _overlapping_texts(figure)


def test_standin_estimation_draws_the_camera_frames_only() -> None:
    rows = [{"kind": k, "extent_px": e, "estimated_length_px": e + 0.5, "angle_error_deg": 3.0}
            for k, e in (("color", 2.0), ("color", 6.0), ("sharp", 0.0))]  # fmt: skip
    figure = plots.plot_standin_estimation(rows)
    assert len(figure.axes) == 2 and all(_labelled(a) for a in figure.axes)
    assert all(len(a.collections[0].get_offsets()) == 2 for a in figure.axes)
    assert "2 stand-in frames" in figure.get_suptitle()
    assert not _overlapping_texts(figure)


def test_figure_style_keeps_the_interactive_mode_a_backend_sets_inside() -> None:
    """A notebook's inline backend turns interactive mode on when the first figure loads it,
    inside the style; restoring the old mode on exit would hide every later figure."""
    from blurloc.plots import figure_style

    before = matplotlib.is_interactive()
    try:
        matplotlib.interactive(False)
        with figure_style():
            assert plt.rcParams["font.size"] == 9
            matplotlib.interactive(True)
        assert matplotlib.is_interactive()
    finally:
        matplotlib.interactive(before)


def test_a_saved_table_shows_as_its_markdown(tmp_path: Path) -> None:
    saved = save_table([], tmp_path, "empty", columns=["scene", "psnr_db"], caption="None yet.")
    assert saved._repr_markdown_() == "None yet.\n\n| scene | psnr_db |\n|---|---|\n"
    assert saved.csv.read_text().splitlines() == ["scene,psnr_db"]
    assert not [p.name for p in tmp_path.iterdir() if p.name.startswith(".")]  # no temporaries
