"""The error figures of SPEC §10 on numpy arrays (mrr.rms, ssim, psnr, flip): the report's own
numbers, known values, and one ValueError for arrays that do not fit."""
import numpy as np
import pytest

import mrr
from conftest import SAMPLES, SIZE


def test_the_reports_error_against_full(demo):
    f = mrr.Frame(demo, effect="ssao", size=SIZE, samples=SAMPLES).render(reference=True)
    full = mrr.Frame(demo, effect="ssao", method="full", size=SIZE, samples=SAMPLES).render()
    error = f.report["error_vs_full"]
    assert mrr.rms(f["final"], full["final"]) == error["rms"]
    assert mrr.ssim(f["final"], full["final"]) == error["ssim"]
    stats, flip_map = mrr.flip(f["final"], full["final"])
    assert stats == error["flip"]
    assert flip_map.shape == f["final"].shape and flip_map.dtype == np.float32


def test_known_values():
    a = np.zeros((16, 16), np.float32)
    b = np.full((16, 16), 0.5, np.float32)
    assert mrr.rms(a, a) == 0.0
    assert mrr.rms(a, b) == pytest.approx(0.5)
    assert mrr.ssim(b, b) == pytest.approx(1.0)
    assert mrr.psnr(a, b) == pytest.approx(10 * np.log10(1 / 0.25))
    assert mrr.flip(b, b)[0]["mean"] == 0.0
    rgb = np.random.default_rng(1).random((16, 16, 3))  # float64, three channels: converted
    assert mrr.rms(rgb, rgb) == 0.0


@pytest.mark.parametrize("test, ref, words", [
    (np.zeros((4, 4)), np.zeros((4, 5)), "differ in shape"),
    (np.zeros(4), np.zeros(4), r"shape \(4,\)"),
    (np.zeros((4, 4), np.complex64), np.zeros((4, 4)), "dtype complex64"),
    ("an image", np.zeros((4, 4)), "expected a numpy array"),
])
def test_arrays_that_do_not_fit(test, ref, words):
    with pytest.raises(ValueError, match=words):
        mrr.rms(test, ref)
