"""Chapter 06's new figures and the convergence widget: what they compute, checked against
photolib's own functions (monoplot_dtm, space_resection) rather than against themselves."""

from __future__ import annotations

import numpy as np
import pytest

import photolib as pl
from photolib.nb import aerial
from photolib.nb import projection as npj

pytestmark = pytest.mark.usefixtures("close_figures")


def test_convergence_explorer_reports_convergence_and_divergence():
    e = npj.ConvergenceExplorer(angle_error=5, centre_error=10)
    assert e.report["text"].startswith("converged in")
    X, xy, c, truth = npj.convergence_scene()
    res = pl.space_resection(X, xy, c, initial=e.start(5, 10))
    np.testing.assert_allclose(res.X0, truth[:3], atol=1e-8)
    e.set(angle_error=80)
    e.update()
    assert "diverged" in e.report["text"] or "not converged" in e.report["text"]


def test_resection_history_updates_shrink_quadratically_near_the_solution():
    X, xy, c, truth = npj.convergence_scene()
    h = npj.resection_history(X, xy, c, truth + np.r_[1.0, -1.0, 2.0, 0.01, -0.01, 0.01], 6)
    k = int(np.argmax(h < 1e-6))
    assert h[k + 1] < 10 * h[k] ** 2 + 1e-15


def test_dtm_iteration_ends_on_the_surface():
    def surface(XY):
        return 100.0 + 0.3 * XY[:, 0]
    it = npj.dtm_iteration([40.0, 10.0], [0.0, 0.0, 1000.0], np.eye(3), 100.0, surface,
                           Z_start=0.0)
    assert it["X"][2] == pytest.approx(surface(it["X"][None, :2])[0], abs=1e-8)
    np.testing.assert_allclose(it["points"][:, 2], it["heights"])
    assert np.all(np.diff(np.abs(it["heights"] - it["X"][2])) < 0)


def test_georeferencing_errors_first_order_shift_and_lever_arm_one_to_one():
    e = aerial.georeferencing_errors(2000.0, boresight_deg=(0.0, 0.02, 0.0))
    assert np.hypot(*e["centre_shift"]) == pytest.approx(2000.0 * np.radians(0.02), rel=1e-6)
    lever = aerial.georeferencing_errors(2000.0, lever_error=(0.1, 0.0, 0.0))
    np.testing.assert_allclose(np.hypot(*lever["shift"].T), 0.1, atol=1e-9)


def test_correction_sizes_are_photolibs_corrections():
    s = aerial.correction_sizes([1500.0], 120.0, r=80.0, ground=300.0)
    K = pl.refraction_constant(1800.0, 300.0)
    assert s["refraction_icao"][0] == pytest.approx(K * (80.0 + 80.0**3 / 120.0**2) * 1e3, rel=1e-9)
    assert s["curvature"][0] == pytest.approx(80.0**3 * 1500.0 / (2 * pl.aerial.EARTH_RADIUS * 120.0**2) * 1e3,
                                              rel=1e-9)


def test_static_figures_draw():
    for fig in (npj.plot_collinearity_geometry(), aerial.plot_corrections(),
                aerial.plot_georeferencing_errors()):
        assert fig.axes
