"""Chapter 10 notebook helpers: the block, the widgets' callbacks and figures, called directly.

Expected values come from OpenCV (``cv2.projectPoints`` for the simulated observations), from
counting by hand (observations and unknowns of the block), or from SciPy (critical values);
not from the library under test.
"""

from __future__ import annotations

import cv2
import matplotlib
import numpy as np
import pytest

matplotlib.use("Agg")

from scipy import stats  # noqa: E402

from photolib.nb import bundle as nbb  # noqa: E402

from .explorer_checks import assert_every_value_redraws, moves  # noqa: E402


pytestmark = pytest.mark.usefixtures("close_figures")

_FLIP = np.diag([1.0, -1.0, -1.0])


def _rot(o, p, k):
    co, so, cp, sp_, ck, sk = np.cos(o), np.sin(o), np.cos(p), np.sin(p), np.cos(k), np.sin(k)
    return (np.array([[1, 0, 0], [0, co, -so], [0, so, co]])
            @ np.array([[cp, 0, sp_], [0, 1, 0], [-sp_, 0, cp]])
            @ np.array([[ck, -sk, 0], [sk, ck, 0], [0, 0, 1]]))


def test_noise_free_observations_are_what_opencv_projects():
    b = nbb.simulate_block(noise_um=0.0)
    for j, e in enumerate(b.exterior):
        rows = b.image_index == j
        R_cv = _FLIP @ _rot(*e[3:]).T
        uv, _ = cv2.projectPoints(b.points[b.point_index[rows]].reshape(-1, 1, 3),
                                  cv2.Rodrigues(R_cv)[0], -R_cv @ e[:3],
                                  np.diag([nbb.C_MM, nbb.C_MM, 1.0]), np.zeros(5))
        uv = uv.reshape(-1, 2)
        np.testing.assert_allclose(b.xy[rows], np.column_stack([uv[:, 0], -uv[:, 1]]), atol=1e-9)
        assert np.all(np.abs(b.xy[rows]) < nbb.HALF_MM)
    assert np.bincount(b.point_index).min() >= 2        # every point on at least two rays


@pytest.mark.parametrize("strips, per, nc", [(1, 2, 3), (2, 3, 4), (3, 4, 12), (2, 3, 0)])
def test_block_report_counts_by_hand(strips, per, nc):
    b = nbb.simulate_block(strips, per, 0.6, 0.0)
    rep = nbb.block_report(strips, per, 0.6, nc)
    rays = sum(int(np.sum(b.image_index == j)) for j in range(strips * per))
    n_points = len(set(b.point_index.tolist()))
    u = 6 * strips * per + 3 * (n_points - nc)
    d = 7 if nc == 0 else 0
    assert (rep["n"], rep["u"], rep["d"], rep["r"]) == (2 * rays, u, d, 2 * rays - u + d)
    assert rep["pattern"].shape == (u, u)
    assert "redundancy r" in rep["html"]


def test_block_report_too_few_control_points_says_so():
    assert "datum not fixed" in nbb.block_report(2, 3, 0.6, 2)["html"]
    assert "datum not fixed" not in nbb.block_report(2, 3, 0.6, 3)["html"]


def test_control_order_starts_at_the_corners():
    b = nbb.simulate_block()
    order = nbb.control_order(b.points)
    XY = b.points[:, :2]
    corners = {int(np.argmin(XY.sum(1))), int(np.argmax(XY.sum(1))),
               int(np.argmax(XY[:, 0] - XY[:, 1])), int(np.argmin(XY[:, 0] - XY[:, 1]))}
    assert set(order[:4].tolist()) == corners
    assert sorted(order.tolist()) == list(range(len(XY)))
    np.testing.assert_array_equal(nbb.control_order(b.points, 6), order[:6])


def test_blunder_is_found_and_critical_values_are_scipys():
    rep = nbb.blunder_report(40.0, 157, alpha=0.001)
    assert rep["found"] and rep["w"].worst == (157, 0)
    r = rep["result"].redundancy
    t = stats.t.ppf(1 - 0.0005, r - 1)
    assert rep["snooping"].critical == pytest.approx(t * np.sqrt(r / (r - 1 + t * t)), rel=1e-9)
    assert rep["w"].critical == pytest.approx(stats.norm.ppf(1 - 0.0005), rel=1e-10)
    none = nbb.blunder_report(0.0, 157)
    assert not none["found"]


def test_blunder_effect_is_proportional_to_the_redundancy_number():
    """v_k changes by −r_k·∇ for a blunder ∇ on observation k (linear model): check it."""
    k = 157
    a, b = nbb.blunder_report(0.0, k), nbb.blunder_report(50.0, k)
    dv = b["result"].residuals[k, 0] - a["result"].residuals[k, 0]
    r_k = a["result"].redundancy_numbers[k, 0]
    assert dv == pytest.approx(-r_k * 0.05, rel=2e-3)


def test_block_explorer_updates_figure_and_text():
    e = nbb.BlockExplorer()
    assert moves(e, "per_strip", 4.0) == (True, True)
    assert e.report["n_images"] == 8
    assert "photolib-explorer" in e.widget._dom_classes


def test_blunder_explorer_updates_figure_and_text():
    e = nbb.BlunderExplorer()
    assert "found" in e.html.value
    e.controls["blunder_um"].value = 0.0
    assert "not detected" in e.html.value or "another" in e.html.value
    e.controls["observation"].value = 160.0
    assert e.report["observation"] == 160


@pytest.mark.parametrize("cls, name, values", [
    (nbb.BlockExplorer, "n_control", (4.0, 8.0)),
    (nbb.BlockExplorer, "strips", (2.0, 3.0)),
    (nbb.BlunderExplorer, "blunder_um", (20.0, 60.0)),
    (nbb.PrecisionExplorer, "noise_um", (2.0, 6.0)),
])
def test_every_value_redraws(cls, name, values):
    assert_every_value_redraws(cls, name, values)


def test_static_figures_have_their_artists():
    b = nbb.simulate_block()
    control = nbb.control_order(b.points, 6)
    fig = nbb.plot_block(b, control)
    assert len(fig.axes[0].lines) == 2 * b.n_images + 2
    rep = nbb.block_report()
    fig = nbb.plot_sparsity(rep["pattern"], 36)
    assert len(fig.axes) == 1
    res, _ = nbb.adjust(b, 6)
    fig = nbb.plot_ellipses(b, res, control)
    assert len(fig.axes[0].lines) == len(b.points) - 6 + 1
    snoop = nbb.blunder_report()["snooping"]
    fig = nbb.plot_statistics(snoop.statistic, snoop.critical, snoop.flagged)
    assert len(fig.axes[0].lines) == 2 + len(snoop.flagged)
    assert nbb.coarse_pattern(rep["pattern"]).shape[0] <= 200


def test_precision_report_scales_with_sigma_and_needs_a_datum():
    a, b = nbb.precision_report(6, 2.0), nbb.precision_report(6, 4.0)
    np.testing.assert_allclose(b["std"], 2.0 * a["std"], rtol=1e-12)
    assert "datum not fixed" in nbb.precision_report(2)["html"]
    assert nbb.precision_report(2)["cov"] is None
    # more control points: the corners of the block get better, nothing gets worse (1e-9)
    few, many = nbb.precision_report(4)["std"], nbb.precision_report(12)["std"]
    new = np.setdiff1d(np.arange(len(few)), nbb.control_order(nbb.simulate_block().points, 12))
    assert np.all(many[new] <= few[new] * (1 + 1e-9)) and many[new].mean() < few[new].mean()


def test_precision_report_agrees_with_the_dense_inverse():
    """σ²·(AᵀA)⁻¹ of the full design matrix (finite differences of the collinearity model)."""
    from scipy.optimize._numdiff import approx_derivative

    b = nbb.simulate_block()
    rep = nbb.precision_report(6, 3.0)
    res, control = rep["result"], rep["control"]
    free = np.setdiff1d(np.arange(len(b.points)), control)
    M = b.n_images

    def model(x):
        ext, P = x[:6 * M].reshape(M, 6), b.points.copy()
        P[free] = x[6 * M:].reshape(-1, 3)
        out = np.empty_like(b.xy)
        for j in range(M):
            m = b.image_index == j
            R = _rot(*ext[j, 3:])
            k = (P[b.point_index[m]] - ext[j, :3]) @ R
            out[m] = -nbb.C_MM * k[:, :2] / k[:, 2:]
        return out.ravel()

    x = np.r_[res.exterior.ravel(), res.points[free].ravel()]
    A = approx_derivative(model, x, method="3-point", abs_step=1e-5)
    Q = np.linalg.inv(A.T @ A) * (3e-3) ** 2
    for n, p in enumerate(free[:12]):
        s = 6 * M + 3 * n
        np.testing.assert_allclose(rep["cov"][p], Q[s:s + 3, s:s + 3], rtol=1e-4, atol=1e-12)


def test_precision_explorer_updates():
    e = nbb.PrecisionExplorer()
    before = e.live.png
    e.controls["n_control"].value = 12.0
    assert e.live.png != before and "12 control points" in e.html.value
    e.controls["n_control"].value = 2.0
    assert "datum not fixed" in e.html.value
    assert "photolib-explorer" in e.widget._dom_classes


# -- reliability and control weighting ----------------------------------------------------------

def test_reliability_report_from_the_redundancy_numbers():
    rep = nbb.reliability_report()
    rel, res = rep["reliability"], rep["result"]
    d0 = stats.norm.ppf(1 - 0.001 / 2) + stats.norm.ppf(0.80)          # SciPy's quantiles
    assert rel.delta0 == pytest.approx(d0, rel=1e-10) and rel.delta0 == pytest.approx(4.13, 1e-3)
    rk = res.redundancy_numbers
    ok = rk > 1e-12
    np.testing.assert_allclose(rel.mdb[ok], d0 * 0.003 / np.sqrt(rk[ok]), rtol=1e-10)
    m = rep["rays"] == 3
    assert rep["table"][3]["mdb_y"] == pytest.approx(np.median(d0 * 3.0 / np.sqrt(rk[m, 1])))
    fig = nbb.plot_reliability(rep)
    assert fig.axes[0].get_yscale() == "log"


def test_blunder_effect_readjusted_equals_linearised():
    rep = nbb.blunder_effect(35, 0)
    assert np.abs(rep["points_linear"]).max() > 0.1                   # a visible effect, m
    np.testing.assert_allclose(rep["points_readjusted"], rep["points_linear"], rtol=0,
                               atol=1e-3 * np.abs(rep["points_linear"]).max())
    np.testing.assert_allclose(rep["exterior_readjusted"], rep["exterior_linear"], rtol=0,
                               atol=2e-2 * np.abs(rep["exterior_linear"]).max())
    assert rep["external_linear"] == pytest.approx(rep["external"], rel=1e-6)
    assert rep["adjusted_shift"] == pytest.approx(rep["size"] * np.sqrt(1 - rep["r"]), rel=1e-4)


def test_control_cases_counted_by_hand():
    b = nbb.simulate_block()
    n, M, P = 2 * len(b.xy), b.n_images, len(b.points)
    cases = nbb.control_cases()
    fixed = [18, 0, 18 + 6, 4 * 2 + 6]                 # fixed coordinates
    observed = [0, 18, 0, 0]                           # coordinates observed with σ
    for (name, case), nf, nc in zip(cases.items(), fixed, observed):
        res = case["result"]
        u = 6 * M + 3 * P - nf
        assert (res.n_control_observations, res.n_unknowns, res.redundancy) == (nc, u,
                                                                                n + nc - u), name
        total = res.redundancy_numbers.sum() + res.control_redundancy_numbers.sum()
        assert total == pytest.approx(res.redundancy, rel=1e-9)
    gnss, fixed6 = cases["6 XYZ, σ = 2 cm (GNSS)"], cases["6 XYZ fixed"]
    assert np.all(gnss["std_new"] > fixed6["std_new"])           # weaker control
    assert 0 < gnss["std_control"] < 20.0                         # better than σ = 20 mm
    assert np.all(cases["6 XYZ + 6 Z"]["std_new"][2] < fixed6["std_new"][2])


def test_flat_block_has_the_same_images_on_a_plane():
    hilly, flat = nbb.simulate_block(flat=False), nbb.simulate_block(flat=True)
    np.testing.assert_array_equal(flat.exterior, hilly.exterior)
    assert np.all(flat.points[:, 2] == 20.0) and np.ptp(hilly.points[:, 2]) > 10


def test_blunder_report_cache_is_the_adjustment_of_those_inputs():
    """The explorer's cached adjustment (a slider moved back redraws without adjusting) is
    the adjustment of the blundered block, done here without the cache."""
    block, clean = nbb._clean(6)
    rep = nbb.blunder_report(37.0, 120)
    res, _ = nbb.adjust(block, 6, blunder=(120, 0, 0.037), start=(clean.exterior, clean.points))
    np.testing.assert_array_equal(rep["result"].residuals, res.residuals)
    assert rep["result"].sigma0 == res.sigma0
    again = nbb.blunder_report(37.0, 120)
    assert again["result"] is rep["result"] and again["html"] == rep["html"]
    other = nbb.blunder_report(38.0, 120)
    assert other["result"] is not rep["result"]
    assert other["result"].sigma0 != rep["result"].sigma0


def test_standard_ellipses_are_the_one_sigma_contours():
    """Every outline point x satisfies xᵀ·Σ⁻¹·x = scale² (the 1σ contour), for a stack of
    random covariances; and the single-matrix form is the stack's first."""
    from photolib.nb.bundle import standard_ellipses
    rng = np.random.default_rng(3)
    A = rng.normal(size=(5, 2, 2))
    cov = A @ A.transpose(0, 2, 1) + 0.1 * np.eye(2)
    ell = standard_ellipses(cov, scale=3.0, n=17)
    assert ell.shape == (5, 17, 2)
    q = np.einsum("mni,mij,mnj->mn", ell, np.linalg.inv(cov), ell)
    np.testing.assert_allclose(q, 9.0, rtol=1e-12)
    np.testing.assert_array_equal(standard_ellipses(cov[0], 3.0, 17), ell[0])
    with pytest.raises(ValueError, match=r"\(3, 3\)"):
        standard_ellipses(np.eye(3))
