"""Chapter 02 notebook helpers: the widgets' callbacks and figures, called directly.

Expected values come from the ray geometry typed out here, root finding on the light cone,
and SciPy's Bessel functions, not from :mod:`photolib.optics`.
"""

from __future__ import annotations

import math

import matplotlib
import numpy as np
import pytest
from scipy import optimize, special

matplotlib.use("Agg")

from photolib.nb import optics as no  # noqa: E402

from .explorer_checks import assert_explorer_widget, assert_every_value_redraws, moves  # noqa: E402


pytestmark = pytest.mark.usefixtures("close_figures")


def _through(ray, point, tol=1e-9):
    """Does the polyline segment after the lens (or before it) pass through ``point``?"""
    for p, q in zip(ray[:-1], ray[1:]):
        cross = (q[0] - p[0]) * (point[1] - p[1]) - (q[1] - p[1]) * (point[0] - p[0])
        if abs(cross) < tol * max(1.0, np.hypot(*(q - p))):
            return True
    return False


@pytest.mark.parametrize("a, f", [(150.0, 50.0), (80.0, 60.0), (400.0, 20.0)])
def test_construction_rays_meet_where_the_lens_equation_says(a, f):
    rays = no.lens_rays(a, f, 10.0)
    ap = 1.0 / (1.0 / f - 1.0 / a)
    tip = np.array([ap, -10.0 * ap / a])
    for ray in rays:
        np.testing.assert_allclose(ray[-1], tip, atol=1e-9)
        np.testing.assert_allclose(ray[0], [-a, 10.0])
    assert _through(rays[0][1:], np.array([f, 0.0]))      # parallel ray → F'
    assert _through(rays[1], np.array([0.0, 0.0]))         # centre ray
    assert _through(rays[2][:2], np.array([-f, 0.0]))      # through F → parallel
    assert rays[2][1, 1] == rays[2][2, 1]


def test_thin_lens_report_real_and_virtual():
    rep = no.thin_lens_report(150.0, 50.0)
    assert rep["real"] and rep["image_distance"] == pytest.approx(75.0)
    assert rep["scale_number"] == pytest.approx(2.0) and rep["image_height"] == pytest.approx(-5.0)
    rep = no.thin_lens_report(40.0, 50.0)
    assert not rep["real"] and np.isnan(rep["image_distance"]) and "no real image" in rep["html"]
    assert len(no.thin_lens_report(50.0, 50.0)["rays"]) == 3   # a = f: rays parallel, no crash
    assert no.thin_lens_report(50.0, 50.0)["virtual"] is None


@pytest.mark.parametrize("a, f", [(20.0, 50.0), (35.0, 50.0), (10.0, 100.0)])
def test_virtual_image_is_where_the_rays_after_the_lens_meet_backwards(a, f):
    rep = no.thin_lens_report(a, f, 10.0)
    zv, yv = rep["virtual"]
    # lines of rays 1 and 2 after the lens, intersected by linear algebra
    rays = rep["rays"]
    (p1, q1), (p2, q2) = rays[0][1:], rays[1][1:]
    A = np.column_stack([q1 - p1, -(q2 - p2)])
    t = np.linalg.solve(A, p2 - p1)
    np.testing.assert_allclose(p1 + t[0] * (q1 - p1), [zv, yv], atol=1e-9)
    assert zv < -a and yv > 10.0                    # farther than the object, upright, larger
    assert 1 / a + 1 / zv == pytest.approx(1 / f)   # the imaging equation with a' = z_v < 0
    assert "virtual image" in rep["html"]


def _cone_blur(a_x, a, f, k):
    apx, ap = a_x * f / (a_x - f), a * f / (a - f)
    return f / k * abs(apx - ap) / apx


@pytest.mark.parametrize("k, focus, u", [(8.0, 5.0, 30.0), (2.8, 2.0, 20.0), (16.0, 3.0, 40.0)])
def test_dof_report_limits_are_the_roots_of_the_cone_blur(k, focus, u):
    rep = no.dof_report(k, focus, u)
    a, f, um = focus * 1e3, no.F_MM, u * 1e-3
    near = optimize.brentq(lambda x: _cone_blur(x, a, f, k) - um, 1.001 * f, a)
    assert rep["dof"].near == pytest.approx(near, rel=1e-9)
    if np.isfinite(rep["dof"].far):
        far = optimize.brentq(lambda x: _cone_blur(x, a, f, k) - um, a, 1e9)
        assert rep["dof"].far == pytest.approx(far, rel=1e-8)
    else:
        assert _cone_blur(1e12, a, f, k) <= um * (1 + 1e-9)
    blur = [_cone_blur(x, a, f, k) * 1e3 for x in rep["distances"]]
    np.testing.assert_allclose(rep["blur"], blur, rtol=1e-9, atol=1e-12)
    assert "near limit" in rep["html"]


def test_airy_report_against_scipy():
    rep = no.airy_report(550.0, 8.0, 4.0)
    lam, k = 0.55, 8.0
    assert rep["radius_um"] == pytest.approx(special.jn_zeros(1, 1)[0] / math.pi * lam * k)
    v = np.pi * rep["r_um"] / (lam * k)
    with np.errstate(invalid="ignore", divide="ignore"):
        ref = np.where(v == 0, 1.0, (2 * special.j1(v) / v) ** 2)
    np.testing.assert_allclose(rep["profile"], ref, atol=1e-5)   # table interpolation
    psf = rep["pixel_psf"]
    assert psf.sum() == pytest.approx(1.0)
    np.testing.assert_allclose(psf, psf.T, atol=1e-15)
    np.testing.assert_allclose(psf, psf[::-1, ::-1], atol=1e-15)
    # centre pixel share by a fine midpoint rule on SciPy's J1
    t = (np.arange(400) + 0.5) / 400 * 20.0 - 10.0
    X, Y = np.meshgrid(t, t)
    vv = np.pi * np.hypot(X, Y) / (lam * k)
    inten = (2 * special.j1(vv) / vv) ** 2
    centre = inten[np.maximum(abs(X), abs(Y)) < 2.0].sum() / inten.sum()
    assert psf[2, 2] == pytest.approx(centre, abs=2e-3)


def test_explorers_update_figure_and_text():
    e = no.ThinLensExplorer()
    assert e.live.output.outputs[0]["data"]["image/png"]
    assert moves(e, "a", 300.0) == (True, True)
    assert e.report["image_distance"] == pytest.approx(300.0 * 50.0 / 250.0)
    assert moves(e, "a", 30.0) == (True, True)
    assert "no real image" in e.html.value and not e._image.get_visible()
    assert moves(e, "f", 25.0) == (True, True) and e._image.get_visible()
    assert_explorer_widget(e, "thin lens explorer")

    e = no.DepthOfFieldExplorer()
    assert moves(e, "k", 16.0) == (True, True)
    assert moves(e, "focus_m", 15.0) == (True, True)
    assert np.isinf(e.report["dof"].far) and "∞" in e.html.value
    assert moves(e, "u_um", 10.0) == (True, True)
    assert e._band.get_x() == pytest.approx(e.report["dof"].near / 1e3)
    assert_explorer_widget(e, "depth of field explorer")

    e = no.AiryExplorer()
    assert moves(e, "k", 16.0) == (True, True)
    assert "10.73 µm" in e.html.value
    assert moves(e, "wavelength_nm", 450.0) == (True, True)
    assert moves(e, "pixel_um", 2.0) == (True, True)
    assert_explorer_widget(e, "Airy disk explorer")


@pytest.mark.parametrize("cls, name, values", [
    (no.ThinLensExplorer, "a", (100.0, 300.0)),
    (no.DepthOfFieldExplorer, "k", (2.8, 11.0)),
    (no.AiryExplorer, "k", (4.0, 11.0)),
])
def test_every_value_redraws(cls, name, values):
    assert_every_value_redraws(cls, name, values)


def test_static_figures_have_their_artists():
    fig = no.plot_refraction(1.5, 1.0, angles_deg=(10, 30, 60))
    assert len(fig.axes[0].lines) == 1 + 2 * 3
    dashed = [ln for ln in fig.axes[0].lines if ln.get_linestyle() == "--"]
    assert len(dashed) == 1                       # only 60° is beyond 41.8°: TIR
    assert len(no.plot_dispersion().axes[0].lines) == 4 + 3
    assert len(no.plot_chromatic_shift().axes[0].lines) == 2
    assert len(no.plot_airy_profile().axes[0].lines) == 3
    fig = no.plot_vignetting_map()
    img = fig.axes[0].images[0].get_array()
    assert img.max() == pytest.approx(1.0, abs=1e-3)
    assert img.min() == pytest.approx(math.cos(math.atan(math.hypot(18, 12) / 24)) ** 4, rel=1e-9)
    fig = no.plot_pinhole_blur(100.0, 550.0)
    d_opt = fig.axes[0].lines[3].get_xdata()[0]
    res = optimize.minimize_scalar(lambda d: d + 2 * 1.21967 * 550e-6 * 100 / d,
                                   bounds=(0.05, 1.0), method="bounded")
    assert d_opt == pytest.approx(res.x, rel=1e-4)
    assert len(no.plot_stereo_acuity().axes[0].lines) == 3
