"""Chapter 07 notebook helpers: widget callbacks called directly, figures, the façade scene."""

from __future__ import annotations

import matplotlib
import numpy as np
import pytest

matplotlib.use("Agg")

from photolib.nb import plane  # noqa: E402
from photolib.transforms import AffineTransform, HelmertTransform, ProjectiveTransform  # noqa: E402

from .explorer_checks import assert_explorer_widget, assert_every_value_redraws, moves  # noqa: E402


# -- projective explorer ----------------------------------------------------------------------

@pytest.mark.parametrize("params, kind", [
    ({}, "Helmert"),
    ({"a1": 0.8, "a2": -0.6, "b1": 0.6, "b2": 0.8, "a0": 0.3}, "Helmert"),
    ({"a1": 1.2, "b2": 0.7}, "affine"),
    ({"a2": 0.3}, "affine"),
    ({"c2": -0.2}, "projective"),
])
def test_projective_report_names_the_smallest_family(params, kind):
    rep = plane.projective_report(**params)
    assert rep["kind"] == kind
    assert kind in rep["html"]
    assert (rep["horizon"] is None) == (kind != "projective")


def test_projective_report_lines_are_the_mapped_grid():
    params = {"a0": 0.2, "a1": 1.1, "a2": 0.3, "b0": -0.1, "b1": 0.2, "b2": 0.9, "c1": 0.2,
              "c2": -0.1}
    rep = plane.projective_report(**params)
    for src, out in zip(plane.square_grid(), rep["lines"]):
        # independent route: the homogeneous matrix H·(x, y, 1), divided by the third row
        H = np.array([[1.1, 0.3, 0.2], [0.2, 0.9, -0.1], [0.2, -0.1, 1.0]])
        h = np.column_stack([src, np.ones(len(src))]) @ H.T
        np.testing.assert_allclose(out, h[:, :2] / h[:, 2:], atol=1e-12)


def test_projective_horizon_is_where_the_denominator_vanishes():
    rep = plane.projective_report(c1=0.3, c2=-0.2)
    for x, y in rep["horizon"]:
        assert abs(1 + 0.3 * x - 0.2 * y) < 1e-12


def test_points_beyond_the_vanishing_line_are_not_drawn():
    rep = plane.projective_report(c1=1.5)  # 1 + 1.5x ≤ 0 for x ≤ −2/3, inside the square
    flat = np.concatenate(rep["lines"])
    assert np.isnan(flat).any() and np.isfinite(flat).any()


def test_projective_explorer_updates_figure_and_text():
    e = plane.ProjectiveExplorer()
    assert e.live.output.outputs[0]["data"]["image/png"]
    assert "projective" in e.html.value
    assert moves(e, "c1", 0.0) == (True, True)
    assert e.report["kind"] == "Helmert"
    assert moves(e, "a1", 1.5) == (True, True)
    assert e.report["kind"] == "affine"
    assert_explorer_widget(e, "projective transformation explorer")


# -- the façade and its rectification -------------------------------------------------------

def test_facade_texture_windows_door_and_outside():
    g = plane.facade_texture([[1.4, 1.6], [0.5, 0.5], [4.0, 0.5], [-0.1, 3.0], [4.0, 6.5]])
    assert g.tolist() == [50.0, 155.0, 90.0, 0.0, 0.0]


def test_control_points_project_onto_the_facade_image():
    obj, pix = plane.control_points(noise_px=0.0)
    img = plane.facade_image()
    # the façade corners are imaged where the photograph has its corners (8, 112), (152, 98), …
    np.testing.assert_allclose(pix[:4], [[8, 112], [152, 98], [150, 18], [6, 4]], atol=0.01)
    # a window centre is dark in the photograph, the wall beside it bright
    t = ProjectiveTransform.from_estimate(obj, pix)
    c, r = np.round(t([1.45, 1.65])).astype(int)
    assert img[r, c] < 80
    c, r = np.round(t([0.5, 3.0])).astype(int)
    assert img[r, c] > 140


def test_rectification_report_ranks_the_models():
    rep = plane.rectification_report()
    s = {name: f.sigma0 for name, f in rep["fits"].items()}
    assert s["projective"] < 0.03 < s["bilinear"] < s["affine"] < s["Helmert"]
    assert rep["rectified"].shape == (48, 64)
    assert "σ0" in rep["html"]
    # the projective rectification puts a window where the façade has one
    d = 8.0 / 63
    col, row = round(1.45 / d), round((6.0 - 1.65) / d)
    assert rep["rectified"][row, col] < 80


def test_moving_a_control_point_shows_in_the_residuals():
    quiet = plane.rectification_report()
    blunder = plane.rectification_report(dcol=8.0, drow=-4.0)
    assert blunder["fits"]["projective"].sigma0 > 5 * quiet["fits"]["projective"].sigma0
    assert np.argmax(np.hypot(*blunder["residuals"].T)) == 4
    np.testing.assert_allclose(blunder["pix"][4] - quiet["pix"][4], [8.0, -4.0])


def test_rectification_report_rejects_unknown_models():
    with pytest.raises(ValueError, match="model must be one of"):
        plane.rectification_report(model="conformal")


def test_helmert_fit_uses_a_right_handed_pixel_frame():
    # rows point down: without the flip a similarity cannot fit at all
    obj, pix = plane.control_points()
    mirrored = HelmertTransform.from_estimate(pix, obj).sigma0
    assert plane.rectification_report()["fits"]["Helmert"].sigma0 < mirrored / 3


def test_rectification_explorer_updates_figure_and_text():
    e = plane.RectificationExplorer()
    assert moves(e, "dcol", 6.0) == (True, True)
    assert "+6.0" in e.html.value
    assert moves(e, "model", "affine") == (True, True)
    assert "<b>affine</b>" in e.html.value
    assert_explorer_widget(e, "plane rectification explorer")


@pytest.mark.parametrize("cls, name, values", [
    (plane.ProjectiveExplorer, "c1", (0.1, 0.3)),
    (plane.RectificationExplorer, "dcol", (2.0, 8.0)),
])
def test_every_value_redraws(cls, name, values):
    # the benchmark's target is 50 ms; leave room on a loaded test machine
    assert_every_value_redraws(cls, name, values)


# -- static figures -----------------------------------------------------------------------

def test_static_figures_draw():
    import matplotlib.pyplot as plt

    src = np.array([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0], [0.5, 0.4]])
    dst = src * 2 + [[0.01, 0.0], [0.0, -0.02], [0.0, 0.0], [0.03, 0.0], [0.0, 0.01]]
    fits = [("Helmert", HelmertTransform.from_estimate(src, dst)),
            ("affine", AffineTransform.from_estimate(src, dst))]
    figs = [plane.plot_transformed_grids([("affine", AffineTransform(a2=0.3))]),
            plane.plot_residuals(dst, fits, exaggeration=10),
            plane.plot_control_points(plane.facade_image(), plane.control_points()[1]),
            plane.plot_rectifications([("a", np.zeros((4, 5)))], (0, 8, 0, 6))]
    assert [len(f.axes) for f in figs] == [1, 2, 1, 1]
    assert "σ0" in figs[1].axes[0].get_title()
    for f in figs:
        plt.close(f)


# -- the real façade: measured corners, zoom widget, rendered fiducial mark --------------------

def test_window_zoom_shows_the_picked_and_refined_corner():
    from photolib.nb import realplane
    e = realplane.WindowZoom(corner=4, half=12)
    assert_explorer_widget(e, "measured window corners: zoom and pick")
    approx, refined = realplane.measurements()
    rep = e.report
    assert rep["crop"].shape[:2] == (25, 25)
    # the crop is centred on the picked pixel, whose centre is at integer coordinates
    c0, c1, r1, r0 = rep["extent"]
    assert ((c0 + c1) / 2, (r0 + r1) / 2) == tuple(approx[4])
    assert np.array_equal(rep["refined"], refined[4])
    assert f"{refined[4, 0]:.2f}" in e.html.value
    for corner in (0, 9):
        e.set(corner=corner, half=20.0)
        assert e.report["crop"].shape[:2] == (41, 41)
        assert np.array_equal(e.report["approx"], approx[corner])


def test_zoom_report_names_a_bad_corner():
    from photolib.nb import realplane
    with pytest.raises(ValueError, match="corner"):
        realplane.zoom_report(realplane.church_photo(), corner=10)
    with pytest.raises(ValueError, match="half"):
        realplane.zoom_report(realplane.church_photo(), corner=0, half=1)


def test_facade_points_and_a_bad_height():
    from photolib.nb import realplane
    pts = realplane.facade_points(0.67)
    assert pts.shape == (10, 2) and set(pts[:, 1]) == {0.0, 0.67}
    with pytest.raises(ValueError, match="height"):
        realplane.facade_points(-1.0)


@pytest.mark.parametrize("centre", [(10.0, 10.0), (10.37, 9.81), (8.5, 11.25)])
def test_rendered_fiducial_mark_has_its_centroid_at_the_centre(centre):
    # independent route: scipy's centre of mass (row, col) of the noise-free dot above the film
    from scipy import ndimage

    from photolib.nb import realplane
    patch = realplane.render_fiducial(centre, noise=0.0)
    row, col = ndimage.center_of_mass(patch - 20.0)
    # a disc sampled by 8 × 8 sub-pixels: its centroid is off by less than a sub-pixel's
    # sixteenth of a pixel
    assert abs(col - centre[0]) < 1 / 16 and abs(row - centre[1]) < 1 / 16
    with pytest.raises(ValueError, match="outside"):
        realplane.render_fiducial((30.0, 5.0))
