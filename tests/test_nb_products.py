"""Chapter 12 notebook helpers: the widgets' callbacks and figures, called directly.

Expected values come from SymPy (:mod:`photolib.derive.products`), OpenCV's
``projectPoints``, or hand-written geometry (ray–plane and slab tests), not from the code
under test.
"""

from __future__ import annotations

import math

import cv2
import matplotlib
import numpy as np
import pytest
import sympy as sp

matplotlib.use("Agg")

import photolib as pl  # noqa: E402
from photolib.derive import products as dp  # noqa: E402
from photolib.nb import products as npr  # noqa: E402
from photolib.rectify import output_grid  # noqa: E402

from .explorer_checks import assert_explorer_widget, assert_every_value_redraws, moves  # noqa: E402
from .scene_checks import segment_hits_box  # noqa: E402


pytestmark = pytest.mark.usefixtures("close_figures")


@pytest.mark.parametrize("h, H, R", [(30.0, 300.0, 120.0), (80.0, 500.0, 10.0), (1.0, 1000.0, 250.0)])
def test_relief_report_agrees_with_sympy(h, H, R):
    rep = npr.relief_report(h, H, R)
    args = (dp.c, dp.Rg, dp.H, dp.h)
    vals = (npr.C_MM, R, H, h)
    assert math.isclose(rep["dr"], float(sp.lambdify(args, dp.relief_displacement())(*vals)),
                        rel_tol=1e-10, abs_tol=1e-12)
    assert math.isclose(rep["r_top"], float(sp.lambdify(args, dp.r_top())(*vals)), rel_tol=1e-12)
    assert math.isclose(rep["formula"], rep["dr"], rel_tol=1e-10, abs_tol=1e-12)
    assert math.isclose(rep["ground_m"], R * h / (H - h), rel_tol=1e-10, abs_tol=1e-12)


@pytest.mark.parametrize("phi, amplitude", [(0.0, 1.0), (8.0, 2.0), (-12.0, 0.5)])
def test_plane_rectification_error_is_the_relief_displacement(phi, amplitude):
    rep = npr.ortho_error_report(phi, amplitude)
    cam = npr.camera(angles_deg=(0.0, phi, 0.0), distortion=False)
    P = rep["points"]
    Z = npr.terrain(P[:, 0], P[:, 1], amplitude)
    # by hand: the ray X0 → (X, Y, Z) meets the reference plane Z_REF at X0 + s·(P − X0)
    s = (npr.Z_REF - cam.X0[2]) / (Z - cam.X0[2])
    on_plane = cam.X0[:2] + s[:, None] * (P - cam.X0[:2])
    np.testing.assert_allclose(rep["plane_err"], on_plane - P, atol=1e-6)
    np.testing.assert_allclose(rep["relief"], on_plane - P, atol=1e-9)
    assert np.abs(rep["diff_err"]).max() < 5e-3            # DTM interpolation only
    assert np.hypot(*rep["plane_err"].T).max() > 0.5 * amplitude


def test_plane_rectification_is_exact_on_flat_ground_whatever_the_tilt():
    for phi in (0.0, 10.0):
        rep = npr.ortho_error_report(phi, 0.0)
        assert np.abs(rep["plane_err"]).max() < 1e-6


@pytest.mark.parametrize("height, offset", [(20.0, 20.0), (45.0, 5.0), (8.0, 30.0)])
def test_true_ortho_report_matches_the_slab_test(height, offset):
    rep = npr.true_ortho_report(height, offset)
    shape, origin, d = npr._TO_GRID
    grid = output_grid(shape, origin, d)
    box = (30.0, 44.0, 18.0, 32.0, height)
    X0 = np.array([box[0] - offset, 25.0, 100.0])
    ref = np.empty(shape, int)
    for i in range(shape[0]):
        for j in range(shape[1]):
            X, Y = grid[i, j]
            if box[0] < X < box[1] and box[2] < Y < box[3]:
                ref[i, j] = 2
            else:
                ref[i, j] = 0 if segment_hits_box(np.array([X, Y, 0.0]), X0, box) else 1
    np.testing.assert_array_equal(rep["classes"], ref)
    dist = box[1] - X0[0]
    expected = float(dp.occluded_length().subs({dp.d: dist, dp.h: height, dp.H: 100.0}))
    assert math.isclose(rep["formula"], expected, rel_tol=1e-12)
    assert abs(rep["length"] - expected) <= d
    assert rep["area"] == (ref == 0).sum() * d * d


def test_render_shows_the_texture_where_opencv_projects_a_ground_point():
    cam = npr.camera(distortion=False)
    img = npr.render(cam)
    rng = np.random.default_rng(4)
    XY = np.column_stack([rng.uniform(10, 110, 400), rng.uniform(5, 85, 400)])
    P = np.column_stack([XY, npr.terrain(XY[:, 0], XY[:, 1])])
    roofs = npr._roofs(XY)
    P = P[~np.isfinite(roofs)]                                     # open ground only
    Rcv, t = pl.opencv_pose_from_exterior(cam.X0, cam.R)
    uv, _ = cv2.projectPoints(P, cv2.Rodrigues(Rcv)[0], t, np.diag([cam.c, cam.c, 1.0]), None)
    uv = uv.reshape(-1, 2)
    col = np.round(uv[:, 0] / cam.pixel_size + (cam.width - 1) / 2).astype(int)
    row = np.round(uv[:, 1] / cam.pixel_size + (cam.height - 1) / 2).astype(int)
    inside = (col >= 0) & (col < cam.width) & (row >= 0) & (row < cam.height)
    # the ground point seen at the pixel centre is within one GSD (0.36 m) of P: compare the
    # texture where it is smooth (no road edge, no building nearby)
    tex = npr.texture(P)
    smooth = np.ones(len(P), bool)
    for dx in (-1.0, 0.0, 1.0):
        for dy in (-1.0, 0.0, 1.0):
            Q = P + [dx, dy, 0.0]
            smooth &= (np.abs(npr.texture(Q) - tex) < 12.0) & ~np.isfinite(npr._roofs(Q[:, :2]))
    sel = inside & smooth
    assert sel.sum() > 150
    # a building may hide the point (relief displacement): allow a few
    agree = np.abs(img[row[sel], col[sel]] - tex[sel]) < 12.0
    assert agree.mean() > 0.9


def test_scene_products_have_their_shapes():
    cam, img, dtm, dsm = npr.building_scene()
    assert img.shape == (cam.height, cam.width) and dsm.order == 0 and dtm.order == 1
    assert dsm.heights.max() == max(b[4] for b in npr.BUILDINGS)


def test_relief_explorer_updates_figure_and_text():
    e = npr.ReliefExplorer()
    assert e.live.output.outputs[0]["data"]["image/png"]
    assert moves(e, "h", 60.0) == (True, True)
    assert math.isclose(e.report["dr"], e.report["r_top"] * 60.0 / 300.0, rel_tol=1e-9)
    assert moves(e, "H", 600.0) == (True, True)
    assert_explorer_widget(e, "relief displacement explorer")


def test_ortho_error_explorer_updates():
    e = npr.OrthoErrorExplorer()
    assert moves(e, "amplitude", 2.5) == (True, True)
    before = e.report["plane_err"]
    assert moves(e, "phi", 10.0)[1]
    np.testing.assert_allclose(e.report["plane_err"], before, atol=1e-6)  # tilt: no change
    seg = e._plane.get_xydata()
    np.testing.assert_allclose(seg[1::3] - seg[0::3], e.scale * e.report["plane_err"])
    assert_explorer_widget(e, "orthophoto explorer")


def test_true_ortho_explorer_updates():
    e = npr.TrueOrthoExplorer()
    area = e.report["area"]
    assert moves(e, "height", 40.0) == (True, True)
    assert e.report["area"] > area
    assert moves(e, "offset", 5.0) == (True, True)
    np.testing.assert_array_equal(e._im.get_array(), e.report["classes"])
    assert_explorer_widget(e, "true orthophoto explorer")


@pytest.mark.parametrize("cls, name, values", [
    (npr.ReliefExplorer, "h", (10.0, 50.0)),
    (npr.OrthoErrorExplorer, "amplitude", (0.5, 2.0)),
    (npr.TrueOrthoExplorer, "height", (10.0, 40.0)),
])
def test_every_value_redraws(cls, name, values):
    assert_every_value_redraws(cls, name, values)


def test_static_figures_have_their_artists():
    fig = npr.plot_relief_geometry()
    assert len(fig.axes) == 3 and len(fig.axes[0].lines) == 6
    rep = npr.relief_report()
    assert [ln.get_xdata()[0] for ln in fig.axes[1].lines[-2:]] == [rep["r_foot"], rep["r_top"]]
    # the zoom: r − r_foot
    assert [ln.get_xdata()[0] for ln in fig.axes[2].lines[-2:]] == [0.0, rep["dr"]]
    fig = npr.plot_products({"a": np.zeros((4, 5)), "b": np.full((4, 5), np.nan)})
    assert len(fig.axes) == 2
    src = np.zeros((10, 12), int)
    src[:, 6:] = 1
    fig = npr.plot_mosaic(np.zeros((10, 12)), src, [[1, 1], [9, 1]], (0, 12, 0, 10))
    assert len(fig.axes[0].lines) == 1
    fig = npr.plot_height_models({"DTM": npr.dtm(), "DSM": npr.dsm()})
    assert len(fig.axes) == 3 and fig.axes[0].images[0].get_array().shape == npr.dtm().shape
    shape, origin, d = (20, 30), (10.0, 50.0), 1.0
    fig = npr.plot_ortho_map(np.zeros(shape), npr.dtm(), shape, origin, d, interval=1.0)
    assert fig.axes[0].collections          # the contour lines


# -- the real mosaic's zoom (photolib.nb.products_real) -------------------------------------------

def _small_mosaic():
    from photolib import image_mosaic as im
    rng = np.random.default_rng(0)
    img = rng.uniform(0, 255, (60, 90))
    shift = pl.AffineTransform(50.0, 1.0, 0.0, 10.0, 0.0, 1.0)
    return im.image_mosaic([img[:, :60], img[10:, 50:]], im.chain_transforms([shift]))


def test_mosaic_zoom_shows_the_window_and_its_source_images():
    from photolib.nb.products_real import MosaicZoom
    mos = _small_mosaic()
    e = MosaicZoom(mos, half=15)
    assert_explorer_widget(e, "mosaic zoom")
    e.set(X=20.0, Y=-20.0, half=15.0)                   # inside image 1 only
    assert "from image(s): 1<" in e.html.value + "<"
    e.set(X=60.0, Y=-30.0, half=15.0)                   # across the seam
    assert "from image(s): 1, 2" in e.html.value
    rs, cs = e.window(60.0, -30.0, 15.0)
    shown = e._img.get_array()
    assert np.allclose(shown, mos.mosaic[rs, cs])
    assert any(moves(e, "X", 30.0))
