"""Notebook helpers: the widgets' callbacks, called directly, and the live-figure plumbing."""

from __future__ import annotations

import numpy as np
import pytest

import photolib as pl
from photolib import nb
from photolib.nb import distortion as nd
from photolib.nb import projection as npj
from photolib.nb import rotations as nr
from photolib.nb.draw import frustum_segments, lines_xyz

from .explorer_checks import assert_explorer_widget, moves


def test_environment_is_complete():
    assert nb.check_environment() == []


def test_version_parsing_rejects_old_versions(monkeypatch):
    monkeypatch.setitem(nb.REQUIREMENTS, "numpy", ((99, 0), "numpy"))
    problems = nb.check_environment()
    assert len(problems) == 1 and "numpy" in problems[0] and "too old" in problems[0]


def test_rounded_removes_negative_zero():
    assert str(nb.rounded(np.array([-1e-17]))) == "[0.]"


# -- chapter 04 ------------------------------------------------------------------------------

@pytest.mark.parametrize("angles", [(10, 20, 30), (-170, 89, 45), (0, -45, -120)])
def test_rotation_report_recovers_angles(angles):
    rep = nr.rotation_report(*angles)
    assert not rep["gimbal"]
    np.testing.assert_allclose(rep["recovered"], angles, atol=1e-6)
    assert rep["orthogonality"] < 1e-12 and abs(rep["det"] - 1) < 1e-12


@pytest.mark.parametrize("phi, name, value", [(90, "ω + κ", 50.0), (-90, "ω − κ", -10.0)])
def test_rotation_report_shows_gimbal_lock(phi, name, value):
    rep = nr.rotation_report(20, phi, 30)
    assert rep["gimbal"] and rep["coupled"] == (name, value)
    assert "Gimbal lock" in rep["html"]
    # the reported split reproduces R
    np.testing.assert_allclose(pl.rotation_opk(*np.radians(rep["recovered"])), rep["R"], atol=1e-12)


def test_order_report_detects_order_dependence():
    assert nr.order_report(30, 0, 40)["angle_deg"] == 0.0
    rep = nr.order_report(30, 40, 20)
    assert rep["angle_deg"] > 1.0
    np.testing.assert_allclose(rep["R_pok"], pl.rotation_pok(*np.radians([30, 40, 20])))


def test_rotation_explorer_updates_figure_and_text():
    e = nr.RotationExplorer()
    assert e.live.output.outputs[0]["data"]["image/png"]
    assert moves(e, "phi", 90.0) == (True, True)
    assert e.report["gimbal"] and "Gimbal lock" in e.html.value
    assert_explorer_widget(e, "ω-φ-κ rotation explorer")


def test_order_explorer_updates():
    e = nr.OrderExplorer()
    assert moves(e, "kappa", 40.0) == (True, True)


def test_explorer_set_redraws_once_with_all_values():
    e = nr.RotationExplorer()
    calls = []
    original = e.draw
    e.draw = lambda **v: calls.append(v) or original(**v)
    e.set(omega=5.0, phi=6.0, kappa=7.0)
    assert calls == [{"omega": 5.0, "phi": 6.0, "kappa": 7.0}]


# -- chapter 05 ------------------------------------------------------------------------------

def test_distortion_sliders_scale_to_mm_units():
    d = nd.distortion_from_sliders(A1=-2.0, B1=1.0, C1=3.0)
    assert d.params["A1"] == pytest.approx(-2e-5) and d.params["C1"] == pytest.approx(3e-4)


def test_distortion_report_grid_is_measured_position():
    rep = nd.distortion_report(A1=-5.0, exaggeration=1.0)
    d = rep["distortion"]
    ideal = np.concatenate(nb.draw.grid_lines(*nd.HALF))
    measured = np.concatenate(rep["lines"])
    np.testing.assert_allclose(d.correct(measured), ideal, atol=1e-9)
    # barrel distortion (A1 < 0) pulls the corners inwards
    assert np.hypot(*measured[np.argmax(np.hypot(*ideal.T))]) < np.hypot(*nd.HALF)


def test_distortion_report_radial_curve_in_micrometres():
    rep = nd.distortion_report(A1=1.0, r0=10.0)
    assert float(rep["distortion"].radial_profile(10.0)) == 0.0  # zero crossing at r0
    np.testing.assert_allclose(rep["dr"], 1e-5 * rep["r"] * (rep["r"] ** 2 - 100) * 1e3)


def test_iteration_report_slow_convergence_is_not_divergence():
    rep = nd.iteration_report(A1=-2.0, radius=20.0)
    assert rep["status"] == {"fixed": nd.CONVERGED, "newton": nd.CONVERGED}
    assert len(rep["newton"]) < len(rep["fixed"])
    # A1 = −5e-4: the steps shrink by q = 3|A1|r'² ≈ 0.45 and just miss tol in 30 steps
    strong = nd.iteration_report(A1=-50.0, radius=20.0)
    assert strong["status"] == {"fixed": nd.SLOW, "newton": nd.CONVERGED}
    r = np.hypot(*strong["measured"])
    assert strong["q"] == pytest.approx(3 * 5e-4 * r**2, rel=1e-9) and strong["q"] < 1
    h = strong["fixed"]
    assert np.all(h[1:] < h[:-1])  # still shrinking at the limit
    assert "still converging" in nd.IterationExplorer(A1=-50.0).html.value


def test_iteration_report_divergence_and_fold():
    # strong pincushion: r' − Δr'(r') never reaches the corner radius, both methods fail
    gone = nd.iteration_report(A1=100.0, radius=21.5)
    assert gone["status"]["fixed"] == nd.DIVERGED and gone["measured"] is None
    # a root far outside the format, beyond the fold of the radial map: flagged, not "converged"
    fold = nd.iteration_report(A1=52.0, A2=-10.0, radius=20.0)
    assert fold["status"]["newton"] == nd.BEYOND_FOLD and np.isnan(fold["q"])


def test_fixed_point_contracts_wherever_the_widget_has_a_measured_position():
    """The chapter's claim: in the widget's range q < 1 wherever a valid measured point exists."""
    for A1 in np.linspace(-100, 100, 11):
        for A2 in (-20.0, 0.0, 20.0):
            rep = nd.iteration_report(A1=A1, A2=A2, radius=21.5)
            if rep["measured"] is not None:
                assert rep["q"] < 1, (A1, A2, rep["q"])
                assert rep["status"]["fixed"] in (nd.CONVERGED, nd.SLOW), (A1, A2)


def test_distortion_report_docstring_bound():
    r = np.hypot(*nd.HALF)
    assert 2e-5 * r**3 * 1000 == pytest.approx(202.5, abs=0.05)
    assert nd.distortion_report(A1=-2.0)["max_um"] < 2e-5 * r**3 * 1000


def test_distortion_explorers_update():
    e = nd.DistortionExplorer()
    assert moves(e, "B1", 5.0) == (True, True)
    i = nd.IterationExplorer()
    assert moves(i, "A1", -60.0) == (True, True)


# -- chapter 06 ------------------------------------------------------------------------------

def test_projection_report_matches_project():
    rep = npj.projection_report(5, -35, 20, 65, 5, 10, 40)
    _edges, ground = npj.scene_points()
    R = pl.rotation_opk(*np.radians([65, 5, 10]))
    np.testing.assert_allclose(rep["ground_xy"], pl.project(ground, [5, -35, 20], R, 40))
    assert rep["behind"] == 0


def test_projection_report_flags_points_behind_camera():
    rep = npj.projection_report(0, -40, 18, -20, 0, 0, 50)  # looking up and away
    assert rep["behind"] > 0 and np.isnan(rep["ground_xy"]).any()


def test_footprint_report_nadir_and_horizon():
    rep = npj.footprint_report(0, 0, 0, Z0=700.0, c=35.0)
    assert rep["area_km2"] == pytest.approx(0.72 * 0.48)
    assert rep["scale_number"] == pytest.approx(20000.0)
    tilted = npj.footprint_report(40, 0, 0, Z0=700.0)
    assert tilted["area_km2"] > rep["area_km2"]
    gone = npj.footprint_report(80, 0, 0)
    assert gone["corners"] is None and "does not meet" in gone["html"]


def test_footprint_horizon_angle_is_atan_c_over_half_height():
    w = npj.horizon_angle(35.0, 12.0)
    assert w == pytest.approx(np.degrees(np.arctan(35.0 / 12.0)))
    assert npj.footprint_report(w - 0.05)["corners"] is not None
    assert npj.footprint_report(w + 0.05)["corners"] is None
    assert npj.footprint_report(w - 0.05)["ray_angle_deg"] < 90 < npj.footprint_report(w + 0.05)["ray_angle_deg"]
    p = npj.horizon_angle(35.0, 18.0)  # pitch: the half width
    assert npj.footprint_report(0, -(p - 0.05))["corners"] is not None
    assert npj.footprint_report(0, -(p + 0.05))["corners"] is None


def test_footprint_explorer_reaches_the_horizon_and_follows_the_footprint():
    f = npj.FootprintExplorer()
    assert f.controls["omega"].max >= 80 and f.controls["phi"].min <= -80
    f.set(omega=40, phi=40)
    extent = f.report["extent_m"]
    assert extent > 9000 and f._ax.get_xlim()[1] >= extent and f._ax.get_ylim()[1] >= extent
    f.set(omega=70, phi=0)
    assert "clipped" in f.html.value
    f.set(omega=75)
    assert f.report["corners"] is None and "does not meet" in f.html.value
    f.set(omega=0)
    assert f._ax.get_xlim()[1] < 2000


def test_footprint_explorer_keeps_its_scale_for_a_slider_moving_back_and_forth():
    """The hysteresis of the axes: 0° ↔ 20° pitch stays on one scale (blitted updates, no
    full redraw), while the footprint always fits inside the axes."""
    f = npj.FootprintExplorer()
    f.set(phi=20.0)
    limit = f._ax.get_xlim()[1]
    for phi in (0.0, 20.0, 0.0, 20.0):
        f.set(phi=phi)
        assert f._ax.get_xlim()[1] == limit and f.live._background is not None
        assert f.report["extent_m"] <= limit
    f.set(phi=0.0, Z0=200.0)   # five times smaller: below a quarter of the axes, rescaled
    assert f._ax.get_xlim()[1] < limit / 4 + 1e-9 and f.report["extent_m"] <= f._ax.get_xlim()[1]


def test_projection_explorers_update():
    e = npj.ProjectionExplorer()
    assert moves(e, "kappa", 20.0) == (True, True)
    f = npj.FootprintExplorer()
    assert moves(f, "phi", 20.0) == (True, True)


def test_frustum_apex_and_direction():
    seg = frustum_segments([1, 2, 3], pl.rotation_opk(0.3, 0.2, 0.1), 10.0, 2.0, 1.0, scale=1.0)
    assert np.allclose(seg[:4, 0], [1, 2, 3])
    # every corner projects back to a format corner
    xy = pl.project(seg[:4, 1], [1, 2, 3], pl.rotation_opk(0.3, 0.2, 0.1), 10.0)
    np.testing.assert_allclose(np.abs(xy), [[2, 1]] * 4)


def test_lines_xyz_separates_segments_with_nan():
    x, _y, _z = lines_xyz(np.arange(12.0).reshape(2, 2, 3))
    assert np.isnan(x[2]) and x.tolist()[:2] == [0.0, 3.0]


# -- chapter 05: plumb-line calibration helpers ------------------------------------------------
def test_plumb_line_images_are_distorted_straight_lines_off_the_centre():
    lens = pl.Distortion(A1=-4e-5)
    ideal, measured = nd.plumb_line_images(lens, noise_um=0.0, extent=0.5)
    assert len(ideal) == 2 * len(nd.PLUMB_FRACTIONS)
    for p, m in zip(ideal, measured):
        np.testing.assert_allclose(m, lens.distort(p), atol=1e-12)
        # each ideal line is straight and misses the principal point
        assert np.linalg.svd(p - p.mean(axis=0), compute_uv=False)[1] < 1e-12
        assert min(abs(p[0, 0]), abs(p[0, 1])) > 0.3 * 0.5 * 12.0
        assert np.abs(p).max(axis=0).tolist() <= [9.0 + 1e-12, 6.0 + 1e-12]
    full, noisy = nd.plumb_line_images(lens, noise_um=1.0, seed=4)
    _, again = nd.plumb_line_images(lens, noise_um=1.0, seed=4)
    assert np.array_equal(np.concatenate(noisy), np.concatenate(again))  # fixed seed
    noise = np.concatenate(noisy) - lens.distort(np.concatenate(full))
    assert 0.8e-3 < noise.std() < 1.2e-3  # 1 µm per coordinate


def test_plumb_line_summary_and_figure():
    import photolib.calibration as cal

    lens = pl.Distortion(A1=-4e-5, A2=2e-8)
    _, measured = nd.plumb_line_images(lens, seed=3)
    fit = cal.plumb_line(measured, c=35.0)
    text = nd.plumb_line_summary(fit, true=lens)
    assert text.count("±") == 2 and "σ0 = 1.05 µm" in text and "error" in text
    assert nd._pm(-2.0312e-5, 6.1e-7, "mm⁻²") == "(-2.031 ± 0.061)e-05 mm⁻²"
    fig = nd.plot_plumb_lines(measured, fit)
    assert len(fig.axes) == 2 and len(fig.axes[1].lines) == 1 + 2 * len(measured)


def test_plumb_line_exaggeration_moves_points_off_their_line_only():
    pts = np.array([[0.0, 1.0], [1.0, 1.2], [2.0, 1.0]])
    shown = nd._exaggerated(pts, np.pi / 2, 1.0, 10.0)   # the line y = 1
    np.testing.assert_allclose(shown, [[0.0, 1.0], [1.0, 3.0], [2.0, 1.0]])


def test_coverage_experiment_shows_that_filling_the_format_matters():
    lens = pl.Distortion(A1=-4e-5, A2=2e-8)
    part, full = nd.coverage_experiment(lens, extents=(0.35, 1.0))
    assert part["extent"] == 0.35 and full["extent"] == 1.0
    assert part["sigma_corner_um"] > 100 * full["sigma_corner_um"]
    assert abs(full["error_corner_um"]) < 3 * full["sigma_corner_um"]
    # the σ at the corner is the covariance propagated to Δr′(r_corner)
    r = float(np.hypot(*nd.HALF))
    assert full["sigma_corner_um"] == pytest.approx(float(full["fit"].radial_sigma(r)) * 1e3)


# -- chapter 05: projection centres of a real lens ----------------------------------------------
def _measured_radius_by_roots(A1, A2, r_ideal):
    """Independent route: the real root of r − A1 r³ − A2 r⁵ = r_ideal next to r_ideal."""
    roots = np.roots([-A2, 0.0, -A1, 0.0, 1.0, -r_ideal])
    real = roots[np.abs(roots.imag) < 1e-9].real
    return float(real[np.argmin(np.abs(real - r_ideal))])


@pytest.mark.parametrize("A1, A2, tau_deg, e", [(-5e-4, 0.0, 25.0, 40.0), (-2e-5, 4e-8, 30.0, 28.0),
                                                 (3e-5, 0.0, 15.0, 35.0)])
def test_projection_centres_geometry_by_an_independent_route(A1, A2, tau_deg, e):
    lens = pl.Distortion(A1=A1, A2=A2)
    tau, c = np.radians(tau_deg), 35.0
    g = nd.projection_centres(lens, tau, c=c, exit_pupil=e)
    r_ideal = c * np.tan(tau)
    r_meas = _measured_radius_by_roots(A1, A2, r_ideal)
    assert g["r_ideal"] == pytest.approx(r_ideal, rel=1e-12)
    assert g["r_measured"] == pytest.approx(r_meas, abs=1e-9)
    assert g["tau_exit"] == pytest.approx(np.arctan(r_meas / e), abs=1e-12)
    # r′ = c·tan τ + Δr′, with Δr′ the course model's Δ at the measured point
    assert g["delta_r"] == pytest.approx(lens.delta([r_meas, 0.0])[0], abs=1e-9)
    assert g["r_measured"] == pytest.approx(c * np.tan(tau) + g["delta_r"], abs=1e-12)
    assert (g["H"], g["O_M"], g["O_exit"]) == (0.0, c, e)


def test_plot_projection_centres_draws_the_rays_at_their_angles():
    lens = pl.Distortion(A1=-5e-4)
    tau, c, e = np.radians(25.0), 35.0, 40.0
    fig = nd.plot_projection_centres(lens, tau, c=c, exit_pupil=e, pupil_separation=10.0)
    lines = {ln.get_label(): np.column_stack(ln.get_data()) for ln in fig.axes[0].lines}
    r_meas = _measured_radius_by_roots(-5e-4, 0.0, c * np.tan(tau))
    for name, start, angle, end in (("exit ray", -e, np.arctan(r_meas / e), r_meas),
                                    ("ideal ray", -c, tau, c * np.tan(tau)),
                                    ("object ray", None, tau, 0.0)):
        (u0, v0), (u1, v1) = lines[name][0], lines[name][-1]
        assert np.arctan2(v1 - v0, u1 - u0) == pytest.approx(angle, abs=1e-12), name
        assert v1 == pytest.approx(end, abs=1e-9) and u1 == pytest.approx(
            -(e + 10.0) if start is None else 0.0), name
    # the ideal ray is parallel to the object ray (τ = τ at O_M′), the exit ray is not
    assert not np.isclose(np.arctan(r_meas / e), tau)
    text = " ".join(t.get_text() for t in fig.axes[0].texts)
    assert f"Δr′ = {r_meas - c * np.tan(tau):+.2f} mm" in text


@pytest.mark.parametrize("kwargs, match", [({"tau": np.pi / 2}, "tau"), ({"tau": -0.1}, "tau"),
                                           ({"c": 0.0}, "c"), ({"exit_pupil": -1.0}, "exit_pupil"),
                                           ({"pupil_separation": -1.0}, "pupil_separation")])
def test_projection_centres_refuses_bad_input(kwargs, match):
    args = {"tau": 0.3, **kwargs}
    tau = args.pop("tau")
    with pytest.raises(ValueError, match=match):
        nd.projection_centres(pl.Distortion(A1=-2e-5), tau, **args)
    with pytest.raises(ValueError, match="radial model only"):
        nd.projection_centres(pl.Distortion(A1=-2e-5, B1=1e-6), 0.3)


def test_iteration_explorer_q_close_to_one_before_the_fold_as_the_chapter_says():
    """Chapter 05: sliders A1 = 76, A2 = −1, radius 14 give q = 0.98 at r′ = 20.8 mm, in the format."""
    rep = nd.iteration_report(A1=76.0, A2=-1.0, radius=14.0)
    r = float(np.hypot(*rep["measured"]))
    assert round(rep["q"], 2) == 0.98 and round(r, 1) == 20.8 and r < np.hypot(*nd.HALF)
    assert rep["status"]["fixed"] in (nd.CONVERGED, nd.SLOW)
    # q is the largest eigenvalue of ∂Δ/∂x: radially ∂Δr′/∂r′ = 3A1r′² + 5A2r′⁴
    assert rep["q"] == pytest.approx(3 * 76e-5 * r**2 + 5 * (-1e-8) * r**4, rel=1e-9)
