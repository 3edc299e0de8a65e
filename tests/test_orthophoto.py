"""Orthophoto, true orthophoto and mosaic by independent routes.

* ``cv2.remap`` with the library's maps, and ``cv2.projectPoints`` for the maps themselves;
* a per-pixel Python loop (own collinearity, own bilinear interpolation) on a tiny grid;
* SymPy (:mod:`photolib.derive.products`) and direct projection for the relief displacement;
* a synthetic scene (flat ground + a box building) rendered by analytic ray casting, whose
  true orthophoto and occluded area are known: a ground point is hidden iff the segment from
  it to the projection centre passes through the box (slab test, not ray marching).
"""

from __future__ import annotations

import math

import cv2
import numpy as np
import pytest
import sympy as sp
from hypothesis import given, settings
from hypothesis import strategies as st

import photolib as pl
from photolib import orthophoto as op
from photolib.derive import products as dp
from photolib.rectify import output_grid

from .scene_checks import segment_hits_box

C = 50.0                                   # mm
PIX = 0.05                                 # mm
W, H_IMG = 600, 500


def _camera(tilt=(0.02, -0.03, 0.4), X0=(50.0, 40.0, 300.0), distortion=None):
    return op.FrameCamera(X0, pl.rotation_opk(*tilt), C, W, H_IMG, PIX, x0=0.03, y0=-0.02,
                          distortion=distortion)


def _hills(X, Y):
    return 20.0 + 8.0 * np.sin(X / 17.0) * np.cos(Y / 13.0) + 0.05 * X


def _dtm():
    return op.DTM.from_function(_hills, (61, 71), (0.0, 90.0), 1.5)


def _texture_image(seed=0):
    rng = np.random.default_rng(seed)
    col, row = np.meshgrid(np.arange(W), np.arange(H_IMG))
    base = 100 + 60 * np.sin(col / 23.0) * np.cos(row / 17.0)
    return base + rng.normal(0, 1.0, base.shape)


# -- DTM ------------------------------------------------------------------------------------------

@settings(max_examples=40, deadline=None)
@given(st.floats(-5, 5), st.floats(-5, 5), st.floats(-100, 100),
       st.lists(st.tuples(st.floats(0, 1), st.floats(0, 1)), min_size=1, max_size=8))
def test_dtm_bilinear_reproduces_a_plane_exactly(a, b, z0, uv):
    dtm = op.DTM.from_function(lambda X, Y: z0 + a * X + b * Y, (5, 7), (10.0, 20.0), 2.0)
    Xmin, Xmax, Ymin, Ymax = dtm.extent
    XY = np.array([[Xmin + u * (Xmax - Xmin), Ymin + v * (Ymax - Ymin)] for u, v in uv])
    np.testing.assert_allclose(dtm.height(XY), z0 + a * XY[:, 0] + b * XY[:, 1],
                               atol=1e-9 * (1 + abs(z0) + 100 * (abs(a) + abs(b))))


def test_dtm_height_agrees_with_scipy_interpolator():
    from scipy.interpolate import RegularGridInterpolator

    dtm = _dtm()
    Xmin, Xmax, Ymin, Ymax = dtm.extent
    xs = Xmin + dtm.spacing * np.arange(dtm.shape[1])
    ys = Ymax - dtm.spacing * np.arange(dtm.shape[0])
    f = RegularGridInterpolator((ys[::-1], xs), dtm.heights[::-1], method="linear")
    rng = np.random.default_rng(3)
    XY = np.column_stack([rng.uniform(Xmin, Xmax, 200), rng.uniform(Ymin, Ymax, 200)])
    np.testing.assert_allclose(dtm.height(XY), f(XY[:, ::-1]), atol=1e-10)


def test_dtm_refuses_bad_input():
    with pytest.raises(ValueError, match=r"heights contains a non-finite value nan at index \(1, 0\)"):
        op.DTM([[0.0, 1.0], [np.nan, 2.0]], (0, 0), 1.0)
    with pytest.raises(ValueError, match="expected \\(rows, cols\\)"):
        op.DTM(np.zeros(4), (0, 0), 1.0)
    with pytest.raises(ValueError, match="spacing must be > 0"):
        op.DTM(np.zeros((2, 2)), (0, 0), -1.0)
    with pytest.raises(ValueError, match="order must be 0"):
        op.DTM(np.zeros((2, 2)), (0, 0), 1.0, order=3)
    dtm = op.DTM(np.zeros((2, 2)), (0, 1), 1.0)
    with pytest.raises(op.OutsideModelError, match=r"XY\[1\] = \[2.0, 0.5\] is outside"):
        dtm.height([[0.5, 0.5], [2.0, 0.5]])
    assert np.isnan(dtm.height([[2.0, 0.5]], outside="nan")[0])
    with pytest.raises(ValueError, match="XY contains a non-finite"):
        dtm.height([[np.nan, 0.5]])


# -- maps and resampling --------------------------------------------------------------------------

def test_ortho_maps_agree_with_cv2_project_points():
    cam, dtm = _camera(), _dtm()
    cr, XYZ = op.ortho_pixel_positions(cam, dtm, (40, 50), (10.0, 80.0), 1.0)
    Rcv, t = pl.opencv_pose_from_exterior(cam.X0, cam.R)
    K = np.array([[cam.c, 0, cam.x0], [0, cam.c, -cam.y0], [0, 0, 1.0]])
    uv, _ = cv2.projectPoints(XYZ.reshape(-1, 3), cv2.Rodrigues(Rcv)[0], t, K, None)
    uv = uv.reshape(-1, 2)                      # (x', −y') in mm
    col = uv[:, 0] / PIX + (W - 1) / 2
    row = uv[:, 1] / PIX + (H_IMG - 1) / 2
    np.testing.assert_allclose(cr.reshape(-1, 2), np.column_stack([col, row]), atol=1e-8)
    np.testing.assert_allclose(XYZ[..., 2], _hills(XYZ[..., 0], XYZ[..., 1]), atol=0.05)


@pytest.mark.parametrize("order, flag", [(1, cv2.INTER_LINEAR), (0, cv2.INTER_NEAREST)])
def test_differential_rectification_matches_cv2_remap(order, flag):
    cam, dtm = _camera(), _dtm()
    img = _texture_image()
    shape, origin = (45, 55), (5.0, 85.0)
    ortho = op.differential_rectification(img, cam, dtm, shape, origin, 1.0, order=order,
                                          fill=-1.0)
    cr, _ = op.ortho_pixel_positions(cam, dtm, shape, origin, 1.0)
    ref = cv2.remap(img.astype(np.float32), cr[..., 0].astype(np.float32),
                    cr[..., 1].astype(np.float32), flag, borderMode=cv2.BORDER_CONSTANT,
                    borderValue=-1.0)
    inside = (cr[..., 0] > 1) & (cr[..., 0] < W - 2) & (cr[..., 1] > 1) & (cr[..., 1] < H_IMG - 2)
    assert inside.mean() > 0.9
    # OpenCV's bilinear weights are quantised to 1/32 pixel: a few grey values on this texture
    tol = 1.5 if order == 1 else 1e-4
    if order == 0:      # ties at exactly .5 may round differently; there are none here
        assert np.all(np.abs(cr - np.round(cr)) != 0.5)
    np.testing.assert_allclose(ortho[inside], ref[inside], atol=tol)


def _loop_reference(img, cam, heights, h_origin, h_spacing, shape, origin, d):
    """Ortho by a per-pixel loop: own collinearity, own bilinear height and grey value."""
    def bilinear(a, col, row):
        c0, r0 = min(int(math.floor(col)), a.shape[1] - 2), min(int(math.floor(row)), a.shape[0] - 2)
        u, v = col - c0, row - r0
        return ((1 - u) * (1 - v) * a[r0, c0] + u * (1 - v) * a[r0, c0 + 1]
                + (1 - u) * v * a[r0 + 1, c0] + u * v * a[r0 + 1, c0 + 1])
    out = np.zeros(shape)
    for row in range(shape[0]):
        for col in range(shape[1]):
            X, Y = origin[0] + col * d, origin[1] - row * d
            Z = bilinear(heights, (X - h_origin[0]) / h_spacing, (h_origin[1] - Y) / h_spacing)
            k = cam.R.T @ (np.array([X, Y, Z]) - cam.X0)
            x = cam.x0 - cam.c * k[0] / k[2]
            y = cam.y0 - cam.c * k[1] / k[2]
            ci = x / cam.pixel_size + (cam.width - 1) / 2
            ri = (cam.height - 1) / 2 - y / cam.pixel_size
            out[row, col] = bilinear(img, ci, ri)
    return out


def test_differential_rectification_matches_a_per_pixel_loop():
    cam, dtm = _camera(), _dtm()
    img = _texture_image(1)
    shape, origin = (6, 7), (30.0, 60.0)
    ours = op.differential_rectification(img, cam, dtm, shape, origin, 2.5)
    ref = _loop_reference(img, cam, dtm.heights, dtm.origin, dtm.spacing, shape, origin, 2.5)
    np.testing.assert_allclose(ours, ref, atol=1e-9)


def test_blockwise_processing_gives_the_same_result_with_a_progress_bar(capsys):
    cam, dtm = _camera(), _dtm()
    img = np.dstack([_texture_image(2), _texture_image(3)])
    args = (img, cam, dtm, (33, 20), (10.0, 70.0), 1.5)
    whole = op.differential_rectification(*args, block_rows=1000)
    blocks = op.differential_rectification(*args, block_rows=4, progress=True)
    np.testing.assert_array_equal(whole, blocks)
    assert whole.shape == (33, 20, 2)
    assert "orthophoto" in capsys.readouterr().err


def test_distortion_is_applied():
    d = pl.Distortion(A1=-1e-4)
    cam0, cam1 = _camera(), _camera(distortion=d)
    cr0, XYZ = op.ortho_pixel_positions(cam0, _dtm(), (5, 5), (20.0, 60.0), 5.0)
    cr1, _ = op.ortho_pixel_positions(cam1, _dtm(), (5, 5), (20.0, 60.0), 5.0)
    xy1 = pl.image_from_pixel(cr1.reshape(-1, 2), W, H_IMG, PIX) - [cam1.x0, cam1.y0]
    ideal = pl.image_from_pixel(cr0.reshape(-1, 2), W, H_IMG, PIX) - [cam0.x0, cam0.y0]
    np.testing.assert_allclose(d.correct(xy1), ideal, atol=1e-9)  # measured − Δ(measured) = ideal
    assert np.abs(cr1 - cr0).max() > 0.3


def test_rectification_refuses_bad_input():
    cam, dtm = _camera(), _dtm()
    img = _texture_image()
    with pytest.raises(op.OutsideModelError, match="outside the height model"):
        op.differential_rectification(img, cam, dtm, (10, 10), (-50.0, 80.0), 1.0)
    with pytest.raises(ValueError, match=r"image has shape \(10, 10\); the camera expects \(500, 600\)"):
        op.differential_rectification(np.zeros((10, 10)), cam, dtm, (10, 10), (10.0, 80.0), 1.0)
    low = _camera(X0=(50.0, 40.0, 5.0))
    with pytest.raises(pl.PointBehindCameraError, match="ortho ground point behind the camera"):
        op.differential_rectification(img, low, dtm, (10, 10), (10.0, 80.0), 1.0)
    with pytest.raises(ValueError, match="block_rows must be a positive integer"):
        op.differential_rectification(img, cam, dtm, (10, 10), (10.0, 80.0), 1.0, block_rows=0)
    with pytest.raises(TypeError, match="model must be"):
        op.ortho_pixel_positions(cam, dtm.heights, (2, 2), (10.0, 80.0), 1.0)
    with pytest.raises(ValueError, match="width must be a positive number of pixels"):
        op.FrameCamera((0, 0, 1), np.eye(3), 50.0, 0, 10, 0.01)


# -- relief displacement --------------------------------------------------------------------------

@settings(max_examples=60, deadline=None)
@given(st.floats(20, 300), st.floats(1, 800), st.floats(300, 6000), st.floats(0.001, 0.5),
       st.floats(0, 2 * math.pi))
def test_relief_displacement_is_what_the_camera_sees(c, R_g, H, frac, az):
    h = frac * H
    X0 = np.array([1000.0, 2000.0, H])
    foot = np.array([X0[0] + R_g * math.cos(az), X0[1] + R_g * math.sin(az), 0.0])
    top = foot + [0, 0, h]
    xy = pl.project(np.array([foot, top]), X0, np.eye(3), c)
    r_foot, r_top = np.hypot(*xy.T)
    assert math.isclose(r_top - r_foot, pl.relief_displacement(r_top, h, H), rel_tol=1e-9)
    assert math.isclose(r_top - r_foot, r_foot * h / (H - h), rel_tol=1e-9)


def test_relief_displacement_agrees_with_sympy():
    f = sp.lambdify((dp.c, dp.Rg, dp.H, dp.h), dp.relief_displacement())
    r_top = sp.lambdify((dp.c, dp.Rg, dp.H, dp.h), dp.r_top())
    for c, Rg, H, h in [(153.0, 400.0, 1500.0, 40.0), (100.0, 50.0, 800.0, 300.0)]:
        assert math.isclose(pl.relief_displacement(r_top(c, Rg, H, h), h, H), f(c, Rg, H, h),
                            rel_tol=1e-12)
    assert sp.cancel(dp.occluded_length() - dp.d * dp.h / (dp.H - dp.h)) == 0
    assert sp.cancel(dp.ground_sampling_distance() - dp.p * (dp.H - dp.h) / dp.c) == 0


def test_relief_displacement_refuses_bad_input():
    with pytest.raises(ValueError, match="must be > 0"):
        pl.relief_displacement(10.0, 5.0, 0.0)
    with pytest.raises(ValueError, match="reaches the flying height"):
        pl.relief_displacement(10.0, 500.0, 500.0)
    with pytest.raises(ValueError, match="r contains a non-finite"):
        pl.relief_displacement(np.nan, 5.0, 100.0)


def test_plane_rectification_errs_by_exactly_the_relief_displacement():
    H, c = 1200.0, 120.0
    X0 = np.array([500.0, 500.0, H])
    cam_R = np.eye(3)
    ground = np.array([[0, 0, 0], [1000, 0, 0], [1000, 1000, 0], [0, 1000, 0], [300, 700, 0.0]])
    xy = pl.project(ground, X0, cam_R, c)
    to_ground = pl.ProjectiveTransform.from_estimate(xy, ground[:, :2])
    rng = np.random.default_rng(5)
    for _ in range(10):
        foot = np.r_[rng.uniform(0, 1000, 2), 0.0]
        h = rng.uniform(5, 100)
        top_xy = pl.project(foot + [0, 0, h], X0, cam_R, c)
        plan = to_ground(top_xy[None])[0]
        err = np.linalg.norm(plan - foot[:2])
        dr = pl.relief_displacement(np.hypot(*top_xy), h, H)
        assert math.isclose(err, dr * H / c, rel_tol=1e-8)
        R_g = np.linalg.norm(foot[:2] - X0[:2])
        assert math.isclose(err, R_g * h / (H - h), rel_tol=1e-8)     # derive.products
        # the error points away from the nadir
        assert np.dot(plan - foot[:2], foot[:2] - X0[:2]) > 0


# -- true orthophoto: the box building ------------------------------------------------------------

BOX = (40.0, 52.0, 30.0, 46.0, 18.0)      # Xmin, Xmax, Ymin, Ymax, height (cell edges)


def _box_dsm(order=0):
    # cells of 1 m centred on integers + 0.5: the box edges are cell edges
    def z(X, Y):
        inside = (X > BOX[0]) & (X < BOX[1]) & (Y > BOX[2]) & (Y < BOX[3])
        return np.where(inside, BOX[4], 0.0)
    return op.DTM.from_function(z, (90, 100), (0.5, 89.5), 1.0, order=order)


def _box_camera():
    return op.FrameCamera((25.0, 20.0, 120.0), pl.rotation_opk(0.01, -0.02, 0.3), 35.0,
                          W, H_IMG, 0.08)


def _render(cam, texture):
    """The image of the box scene by analytic ray casting (plane Z = 0 and the box)."""
    col, row = np.meshgrid(np.arange(cam.width), np.arange(cam.height))
    xy = pl.image_from_pixel(np.column_stack([col.ravel(), row.ravel()]), cam.width,
                             cam.height, cam.pixel_size) - [cam.x0, cam.y0]
    rays = np.column_stack([xy, np.full(len(xy), -cam.c)]) @ cam.R.T
    t_ground = -cam.X0[2] / rays[:, 2]
    # roof: Z = h inside the footprint; walls hit at their planes
    best = t_ground.copy()
    for axis, value in ((2, BOX[4]), (0, BOX[0]), (0, BOX[1]), (1, BOX[2]), (1, BOX[3])):
        with np.errstate(divide="ignore", invalid="ignore"):
            t = (value - cam.X0[axis]) / rays[:, axis]
        P = cam.X0 + t[:, None] * rays
        ok = ((t > 0) & (P[:, 0] >= BOX[0] - 1e-9) & (P[:, 0] <= BOX[1] + 1e-9)
              & (P[:, 1] >= BOX[2] - 1e-9) & (P[:, 1] <= BOX[3] + 1e-9)
              & (P[:, 2] >= -1e-9) & (P[:, 2] <= BOX[4] + 1e-9))
        best = np.where(ok & (t < best), t, best)
    P = cam.X0 + best[:, None] * rays
    return texture(P).reshape(cam.height, cam.width)


def _texture(P):
    return np.where(P[:, 2] > BOX[4] - 1e-6, 220.0 + 10 * np.sin(P[:, 0] / 2.0),
                    np.where(P[:, 2] > 1e-6, 0.0,
                             100.0 + 40 * np.sin(P[:, 0] / 6.0) * np.cos(P[:, 1] / 5.0)))


@pytest.mark.parametrize("step", [None, 0.05])
def test_visibility_matches_the_analytic_occlusion_of_a_box(step):
    cam, dsm = _box_camera(), _box_dsm()
    shape, origin = (60, 70), (20.5, 69.5)
    vis = op.visibility(cam, dsm, shape, origin, 1.0, step=step)
    grid = output_grid(shape, origin, 1.0)
    ref = np.zeros(shape, bool)
    for i in range(shape[0]):
        for j in range(shape[1]):
            X, Y = grid[i, j]
            on_roof = BOX[0] < X < BOX[1] and BOX[2] < Y < BOX[3]
            P = np.array([X, Y, BOX[4] if on_roof else 0.0])
            ref[i, j] = on_roof or not segment_hits_box(P, cam.X0, BOX)
    assert (~ref).sum() > 50                              # a real occluded area
    np.testing.assert_array_equal(vis, ref)


def test_true_orthophoto_of_the_box_scene_is_the_texture():
    cam, dsm = _box_camera(), _box_dsm()
    img = _render(cam, _texture)
    shape, origin = (60, 70), (20.5, 69.5)
    ortho, vis = op.true_orthophoto(img, cam, dsm, shape, origin, 1.0, step=0.05)
    grid = output_grid(shape, origin, 1.0)
    on_roof = ((grid[..., 0] > BOX[0]) & (grid[..., 0] < BOX[1])
               & (grid[..., 1] > BOX[2]) & (grid[..., 1] < BOX[3]))
    Z = np.where(on_roof, BOX[4], 0.0)
    truth = _texture(np.concatenate([grid, Z[..., None]], -1).reshape(-1, 3)).reshape(shape)
    assert np.all(np.isnan(ortho[~vis])) and (~vis).sum() > 50
    # away from the edges (roof outline, occlusion boundary) the values are the texture
    cls = np.where(~vis, 0, np.where(on_roof, 2, 1))
    pad = np.pad(cls, 2, mode="edge")
    stable = np.ones(shape, bool)
    for di in range(-2, 3):
        for dj in range(-2, 3):
            stable &= pad[2 + di:2 + di + shape[0], 2 + dj:2 + dj + shape[1]] == cls
    sel = stable & vis
    assert sel.sum() > 2000
    np.testing.assert_allclose(ortho[sel], truth[sel], atol=2.0)
    # an ordinary orthophoto on the bare ground (DTM) shows the roof where ground is hidden
    dtm = op.DTM(np.zeros(dsm.shape), dsm.origin, dsm.spacing)
    plain = op.differential_rectification(img, cam, dtm, shape, origin, 1.0)
    ghost = (~vis) & stable
    assert np.mean(plain[ghost] > 200.0) > 0.5          # the roof falls over the hidden ground


@pytest.mark.parametrize("shift", [0.0, 0.5])
def test_gentle_stairs_hide_nothing_even_with_pixels_on_cell_edges(shift):
    # a DSM of constant cells rising 0.1 m per cell; ortho pixel centres on the cell centres
    # (shift 0) or exactly on the cell edges (shift ½): every ray from high above is free
    dsm = op.DTM.from_function(lambda X, Y: 0.1 * np.floor(X) + 0.0 * Y, (40, 40),
                               (0.5, 39.5), 1.0, order=0)
    cam = op.FrameCamera((20.0, 20.0, 200.0), np.eye(3), 35.0, W, H_IMG, 0.06)
    vis = op.visibility(cam, dsm, (30, 30), (5.0 + shift, 35.0 - shift), 1.0)
    assert vis.all()


def test_visibility_refuses_a_camera_below_the_surface():
    dsm = _box_dsm()
    cam = op.FrameCamera((45.0, 40.0, 10.0), np.eye(3), 35.0, W, H_IMG, 0.06)
    with pytest.raises(pl.PointBehindCameraError, match="not below the projection centre"):
        op.visibility(cam, dsm, (60, 70), (20.5, 69.5), 1.0)


# -- mosaic ---------------------------------------------------------------------------------------

def test_mosaic_seamline_is_the_perpendicular_bisector():
    rng = np.random.default_rng(7)
    shape, origin, d = (30, 40), (0.0, 29.0), 1.0
    a, b = rng.uniform(0, 1, shape), rng.uniform(2, 3, shape)
    a[:5, :5] = np.nan                                     # a hole: the other image fills it
    na, nb = np.array([5.1, 10.2]), np.array([33.3, 20.7])
    mosaic, src = op.mosaic_nearest_nadir([a, b], [na, nb], origin, d)
    for i in range(shape[0]):
        for j in range(shape[1]):
            P = np.array([origin[0] + j * d, origin[1] - i * d])
            # nearer to a  <=>  on a's side of the bisector: (P − midpoint)·(nb − na) < 0
            expect = 0 if (np.dot(P - (na + nb) / 2, nb - na) < 0 and np.isfinite(a[i, j])) else 1
            assert src[i, j] == expect
            assert mosaic[i, j] == (a if expect == 0 else b)[i, j]


def test_mosaic_refuses_bad_input_and_marks_empty_pixels():
    a = np.full((2, 2), np.nan)
    m, src = op.mosaic_nearest_nadir([a, a], [[0, 0], [1, 1]], (0, 0), 1.0)
    assert np.all(src == -1) and np.all(np.isnan(m))
    with pytest.raises(ValueError, match=r"nadirs has shape \(1, 2\); expected \(2, 2\)"):
        op.mosaic_nearest_nadir([a, a], [[0, 0]], (0, 0), 1.0)
    with pytest.raises(ValueError, match="nadirs contains a non-finite"):
        op.mosaic_nearest_nadir([a, a], [[0, 0], [np.nan, 1]], (0, 0), 1.0)


@pytest.mark.parametrize("c, H, h, R_g, dZ", [(50.0, 300.0, 20.0, 80.0, 1.5), (153.0, 1500.0, 300.0, 600.0, -4.0)])
def test_height_error_and_plane_error_formulas_agree_with_monoplotting(c, H, h, R_g, dZ):
    X0 = np.array([0.0, 0.0, H])
    xy = pl.project([R_g, 0.0, h + dZ], X0, np.eye(3), c)      # the ortho pixel's image point
    seen = pl.monoplot(xy, X0, np.eye(3), c, Z=h)               # what the camera saw there
    exact, first = dp.ortho_error_from_height_error()
    subs = {dp.c: c, dp.H: H, dp.h: h, dp.Rg: R_g, dp.dZ: dZ}
    assert math.isclose(seen[0] - R_g, float(exact.subs(subs)), rel_tol=1e-9)
    assert math.isclose(float(first.subs(subs)), dZ * R_g / (H - h), rel_tol=1e-12)
    # plane rectification onto Z = 0 of the top of a tower of height h at R_g
    top = pl.project([R_g, 0.0, h], X0, np.eye(3), c)
    on_plane = pl.monoplot(top, X0, np.eye(3), c, Z=0.0)
    assert math.isclose(on_plane[0] - R_g, float(dp.plane_rectification_error().subs(subs)),
                        rel_tol=1e-9)


# -- input handling (red-team audit) --------------------------------------------------------------

def test_visibility_bounds_the_number_of_ray_steps(monkeypatch):
    """step=1e-7 used to march 5·10⁷ steps one by one (a hang); a too small step now raises."""
    dsm = op.DTM([[0, 0, 10.0, 0, 0]] * 5, (-2.0, 2.0), 1.0, order=1)
    cam = op.FrameCamera([50.0, 0, 100], np.eye(3), 50.0, 201, 201, 0.01)
    monkeypatch.setattr(op, "MAX_RAY_STEPS", 1000)
    with pytest.raises(ValueError, match=r"step = 0.001 would need 5.1e\+03 samples along the "
                                         r"longest ray .* MAX_RAY_STEPS = 1,000"):
        op.visibility(cam, dsm, (3, 3), (-1.0, 1.0), 1.0, step=1e-3)
    monkeypatch.undo()
    with pytest.raises(ValueError, match="use a larger step"):
        op.visibility(cam, dsm, (3, 3), (-1.0, 1.0), 1.0, step=1e-7)
    # 5·10⁴ steps per ray (3.8 s before, one step at a time): the same answer as a coarse step
    np.testing.assert_array_equal(op.visibility(cam, dsm, (3, 3), (-1.0, 1.0), 1.0, step=1e-4),
                                  op.visibility(cam, dsm, (3, 3), (-1.0, 1.0), 1.0, step=0.01))


@pytest.mark.parametrize("step", [0.05, 0.3])
def test_visibility_in_blocks_of_steps_equals_marching_step_by_step(step):
    cam, dsm = _box_camera(), _box_dsm(order=1)
    shape, origin = (60, 70), (20.5, 69.5)
    vis = op.visibility(cam, dsm, shape, origin, 1.0, step=step)
    # the plain loop over the steps of every ray (the implementation before the blocks)
    grid = output_grid(shape, origin, 1.0).reshape(-1, 2)
    P = np.column_stack([grid, dsm.height(grid)])
    ray = cam.X0 - P
    t_top = np.clip((dsm.heights.max() - P[:, 2]) / ray[:, 2], 0.0, 1.0)
    plan = np.hypot(ray[:, 0], ray[:, 1]) * t_top
    ref = np.ones(len(P), bool)
    active = np.flatnonzero(plan > 0)
    for k in range(1, int(np.ceil(plan.max() / step)) + 1):
        active = active[(k - 1) * step < plan[active]]
        t = np.minimum(k * step / plan[active], 1.0) * t_top[active]
        q = P[active] + t[:, None] * ray[active]
        hidden = q[:, 2] < dsm._lookup(q[:, :2]) - 1e-6
        ref[active[hidden]] = False
        active = active[~hidden]
    assert (~ref).sum() > 50
    np.testing.assert_array_equal(vis, ref.reshape(shape))


def test_dtm_keeps_its_own_copy_of_the_heights():
    heights = np.zeros((3, 3))
    dtm = op.DTM(heights, (0.0, 2.0), 1.0)
    heights[1, 1] = 100.0                       # the caller's array changes afterwards
    assert dtm.heights[1, 1] == 0.0 and dtm.height([1.0, 1.0]) == 0.0


@pytest.mark.parametrize("width", ["a", np.nan, 2.5, True])
def test_frame_camera_width_must_be_a_whole_number_of_pixels(width):
    with pytest.raises(ValueError, match="width must be a positive number of pixels, got"):
        op.FrameCamera((0, 0, 1), np.eye(3), 50.0, width, 10, 0.01)


@pytest.mark.parametrize("kwargs, error, match", [
    (dict(R=np.diag([1.0, 1.0, -1.0])), ValueError, "R has det"),
    (dict(R=np.ones((3, 3))), ValueError, "R is not orthonormal"),
    (dict(R=np.eye(2)), ValueError, r"R has shape \(2, 2\)"),
    (dict(c=0.0), ValueError, "c must be"),
    (dict(c=np.nan), ValueError, "c"),
    (dict(x0="a"), ValueError, "x0"),
    (dict(distortion=(0.1, 0.0)), TypeError, "distortion must be a photolib.Distortion"),
])
def test_frame_camera_checks_its_orientation_when_built(kwargs, error, match):
    """A bad R, c, principal point or distortion fails at construction, naming the value,
    not later inside a rectification."""
    args = dict(X0=(0, 0, 1), R=np.eye(3), c=50.0, width=10, height=10, pixel_size=0.01)
    args.update(kwargs)
    with pytest.raises(error, match=match):
        op.FrameCamera(**args)


# -- FrameCamera owns its arrays (audit P1) --------------------------------------------------------

def test_frame_camera_does_not_share_the_callers_arrays():
    X0, R = np.array([0.0, 0.0, 100.0]), np.eye(3)
    cam = op.FrameCamera(X0, R, 50.0, 101, 101, 0.01)
    before = cam.pixel([[1.0, 0.0, 0.0]])
    X0[2] = 200.0
    R[:] = pl.rotation_opk(0.1, 0.0, 0.0)
    np.testing.assert_array_equal(cam.X0, [0.0, 0.0, 100.0])
    np.testing.assert_array_equal(cam.R, np.eye(3))
    np.testing.assert_array_equal(cam.pixel([[1.0, 0.0, 0.0]]), before)


def test_frame_camera_arrays_are_read_only():
    cam = op.FrameCamera(np.array([0.0, 0.0, 100.0]), np.eye(3), 50.0, 101, 101, 0.01)
    with pytest.raises(ValueError, match="read-only"):
        cam.X0[2] = 5.0
    with pytest.raises(ValueError, match="read-only"):
        cam.R[0, 0] = 2.0
    nadir = cam.nadir
    nadir[0] = 9.0                                # a copy: writable, camera unchanged
    assert cam.X0[0] == 0.0


@pytest.mark.parametrize("args, match", [
    (("abc", 30.0, 1000.0), "r must be numeric"),
    ((50.0, "abc", 1000.0), "dh must be numeric"),
    ((50.0, 30.0, 1 + 1j), "H must be real"),
])
def test_relief_displacement_names_non_numeric_input(args, match):
    with pytest.raises(ValueError, match=match):
        op.relief_displacement(*args)
