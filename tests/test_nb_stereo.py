"""Chapter 09 notebook helpers: the widgets' callbacks and figures, called directly.

Expected values come from OpenCV (triangulatePoints, computeCorrespondEpilines), from the
scene's construction (object points, true cameras) or from a pinhole written out here.
"""

from __future__ import annotations

import cv2
import matplotlib
import numpy as np
import pytest

matplotlib.use("Agg")

import photolib as pl  # noqa: E402
from photolib.nb import stereo as ns  # noqa: E402

from .explorer_checks import assert_explorer_widget, assert_every_value_redraws, moves  # noqa: E402


pytestmark = pytest.mark.usefixtures("close_figures")


@pytest.mark.parametrize("B, h", [(20.0, 100.0), (5.0, 250.0), (60.0, 40.0)])
def test_pair_report_point_is_the_opencv_triangulation(B, h):
    rep = ns.pair_report(B, h, 4.0)
    P = [np.diag([ns.C_MM, ns.C_MM, 1.0]) @ np.column_stack(pl.opencv_pose_from_exterior(X0, np.eye(3)))
         for X0 in (np.zeros(3), np.array([B, 0.0, 0.0]))]
    H = cv2.triangulatePoints(P[0], P[1], np.array([[rep["x1_mm"]], [0.0]]),
                              np.array([[rep["x2_mm"]], [0.0]]))
    np.testing.assert_allclose((H[:3] / H[3]).ravel(), [B / 2, 0.0, -h], atol=1e-9)
    assert rep["Z_m"] == pytest.approx(-h, rel=1e-12)
    # σ_Z by first-order propagation written out: dZ/dpx = c·B/px²; px in mm, Z in m
    assert rep["sigma_Z_mm"] == pytest.approx(ns.C_MM * B / rep["px_mm"] ** 2 * 4e-3 * 1e3,
                                              rel=1e-12)
    assert rep["m"] == pytest.approx(h * 1e3 / ns.C_MM)


def test_pair_report_forward_overlap():
    assert ns.pair_report(0.4 * 2 * 18.0 * 2.0, 100.0)["overlap"] == pytest.approx(0.6)  # m = 2000
    assert ns.pair_report(100.0, 20.0)["overlap"] == 0.0


def test_epipolar_report_line_contains_the_ray_images_like_opencv():
    rep = ns.epipolar_report(4.0, -2.5, 10.0, -7.0)
    a, b, d = rep["line"]
    assert np.max(np.abs(rep["marks"] @ [a, b] + d)) < 1e-9
    R2 = pl.rotation_opk(0.0, np.radians(10.0), np.radians(-7.0))
    (Ra, ta), (Rb, tb) = (pl.opencv_pose_from_exterior(np.zeros(3), np.eye(3)),
                          pl.opencv_pose_from_exterior([ns.BASE_M, 0, 0], R2))
    Rr, tr = Rb @ Ra.T, tb - Rb @ Ra.T @ ta
    tx = np.array([[0, -tr[2], tr[1]], [tr[2], 0, -tr[0]], [-tr[1], tr[0], 0]])
    Ki = np.linalg.inv(np.diag([ns.C_MM, ns.C_MM, 1.0]))
    F_cv = Ki.T @ tx @ Rr @ Ki
    line = cv2.computeCorrespondEpilines(np.array([[[4.0, 2.5]]]), 1, F_cv).ravel()
    ours = np.array([a, -b, d])
    np.testing.assert_allclose(ours * np.sign(ours @ line), line, atol=1e-9)


def test_epipolar_report_normal_case_has_no_y_parallax():
    rep = ns.epipolar_report(-6.0, 7.0, 0.0, 0.0)
    np.testing.assert_allclose(rep["marks"][:, 1], 7.0, atol=1e-12)
    assert rep["py_mm"] == pytest.approx(0.0, abs=1e-12)
    assert abs(ns.epipolar_report(-6.0, 7.0, 5.0, 0.0)["py_mm"]) > 0.01


def test_pair_scene_is_the_projection_of_its_points():
    s = ns.pair_scene(noise_um=0.0)
    for X0, R, xy in ((s["X01"], s["R1"], s["xy1"]), (s["X02"], s["R2"], s["xy2"])):
        k = (s["X"] - X0) @ R
        np.testing.assert_allclose(xy, -ns.C_MM * k[:, :2] / k[:, 2:], atol=1e-12)
        assert np.all(np.abs(xy) < ns.HALF)


def test_relative_history_converges_to_the_true_relative_orientation():
    s = ns.pair_scene(noise_um=0.0)
    hist = ns.relative_history(s["xy1"], s["xy2"], ns.C_MM, 1.0)
    # the true relative orientation: image 2 in the frame of camera 1, scaled to bx = 1
    b = s["R1"].T @ (s["X02"] - s["X01"])
    R2rel = s["R1"].T @ s["R2"]
    ref = np.r_[b[1:] / b[0], pl.opk_from_rotation(R2rel)]
    err = np.linalg.norm(hist - ref, axis=1)
    assert err[0] > 0.01 and err[-1] < 1e-9 and len(hist) <= 9
    fig = ns.plot_relative_convergence(hist, ref)
    assert len(fig.axes[0].lines[0].get_ydata()) == len(hist)


def test_stereo_pair_explorer_updates():
    e = ns.StereoPairExplorer()
    assert e.live.output.outputs[0]["data"]["image/png"]
    assert moves(e, "B", 40.0) == (True, True)
    assert e.report["sigma_Z_mm"] == pytest.approx(ns.pair_report(40.0, 100.0, 4.0)["sigma_Z_mm"])
    assert moves(e, "h", 200.0) == (True, True)
    assert moves(e, "sigma_px_um", 8.0) == (True, True)
    curve = e._curve.get_ydata()
    i = int(np.argmin(abs(e.B_RANGE - 40.0)))
    assert curve[i] == pytest.approx(ns.pair_report(40.0, 200.0, 8.0)["sigma_Z_mm"])
    assert_explorer_widget(e, "stereo pair explorer")


def test_epipolar_explorer_updates():
    e = ns.EpipolarExplorer()
    assert moves(e, "x1", -4.0) == (True, True)
    assert moves(e, "kappa_deg", 0.0) == (True, True)
    assert moves(e, "phi_deg", 0.0) == (True, True)
    assert "+0.000 mm" in e.html.value           # normal case: no y-parallax
    assert_explorer_widget(e, "epipolar line explorer")


def test_normal_case_figure():
    fig = ns.plot_normal_case(20.0, 100.0)
    assert len(fig.axes) == 1 and len(fig.axes[0].lines) == 7


@pytest.mark.parametrize("cls, name, values", [
    (ns.StereoPairExplorer, "B", (10.0, 50.0)),
    (ns.StereoPairExplorer, "h", (60.0, 250.0)),
    (ns.EpipolarExplorer, "x1", (-10.0, 10.0)),
    (ns.EpipolarExplorer, "kappa_deg", (-20.0, 20.0)),
])
def test_every_value_redraws(cls, name, values):
    assert_every_value_redraws(cls, name, values)


def test_digitised_house_is_opencvs_triangulation_of_the_measurements():
    d = ns.digitise_house(B=20.0, h=100.0, noise_um=3.0)
    P = [np.diag([ns.C_MM, ns.C_MM, 1.0]) @ np.column_stack(pl.opencv_pose_from_exterior(X0, np.eye(3)))
         for X0 in (np.zeros(3), np.array([20.0, 0.0, 0.0]))]
    H = cv2.triangulatePoints(P[0], P[1], (d["xy1"] * [1, -1]).T, (d["xy2"] * [1, -1]).T)
    # OpenCV's linear triangulation also uses y'2; in the normal case Y from image 1 differs
    # by the y-parallax only, so all three agree within the noise
    np.testing.assert_allclose(d["measured"][:, [0, 2]], (H[:3] / H[3]).T[:, [0, 2]], rtol=1e-3)
    assert np.abs(d["error_mm"][:, 2]).max() < 4 * d["sigma"][1]
    assert d["measured_edges"].shape == d["edges"].shape == (17, 2, 3)
    exact = ns.digitise_house(noise_um=0.0)
    np.testing.assert_allclose(exact["measured_edges"], exact["edges"], atol=1e-9)
    fig = ns.plot_digitised(d)
    assert len(fig.axes) == 2 and len(fig.axes[0].lines) == 2


def test_digitised_house_prediction_explains_the_measured_rms():
    # per-corner σ by Monte Carlo over many noise draws, independent of the SymPy propagation
    d = ns.digitise_house(B=20.0, h=100.0, noise_um=3.0)
    errs = np.array([ns.digitise_house(B=20.0, h=100.0, noise_um=3.0, seed=k)["error_mm"]
                     for k in range(3000)])
    mc_sigma = errs.std(axis=0)                                       # (P, 3), mm
    np.testing.assert_allclose(d["sigma_corners"], mc_sigma, rtol=0.06)
    np.testing.assert_allclose(d["sigma_rms"], np.sqrt(np.mean(mc_sigma**2, axis=0)), rtol=0.03)
    # the house stands below the base: X is better than m·σ_x' (6.0 mm), about m·σ/√2
    assert d["sigma_rms"][0] < 0.8 * d["sigma"][0]
    rms = np.sqrt(np.mean(d["error_mm"] ** 2, axis=0))
    assert abs(rms[0] - d["sigma_rms"][0]) < abs(rms[0] - d["sigma"][0])


def test_artificial_stereo_rays_meet_at_the_fused_point():
    e, d, s = 65.0, 250.0, 40.0
    fig = ns.plot_artificial_stereo(e, d, s)
    # rays eye → homologous image point, intersected by linear algebra
    t = np.linalg.solve(np.column_stack([[-s / 2 + e / 2, d], [s / 2 - e / 2, d]]),
                        np.array([e, 0.0]))
    P = np.array([-e / 2, 0.0]) + t[0] * np.array([-s / 2 + e / 2, d])
    np.testing.assert_allclose(fig.fused, P, atol=1e-9)
    with pytest.raises(ValueError):
        ns.plot_artificial_stereo(e, d, e)                # parallel rays: no fused point


# -- the real-photograph and independent-orientation helpers of chapter 09 ------------------------

def test_compare_orientations_is_one_model_by_the_true_cameras():
    # independent route: the model of exact data is the object scene in the frame of camera 1,
    # scaled to the dependent base (truth from the scene's construction)
    s = ns.pair_scene(noise_um=0.0)
    cmp = ns.compare_orientations(s)
    assert cmp["difference"] < 1e-9
    b = s["R1"].T @ (s["X02"] - s["X01"])
    truth = (s["X"] - s["X01"]) @ s["R1"] / b[0]
    np.testing.assert_allclose(cmp["dependent"].model, truth, atol=1e-8)
    np.testing.assert_allclose(cmp["mapped"], truth, atol=1e-8)


def test_real_figures_draw():
    r = ns.real_depth(n=60)
    assert len(r["d"]) > 30
    for fig in (ns.plot_real_depth(r), ns.plot_depth_histogram(r),
                ns.plot_orientation_comparison(ns.compare_orientations())):
        assert fig is not None
    e = ns.real_epipolar()
    assert ns.plot_real_epipolar(e, r, n=4) is not None


def test_real_epipolar_lines_pass_through_the_matches():
    e = ns.real_epipolar()
    inl = e["inliers"]
    lines = pl.epipolar_lines(e["F"], e["x1"][inl], image=2)
    dist = np.abs(np.sum(lines[:, :2] * e["x2"][inl], axis=1) + lines[:, 2])
    assert np.median(dist) < 0.3                          # px, on the half-size images
