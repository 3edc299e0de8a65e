"""Chapter 14's two widgets (photolib.nb.project.ChainExplorer and NoiseExplorer): what they
show is the chain run on the chosen input, checked against independent routes — the
intersection angle from the camera centres by the law of cosines, the added noise's σ0 against
its expectation √(σ0,real² + σ²), and the check points' RMS against OpenCV's triangulation of
the same noisy coordinates with photolib's orientations."""

from __future__ import annotations

import cv2
import numpy as np
import pytest

import photolib as pl
from photolib.nb import project as pj

from .explorer_checks import assert_explorer_widget

CHECK = (4, 13, 20, 31, 39, 48)
W, H = 640, 480


def test_chain_explorer_starts_with_the_notebooks_chain():
    e = pj.ChainExplorer(2, 11, CHECK)
    assert_explorer_widget(e, "the chain on a pair of views: geometry and accuracy")
    ref = pj.chain(2, 11, CHECK)
    assert e.chain.check == CHECK
    np.testing.assert_array_equal(e.chain.points, ref.points)
    assert f"{ref.rms:.3f} mm" in e.html.value and f"{ref.predicted_rms:.3f} mm" in e.html.value
    assert "left03.jpg" in e.html.value and "left12.jpg" in e.html.value


def test_chain_explorer_angle_is_the_law_of_cosines():
    """α from the three side lengths of the triangle (centre A, centre B, board centre)."""
    e = pj.ChainExplorer(2, 11, CHECK)
    C = pj.calibration().result.exterior[:, :3]
    m = pj.board_points().mean(axis=0)
    for a, b in ((0, 13), (8, 12), (1, 9)):
        e.set(view_a=float(a), view_b=float(b))
        p, q, r = (np.linalg.norm(C[a] - m), np.linalg.norm(C[b] - m),
                   np.linalg.norm(C[a] - C[b]))
        alpha = np.degrees(np.arccos((p * p + q * q - r * r) / (2 * p * q)))
        assert f"α = {alpha:.1f}°" in e.html.value
        assert ("Small intersection angle" in e.html.value) == (alpha < pj.MIN_ANGLE_DEG)


def test_chain_explorer_glancing_pair_is_worse_than_a_wide_one():
    """left09/left13 meet at 3.5°: their predicted Z precision is far poorer than left01/left14's
    (37.5°); the intersection geometry, not the measurement, makes the difference."""
    e = pj.ChainExplorer(8, 12, CHECK)
    narrow = e.chain
    e.set(view_a=0.0, view_b=13.0)
    wide = e.chain
    assert narrow.predicted_rms > 4 * wide.predicted_rms
    assert narrow.rms > 2 * wide.rms


def test_chain_explorer_same_view_gives_a_message_not_an_error():
    e = pj.ChainExplorer(2, 11, CHECK)
    before = e.live.png
    e.set(view_b=2.0)
    assert e.chain is None
    assert "same photograph (left03.jpg)" in e.html.value
    assert e.live.png != before
    e.set(view_b=11.0)
    assert e.chain is not None and e.chain.views == (2, 11)


def test_chain_explorer_more_check_points_fewer_control_points():
    e = pj.ChainExplorer(2, 11, CHECK)
    e.set(n_check=20.0)
    ch = e.chain
    assert len(ch.check) == 20 and len(ch.control) == 34
    assert not set(ch.check) & set(ch.control)
    assert {pj.corner_grid(k)[0] // 3 for k in ch.check} == {0, 1}
    assert ch.resections[0].redundancy == 2 * 34 - 6
    e.set(n_check=6.0)
    assert e.chain.check == CHECK


def test_chain_explorer_refuses_a_bad_check_list():
    with pytest.raises(ValueError, match="3 … 24"):
        pj.ChainExplorer(2, 11, [1, 2])


def _opencv_rms(ch):
    """Check-point RMS by cv2.triangulatePoints (linear, homogeneous) from photolib's two
    orientations and the same (noisy) corrected image coordinates; mm."""
    cam = pj.calibration().result
    K = np.array([[cam.c, 0, cam.x0 + (W - 1) / 2], [0, cam.c, (H - 1) / 2 - cam.y0], [0, 0, 1.0]])
    P = []
    for r in ch.resections:
        # camera frame of OpenCV: x right, y down, z forward = photolib's (x, −y, −z)
        Rcv = np.diag([1.0, -1.0, -1.0]) @ r.R.T
        P.append(K @ np.column_stack([Rcv, -Rcv @ r.X0]))
    px = [pl.pixel_from_image(xy, W, H, 1.0).T for xy in ch.xy]
    Xh = cv2.triangulatePoints(P[0], P[1], px[0], px[1])
    X = (Xh[:3] / Xh[3]).T
    return float(np.sqrt(np.mean(np.sum((X - ch.true) ** 2, axis=1))))


def test_noise_explorer_sigma0_follows_the_added_noise():
    """σ0 of the resections pooled ≈ √(σ0,real² + σ²): 2 × 90 redundancies, so σ0's relative
    standard deviation is 1/√(2·180) ≈ 5 %; allow 4 of them (20 %)."""
    e = pj.NoiseExplorer(2, 11, CHECK, sigma=0.0)
    assert_explorer_widget(e, "noise on the measurement: σ0, check-point RMS and their prediction")
    real = pj._pooled_sigma0(e.chain)
    np.testing.assert_allclose(e.chain.points, pj.chain(2, 11, CHECK).points, rtol=0, atol=0)
    for sigma in (0.5, 1.0, 2.0):
        e.set(sigma=sigma)
        expect = np.hypot(real, sigma)
        assert abs(pj._pooled_sigma0(e.chain) / expect - 1) < 0.2
        assert f"{expect:.3f} px" in e.html.value


def test_noise_explorer_rms_is_opencvs_and_near_its_prediction():
    """The check-point RMS shown equals OpenCV's triangulation of the same coordinates (the
    linear and the least-squares intersection differ by far less than 1 µm at 0.5 px noise),
    and over ten draws at σ = 1 px its mean lies within 35 % of the mean prediction (six check
    points, 18 coordinates per draw: the RMS of one draw scatters by about 1/√(2·18) ≈ 17 %)."""
    e = pj.NoiseExplorer(2, 11, CHECK, sigma=0.5)
    assert abs(_opencv_rms(e.chain) - e.chain.rms) < 1e-3
    assert f"{e.chain.rms:.3f} mm" in e.html.value
    rms, pred = [], []
    for d in range(10):                  # the widget's draws, without redrawing its curve
        ch = pj.chain(2, 11, CHECK, e.noise(1.0, d))
        rms.append(ch.rms)
        pred.append(ch.predicted_rms)
    assert abs(np.mean(rms) / np.mean(pred) - 1) < 0.35
    # one draw, scaled: the noise is proportional to σ
    np.testing.assert_allclose(e.noise(2.0, 3), 2 * e.noise(1.0, 3), rtol=0, atol=0)


def test_noise_explorer_curve_and_marker_move():
    e = pj.NoiseExplorer(2, 11, CHECK, sigma=0.5, draw=0)
    png = e.live.png
    curve = e._rms_line.get_ydata().copy()
    e.set(sigma=1.5)
    assert e.live.png != png
    np.testing.assert_array_equal(e._rms_line.get_ydata(), curve)   # same draw: same curve
    e.set(draw=4.0)
    assert not np.array_equal(e._rms_line.get_ydata(), curve)
    assert e._rms_line.get_ydata()[0] == pytest.approx(pj.chain(2, 11, CHECK).rms, abs=1e-12)


def test_noise_input_is_checked():
    with pytest.raises(ValueError, match=r"\(2, 54, 2\)"):
        pj.chain(2, 11, CHECK, noise=np.zeros((2, 53, 2)))
    bad = np.zeros((2, 54, 2))
    bad[0, 0, 0] = np.nan
    with pytest.raises(ValueError, match="finite"):
        pj.chain(2, 11, CHECK, noise=bad)
    with pytest.raises(ValueError, match="differ"):
        pj.NoiseExplorer(5, 5, CHECK)
    with pytest.raises(ValueError, match="distinct"):
        pj.chain(2, 11, [4, 4, 13])
