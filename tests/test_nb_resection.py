"""Chapter 08 notebook helpers: the widgets' callbacks and figures, called directly.

Expected values come from OpenCV (``solvePnP``, ``decomposeProjectionMatrix``) or from the
chapter's construction (the true camera), not from the library under test.
"""

from __future__ import annotations

import cv2
import matplotlib
import numpy as np
import pytest

matplotlib.use("Agg")

import photolib as pl  # noqa: E402
from photolib.nb import resection as nr  # noqa: E402

from .explorer_checks import assert_explorer_widget, assert_every_value_redraws, moves  # noqa: E402


pytestmark = pytest.mark.usefixtures("close_figures")

_FLIP = np.diag([1.0, -1.0, -1.0])  # our camera frame (−z viewing, y up) → OpenCV's


def _solve_pnp(X, xy):
    """Projection centre and R (camera → object) by OpenCV's iterative PnP."""
    K = np.array([[nr.C_MM, 0.0, 0.0], [0.0, nr.C_MM, 0.0], [0.0, 0.0, 1.0]])
    uv = np.column_stack([xy[:, 0], -xy[:, 1]])
    ok, rvec, tvec = cv2.solvePnP(np.asarray(X, float), uv, K, np.zeros(5),
                                  flags=cv2.SOLVEPNP_ITERATIVE)
    assert ok
    R_cv = cv2.Rodrigues(rvec)[0]
    return (-R_cv.T @ tvec).ravel(), (_FLIP @ R_cv).T


def test_observations_are_the_true_camera_seen_by_opencv():
    X = nr.control_points(10)
    X0, R = nr.true_camera()
    R_cv = _FLIP @ R.T
    uv, _ = cv2.projectPoints(X.reshape(-1, 1, 3), cv2.Rodrigues(R_cv)[0], -R_cv @ X0,
                              np.diag([nr.C_MM, nr.C_MM, 1.0]), np.zeros(5))
    uv = uv.reshape(-1, 2)
    np.testing.assert_allclose(nr.observations(X), np.column_stack([uv[:, 0], -uv[:, 1]]),
                               atol=1e-9)
    assert np.all(np.abs(nr.observations(nr.control_points())) < nr.HALF)  # all in the format


def test_control_points_flatten_with_depth():
    flat, deep = nr.control_points(depth=0.0), nr.control_points(depth=8.0)
    np.testing.assert_array_equal(flat[:, :2], deep[:, :2])
    assert np.ptp(flat[:, 2]) == 0.0 and 0.0 < np.ptp(deep[:, 2]) <= 8.0


@pytest.mark.parametrize("noise, n", [(0.0, 6), (10.0, 12), (30.0, 20)])
def test_resection_report_agrees_with_opencv_pnp(noise, n):
    rep = nr.resection_report(noise, n)
    X = nr.control_points(n)
    C, R = _solve_pnp(X, rep["xy"])
    res = rep["result"]
    # both minimise the same image residuals, so they agree far below the noise effect
    np.testing.assert_allclose(res.X0, C, atol=1e-6 + 1e-4 * noise)
    np.testing.assert_allclose(res.R, R, atol=1e-7 + 1e-5 * noise)
    assert res.redundancy == 2 * n - 6
    if noise == 0.0:
        assert rep["sigma0_um"] < 1e-6 and rep["error_mm"] < 1e-6
    else:
        assert 0.3 * noise < rep["sigma0_um"] < 2.0 * noise
        assert np.all(rep["std"] > 0)
    assert f"redundancy r = {2 * n - 6}" in rep["html"]


def test_resection_report_std_grows_with_noise_and_shrinks_with_points():
    a, b, c = (nr.resection_report(5.0, 8), nr.resection_report(20.0, 8),
               nr.resection_report(20.0, 20))
    assert np.all(b["std"] > a["std"])
    assert np.all(c["std"] < b["std"])


def test_resection_report_three_points_has_no_sigma0():
    rep = nr.resection_report(5.0, 3)
    assert rep["result"].redundancy == 0 and np.isnan(rep["sigma0_um"])
    assert "no redundancy" in rep["html"]


def test_dlt_report_recovers_the_true_camera_as_opencv_does():
    rep = nr.dlt_report(5.0, 0.0)
    P = np.append(rep["estimate"].L, 1.0).reshape(3, 4)
    K, _, C, *_ = cv2.decomposeProjectionMatrix(P)
    K = K / K[2, 2]
    d = rep["decomposition"]
    np.testing.assert_allclose([d.c_x, d.c_y, d.x0, d.y0], [abs(K[0, 0]), abs(K[1, 1]),
                                                           K[0, 2], K[1, 2]], atol=1e-8)
    np.testing.assert_allclose([abs(K[0, 0]), K[0, 2], K[1, 2]], [nr.C_MM, 0.0, 0.0], atol=1e-8)
    np.testing.assert_allclose((C[:3] / C[3]).ravel(), nr.TRUE_X0, atol=1e-8)
    assert rep["errors"]["X0"] < 1e-8


def test_dlt_report_coplanar_points_give_a_clear_error():
    rep = nr.dlt_report(0.0, 5.0)
    assert rep["flatness"] == 0.0 and rep["decomposition"] is None
    assert "coplanar" in rep["error"] and "ValueError" in rep["html"] and "#b00" in rep["html"]


def test_dlt_error_grows_as_the_field_flattens():
    curve = nr.dlt_depth_curve([0.0, 0.25, 1.0, 4.0, 10.0], noise_um=5.0)
    assert np.isnan(curve["c"][0])
    assert curve["c"][1] > curve["c"][2] > curve["c"][4]
    assert curve["X0"][1] > curve["X0"][4]


def test_resection_history_good_start_converges_and_poor_start_diverges():
    X = nr.control_points(12)
    xy = nr.observations(X)
    hist, failure = nr.resection_history(X, xy, nr.C_MM, nr._start())
    assert failure is None
    err = np.linalg.norm(hist[:, :3] - nr.TRUE_X0, axis=1)
    assert err[0] > 1.0 and err[-1] < 1e-8 and len(hist) <= 10
    assert err[2] < err[1] < err[0]           # Gauss-Newton: fast decrease
    poor = np.r_[nr.TRUE_X0, np.radians(nr.TRUE_ANGLES_DEG)] + np.r_[0, 0, 0, 0, 0, np.pi]
    hist, failure = nr.resection_history(X, xy, nr.C_MM, poor)
    assert failure is not None  # diverged, or the normal equations became singular


def test_resection_explorer_updates_figure_and_text():
    e = nr.ResectionExplorer()
    assert e.live.output.outputs[0]["data"]["image/png"]
    assert moves(e, "noise_um", 25.0) == (True, True)
    assert "25 µm" in e.html.value
    assert moves(e, "n_points", 4.0) == (True, True)
    assert e.report["result"].redundancy == 2
    assert_explorer_widget(e, "space resection explorer")


def test_dlt_explorer_updates_and_shows_the_coplanar_error():
    e = nr.DLTExplorer()
    assert moves(e, "depth", 2.0) == (True, True)
    assert moves(e, "depth", 0.0) == (True, True)
    assert "coplanar" in e.html.value and e.report["decomposition"] is None
    assert moves(e, "noise_um", 12.0) == (True, True)
    assert set(e._curves) == {5.0, 12.0}
    assert_explorer_widget(e, "DLT geometry explorer")


@pytest.mark.parametrize("cls, name, values", [
    (nr.ResectionExplorer, "noise_um", (10.0, 30.0)),
    (nr.ResectionExplorer, "n_points", (6.0, 18.0)),
    (nr.DLTExplorer, "depth", (1.0, 6.0)),
])
def test_every_value_redraws(cls, name, values):
    assert_every_value_redraws(cls, name, values)


def test_static_figures_have_their_artists():
    X = nr.control_points(12)
    X0, R = nr.true_camera()
    fig = nr.plot_scene(X, [(X0, R, "0.5", "true")])
    assert len(fig.axes) == 1 and len(fig.axes[0].lines) == 2
    rep = nr.resection_report(10.0, 12)
    fig = nr.plot_residuals(rep["xy"], rep["residuals"])
    vectors = fig.axes[0].lines[2].get_xydata()
    np.testing.assert_allclose(vectors[1::3] - vectors[0::3], 200.0 * rep["residuals"])
    hist = nr.resection_history(X, nr.observations(X), nr.C_MM, nr._start())
    fig = nr.plot_convergence({"good": hist}, hist[0][-1])
    err = fig.axes[0].lines[0].get_ydata()
    assert len(fig.axes[0].lines) == 1 and err[0] > 1.0 and err[-1] == 1e-14
    fig = nr.plot_dlt_depth(nr.dlt_depth_curve([0.0, 1.0, 2.0]))
    assert len(fig.axes[0].lines) == 3


def test_resection_report_matches_the_library_on_a_known_case():
    # 8 exact points: the true orientation comes back, angles in the library's radians
    rep = nr.resection_report(0.0, 8)
    np.testing.assert_allclose([rep["result"].omega, rep["result"].phi, rep["result"].kappa],
                               np.radians(nr.TRUE_ANGLES_DEG), atol=1e-10)
    assert isinstance(rep["result"], pl.resection.ResectionResult)
