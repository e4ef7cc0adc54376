"""The reference answers to the notebooks' "Try it" exercises run, and their checks pass."""

from __future__ import annotations

import importlib.util
import json

from blurloc.blur import BLUR_THRESHOLD
from blurloc.config import NOTEBOOKS_DIR
from blurloc.runner import notebook_names


def _answers():
    path = NOTEBOOKS_DIR / "solutions" / "answers.py"
    spec = importlib.util.spec_from_file_location("answers", path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


answers = _answers()


def test_nb01_length_and_angle_are_read_off_the_spectrum() -> None:
    for length, (found_length, found_angle) in answers.nb01_length_and_angle().items():
        assert abs(found_length - length) < 1.0 and abs(found_angle - 30.0) < 1.5


def test_nb01_noise_fills_the_sinc_zeros() -> None:
    floor = answers.nb01_noise_floor()
    assert floor[0.02] > floor[0.005] + 1.0


def test_nb01_a_higher_threshold_flags_fewer_frames() -> None:
    flagged, scores = answers.nb01_threshold()
    assert flagged[3.0] <= flagged[BLUR_THRESHOLD]
    assert scores[-1] > scores[0]  # longer blur, higher score


def test_nb01_shrinking_the_frame_shrinks_the_blur_in_pixels() -> None:
    full, small = answers.nb01_frame_size()
    assert abs(small - 16.0 / 4) < 1.0 and full > 2 * small  # a quarter of the true 16 px


def test_nb02_the_nsr_curve_peaks_between_its_ends() -> None:
    curve = answers.nb02_nsr()
    assert curve[1e-2] > max(curve[1e-4], curve[1.0]) + 5.0


def test_nb02_linear_light_restores_blur_made_in_linear_light_better() -> None:
    found = answers.nb02_linear_light()
    assert found["linear"] > found["gamma"]


def test_nb02_mirror_padding_matches_mirror_borders() -> None:
    found = answers.nb02_boundaries()
    assert found["reflect"] > found["wrap"]


def test_nb02_short_blur_has_no_spectral_zeros() -> None:
    zeros = answers.nb02_kernel_zeros()
    assert zeros[1.5] > 0.2 and zeros[10.0] < 0.01


def test_nb00_blur_grows_with_the_exposure_and_the_resolution() -> None:
    extent = answers.nb00_exposure()
    assert 1.6 < extent[2.2] / extent[1.1] < 2.4 and 1.6 < extent[4.4] / extent[2.2] < 2.4
    larger = answers.nb00_exposure(strengths=(2.2,), size=(320, 240))[2.2]
    assert 1.6 < larger / extent[2.2] < 2.4  # twice the pixels, twice the blur in pixels


def test_nb00_a_quick_standin_has_a_mean_pose_baseline() -> None:
    (row,) = answers.nb00_baseline(route_share=0.0)
    assert row["scene"] == "heads" and row["position_m"] > 0.0 and row["nearest_ratio"] > 0.0


def test_every_try_it_item_has_a_starter_cell_with_a_check() -> None:
    for name in notebook_names():
        cells = json.loads((NOTEBOOKS_DIR / f"{name}.ipynb").read_text())["cells"]
        sources = ["".join(c["source"]) for c in cells]
        start = next(i for i, s in enumerate(sources) if s.startswith("## Try it"))
        end = next(i for i, s in enumerate(sources) if s.startswith("## What we saw"))
        code = [c for c in cells[start:end] if c["cell_type"] == "code"]
        starters = [c for c in code if "_explorer(" not in "".join(c["source"])]  # sliders
        assert starters, f"{name}: no starter cell under Try it"
        for cell in starters:
            source = "".join(cell["source"])
            assert "assert " in source, f"{name}: a starter cell without a check"
            assert len(source.splitlines()) <= 25 and "def " not in source, name
