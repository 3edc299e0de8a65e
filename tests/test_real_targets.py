"""photolib.measurement's real-target code (``_real.py``: ``yellowness``, ``fit_line_tls``,
``measure_targets``, ``RealTarget``) on the real photograph ``photolib.data.yellowtargets()``
(mvtb-data), each number against a route that does not go through photolib: the blobs by
OpenCV's connected components, the binary centroid by ``scipy.ndimage.center_of_mass`` and
``cv2.moments``, the weighted centroid by a NumPy one-liner over the same weights, the lines by
the scatter matrix's eigenvectors and ``cv2.fitLine``, the diagonal centre by homogeneous cross
products, the threshold by Tsai's closed form from the central moments.

Tolerances: positions are sums of a few thousand terms of size ≤ 640, so two float64 routes
agree to ~1e-12 px; 1e-9 px leaves three orders of margin and still catches any real
difference (a pixel more or less in a blob of ~6000 moves its centroid by ~1e-3 px).
"""

from __future__ import annotations

import functools

import cv2
import numpy as np
import pytest
from scipy import ndimage, signal

from photolib.data import yellowtargets
from photolib.measurement import (
    RealTarget,
    edge_points,
    fit_line_tls,
    measure_targets,
    noise_autocorrelation,
    weighted_centroid,
    yellowness,
)

CROSS = cv2.getStructuringElement(cv2.MORPH_CROSS, (3, 3))  # = SciPy's default structure
MIN_AREA = 1000                                              # measure_targets' default


@functools.cache
def _photo():
    rgb = yellowtargets()[0]
    return rgb, tuple(measure_targets(rgb))


@functools.cache
def _yellow():
    """min(R, G) − B by NumPy alone (not photolib's yellowness)."""
    a = _photo()[0].astype(np.float64)
    return np.minimum(a[..., 0], a[..., 1]) - a[..., 2]


@functools.cache
def _components(t):
    """OpenCV's 4-connected components of Y > t (SciPy's ndimage.label default is 4-connected):
    {area: (mask, stats row)} for the blobs of at least MIN_AREA pixels, background left out."""
    n, lab, stats, _ = cv2.connectedComponentsWithStats((_yellow() > t).astype(np.uint8),
                                                        connectivity=4)
    big = {}
    for k in range(1, n):
        if stats[k, cv2.CC_STAT_AREA] >= MIN_AREA:
            big[int(stats[k, cv2.CC_STAT_AREA])] = (lab == k, stats[k])
    return big


def _targets_with_masks():
    _, targets = _photo()
    comps = _components(targets[0].threshold)
    return [(tg, *comps[tg.area]) for tg in targets]


def test_yellowness_is_min_rg_minus_b():
    y = yellowness(_photo()[0])
    assert y.dtype == np.float64 and y.shape == (480, 640)
    assert np.array_equal(y, _yellow())


def test_threshold_is_tsai_closed_form_and_the_same_for_all_targets():
    """The default threshold (h1 + h2)/2: the two levels are the roots of z² − (μ3/μ2) z − μ2 = 0
    in the centred grey value (Tsai 1985 with m1 = 0), so their mean is m1 + μ3/(2 μ2)."""
    _, targets = _photo()
    y = _yellow().ravel()
    c = y - y.mean()
    expected = y.mean() + np.mean(c**3) / (2 * np.mean(c**2))
    for tg in targets:
        # t ≈ 44 from sums of 3e5 cubes: float64 agreement ~1e-12 relative
        assert tg.threshold == pytest.approx(expected, rel=1e-9, abs=0)


def test_four_targets_are_the_blobs_opencv_finds():
    """measure_targets finds exactly the blobs of ≥ min_area pixels, with their areas, and its
    window is the blob's bounding box widened by 3 px (inclusive–exclusive)."""
    _, targets = _photo()
    comps = _components(targets[0].threshold)
    assert len(targets) == 4
    assert sorted(tg.area for tg in targets) == sorted(comps)
    for tg in targets:
        assert isinstance(tg, RealTarget)
        _, s = comps[tg.area]
        left, top, w, h = (int(s[i]) for i in (cv2.CC_STAT_LEFT, cv2.CC_STAT_TOP,
                                                cv2.CC_STAT_WIDTH, cv2.CC_STAT_HEIGHT))
        assert tg.bbox == (left - 3, top - 3, left + w + 3, top + h + 3)


@pytest.mark.parametrize("k", range(4))
def test_binary_centroid_is_scipys_and_opencvs(k):
    tg, mask, _ = _targets_with_masks()[k]
    r, c = ndimage.center_of_mass(mask)                          # (row, col)
    assert np.allclose(tg.binary, [c, r], rtol=0, atol=1e-9)
    m = cv2.moments(mask.astype(np.uint8), binaryImage=True)
    assert m["m00"] == tg.area
    assert np.allclose(tg.binary, [m["m10"] / m["m00"], m["m01"] / m["m00"]], rtol=0, atol=1e-9)


def _weights(tg, mask):
    """w = max(Y − t, 0) on the blob grown by two cross-shaped dilations (the module's window:
    pixels farther out are set to t, i.e. get no weight)."""
    grown = cv2.dilate(mask.astype(np.uint8), CROSS, iterations=2).astype(bool)
    return np.where(grown, np.maximum(_yellow() - tg.threshold, 0.0), 0.0)


@pytest.mark.parametrize("k", range(4))
def test_weighted_centroid_is_the_numpy_one_liner(k):
    tg, mask, _ = _targets_with_masks()[k]
    w = _weights(tg, mask)
    rows, cols = np.indices(w.shape)
    expected = np.array([(cols * w).sum(), (rows * w).sum()]) / w.sum()
    assert np.allclose(tg.weighted, expected, rtol=0, atol=1e-9)
    # the grey values pull it away from the binary centroid, but stay inside the blob
    assert mask[int(round(tg.weighted[1])), int(round(tg.weighted[0]))]


@pytest.mark.parametrize("k", range(4))
def test_weighted_centroid_precision_is_plausible(k):
    """σ of the weighted centroid: (a) the propagation formula σ_g/Σw·sqrt(Σ(x − x_c)²) over
    the pixels with w > 0, with σ_g the sample σ of the interior (blob eroded 4× by the cross),
    recomputed here; (b) positive and below 0.1 px; (c) a Monte Carlo of the same linear model
    (independent noise σ_g on the weighted pixels); (d) σ_g is the interior's noise, not mostly
    the illumination trend: it is at least the RMS residual r of a quadratic trend surface
    fitted to the interior and at most 1.25 r (σ_g² = r² + trend², so trend < 0.75 r)."""
    tg, mask, _ = _targets_with_masks()[k]
    interior = cv2.erode(mask.astype(np.uint8), CROSS, iterations=4).astype(bool)
    y = _yellow()
    sigma_g = np.std(y[interior], ddof=1)
    assert tg.sigma_g == pytest.approx(sigma_g, rel=1e-12)
    w = _weights(tg, mask)
    on = w > 0
    rows, cols = np.nonzero(on)
    xc = tg.weighted
    expected = sigma_g / w.sum() * np.sqrt([np.sum((cols - xc[0]) ** 2),
                                           np.sum((rows - xc[1]) ** 2)])
    assert np.allclose(tg.weighted_std, expected, rtol=1e-9, atol=0)
    assert np.all(tg.weighted_std > 0) and np.all(tg.weighted_std < 0.1)
    # (c) 400 draws: the sample σ of a σ has relative error 1/sqrt(2·399) = 3.5 %; 15 % is > 4×
    rng = np.random.default_rng(k)
    wv = w[on]
    noisy = wv + rng.normal(0.0, sigma_g, (400, wv.size))
    mc = np.column_stack([noisy @ cols, noisy @ rows]) / noisy.sum(axis=1)[:, None]
    assert np.allclose(mc.std(axis=0, ddof=1), tg.weighted_std, rtol=0.15, atol=0)
    # (d)
    r_i, c_i = np.nonzero(interior)
    A = np.column_stack([np.ones_like(c_i), c_i, r_i, c_i**2, c_i * r_i, r_i**2]).astype(float)
    v = y[interior]
    res = v - A @ np.linalg.lstsq(A, v, rcond=None)[0]
    rms = np.sqrt(res @ res / (len(v) - 6))
    assert rms <= tg.sigma_g <= 1.25 * rms


@pytest.mark.parametrize("k", range(4))
def test_interior_noise_correlation_and_the_centroid_factor(k):
    """ρ of the interior noise by SciPy's ``correlate2d`` of this test's own trend residuals
    (normalised by the correlated mask: the pairs inside the interior), and the factor
    ``noise_factor`` = √(Σ ρ over lags ≤ 1): neighbours correlate by about 1/2 (demosaicing
    and JPEG), so the independent-noise σ of the centroid is about half the true one."""
    tg, mask, _ = _targets_with_masks()[k]
    interior = cv2.erode(mask.astype(np.uint8), CROSS, iterations=4).astype(bool)
    y = _yellow()
    r_i, c_i = np.nonzero(interior)
    A = np.column_stack([np.ones_like(c_i), c_i, r_i, c_i**2, c_i * r_i, r_i**2]).astype(float)
    e = np.zeros(y.shape)
    e[r_i, c_i] = y[r_i, c_i] - A @ np.linalg.lstsq(A, y[r_i, c_i], rcond=None)[0]
    r0, r1, c0, c1 = r_i.min(), r_i.max() + 1, c_i.min(), c_i.max() + 1
    ew, mw = e[r0:r1, c0:c1], interior[r0:r1, c0:c1].astype(float)
    sums = signal.correlate2d(ew, ew, mode="full")
    pairs = signal.correlate2d(mw, mw, mode="full")
    cr, cc = np.array(sums.shape) // 2
    window = (slice(cr - 1, cr + 2), slice(cc - 1, cc + 2))
    ref = (sums[window] / pairs[window]) / (sums[cr, cc] / pairs[cr, cc])
    rho = noise_autocorrelation(y, interior)
    assert np.allclose(rho, ref, rtol=0, atol=1e-10)
    assert tg.noise_factor == pytest.approx(np.sqrt(ref.sum()), rel=1e-10)
    assert 0.35 < rho[1, 2] < 0.7 and 0.35 < rho[2, 1] < 0.7  # the neighbours
    assert 1.6 < tg.noise_factor < 2.5


def test_centroid_sigma_under_correlated_noise_grows_by_the_noise_factor():
    """Monte Carlo: a flat square target (weights g − t) with white noise boxed 2 × 2
    (ρ = 1/2 to a side, 1/4 to a corner: Σρ = 4 over lags ≤ 1). The sample σ of the weighted
    centroid over 300 draws is ``weighted_centroid``'s independent-noise σ times √(Σ ρ) of
    ``noise_autocorrelation`` on one draw — to 15 % (σ of a sample σ over 300 draws: 4 %)."""
    rng = np.random.default_rng(2)
    size, lo, hi, sigma = 48, 14, 34, 3.0
    base = np.zeros((size, size))
    base[lo:hi, lo:hi] = 100.0
    inside = np.zeros((size, size), bool)
    inside[lo + 2:hi - 2, lo + 2:hi - 2] = True

    def draw():
        w = rng.normal(0.0, 1.0, (size + 1, size + 1))
        boxed = (w[:-1, :-1] + w[1:, :-1] + w[:-1, 1:] + w[1:, 1:]) / 2  # σ 1, correlated
        return np.where(base > 0, base + sigma * boxed, 0.0)

    first = draw()
    rho = noise_autocorrelation(first, inside)
    assert rho.sum() == pytest.approx(4.0, abs=0.6)
    white_sigma = weighted_centroid(first, 0.0, sigma).std
    samples = np.array([weighted_centroid(draw(), 0.0).colrow for _ in range(300)])
    np.testing.assert_allclose(samples.std(axis=0, ddof=1),
                               white_sigma * np.sqrt(rho.sum()), rtol=0.15)
    # and independent-noise σ alone would be off by the factor 2
    assert np.all(samples.std(axis=0, ddof=1) > 1.5 * white_sigma)


def test_noise_autocorrelation_refuses_bad_input():
    with pytest.raises(ValueError, match=r"image must be 2-D and mask of its shape"):
        noise_autocorrelation(np.zeros((4, 4)), np.ones((3, 3), bool))
    with pytest.raises(ValueError, match="the mask has 4 pixels"):
        noise_autocorrelation(np.zeros((4, 4)), np.eye(4, dtype=bool))
    with pytest.raises(ValueError, match="max_lag must be ≥ 0, got -1"):
        noise_autocorrelation(np.zeros((4, 4)), np.ones((4, 4), bool), max_lag=-1)
    with pytest.raises(ValueError, match="no noise to measure"):
        noise_autocorrelation(np.ones((6, 6)), np.ones((6, 6), bool))
    bad = np.zeros((6, 6))
    bad[2, 3] = np.nan
    with pytest.raises(ValueError, match="image contains a non-finite value nan"):
        noise_autocorrelation(bad, np.ones((6, 6), bool))


def _side_points(tg, i, edges, band=3.0):
    """Edge points near side i (between corners i−1 and i, the line of side fit i): within
    ``band`` px of the segment and in its middle 60 % (away from the rounded corners)."""
    a, b = tg.corners[i - 1], tg.corners[i]
    d = (b - a) / np.linalg.norm(b - a)
    rel = edges - a
    s = rel @ d / np.linalg.norm(b - a)
    dist = np.abs(rel @ [-d[1], d[0]])
    return edges[(s > 0.2) & (s < 0.8) & (dist < band)], a, d


@functools.cache
def _edges():
    return edge_points(_yellow(), 20.0).colrow


@pytest.mark.parametrize("k", range(4))
def test_fit_line_tls_is_the_scatter_eigenvector_and_cv2_fitline(k):
    """On the subpixel edge points of each side of a real target: the normal is the scatter
    matrix's eigenvector of the smallest eigenvalue (eigh), the direction its principal one
    and cv2.fitLine's (DIST_L2); σ0²·(N − 2) is that smallest eigenvalue."""
    tg = _photo()[1][k]
    for i in range(4):
        p, _, _ = _side_points(tg, i, _edges())
        assert len(p) >= 10
        n, d, s0 = fit_line_tls(p)
        m = p.mean(axis=0)
        lam, vec = np.linalg.eigh((p - m).T @ (p - m))           # ascending
        # eigen/singular vectors of a 2 × 2 float64 problem: agreement ~1e-15; 1e-12 allows
        # for the spread of N ≈ 20-60 points of size ~400 in the sums
        assert abs(abs(n @ vec[:, 0]) - 1) < 1e-12
        assert abs(n @ vec[:, 1]) < 1e-12                         # n ⟂ principal direction
        assert d == pytest.approx(n @ m, abs=1e-9)
        assert s0**2 * (len(p) - 2) == pytest.approx(lam[0], rel=1e-9, abs=1e-12)
        # cv2.fitLine works in float32 (points and the angle): on centred points of size
        # ≤ 60 px the rounding is ~4e-6 px over a span ≥ 20 px, so the direction agrees to
        # ~2e-7; 1e-6 as asked
        vx, vy, _, _ = cv2.fitLine((p - m).astype(np.float32), cv2.DIST_L2, 0, 0.01, 0.01).ravel()
        assert abs(n[0] * vx + n[1] * vy) < 1e-6                   # its direction ⟂ n
        assert abs(np.hypot(vx, vy) - 1) < 1e-6


@pytest.mark.parametrize("k", range(4))
def test_sides_corners_and_diagonal_centre(k):
    """The corners are a convex quadrilateral around the blob; the centre is the intersection
    of the diagonals (homogeneous cross products); each side's σ0 is the spread of the edge
    points about that side's line."""
    tg = _photo()[1][k]
    _, mask, _ = _targets_with_masks()[k]
    C = np.column_stack([tg.corners, np.ones(4)])
    centre_h = np.cross(np.cross(C[0], C[2]), np.cross(C[1], C[3]))
    # corners are ~400 px: the cross products are exact to ~1e-13 relative, 1e-9 px is safe
    assert np.allclose(tg.centre, centre_h[:2] / centre_h[2], rtol=0, atol=1e-9)
    # convex and consistently ordered: the four edge turns have one sign
    e = np.roll(tg.corners, -1, axis=0) - tg.corners
    turns = e[:, 0] * np.roll(e, -1, axis=0)[:, 1] - e[:, 1] * np.roll(e, -1, axis=0)[:, 0]
    assert np.all(turns > 0) or np.all(turns < 0)
    assert mask[int(round(tg.centre[1])), int(round(tg.centre[0]))]
    assert tg.side_points >= 4 * 5                                 # ≥ 5 edge points per side
    for i in range(4):
        p, a, d = _side_points(tg, i, _edges())
        r = (p - a) @ [-d[1], d[0]]
        rms = np.sqrt(np.mean((r - r.mean()) ** 2))
        # a subset of the fit's own points (middle 60 % of the side, within 3 px) about a line
        # that is their fit's but for the selection: the same spread within a factor 2
        assert 0.5 * tg.side_sigma[i] <= rms <= 2 * tg.side_sigma[i]
        # the line runs through them: a subset's mean residual is ~σ0/sqrt(N) from a fit of
        # all its points, plus the edge's bend between middle and ends; 1·σ0 bounds both
        assert abs(r.mean()) < tg.side_sigma[i]
        assert 0 < tg.side_sigma[i] < 1.5                          # paper edges: < 1.5 px


def test_weighted_centroid_via_photolib_on_the_window_is_the_targets():
    """The same weights through the public weighted_centroid on the whole image (not the
    window) give the target's value: the window offset is added correctly."""
    tg, mask, _ = _targets_with_masks()[0]
    grown = cv2.dilate(mask.astype(np.uint8), CROSS, iterations=2).astype(bool)
    img = np.where(grown, _yellow(), tg.threshold)
    wc = weighted_centroid(img, tg.threshold)
    assert np.allclose(wc.colrow, tg.weighted, rtol=0, atol=1e-9)


# -- bad input ------------------------------------------------------------------------------

@pytest.mark.parametrize("shape", [(20, 30), (20, 30, 2), (3,)])
def test_yellowness_wrong_shape_names_the_shape(shape):
    with pytest.raises(ValueError, match=rf"\(H, W, 3\).*got shape \({shape[0]},"):
        yellowness(np.zeros(shape))


def test_yellowness_and_measure_targets_refuse_nan_naming_it():
    rgb = _photo()[0].astype(float)
    rgb[5, 7, 1] = np.nan
    for f in (yellowness, measure_targets):
        with pytest.raises(ValueError, match=r"rgb contains a non-finite value nan at index "
                                             r"\(5, 7, 1\)"):
            f(rgb)


def test_measure_targets_on_a_grey_image():
    """A noisy grey image (independent noise per channel): no blob of min_area pixels, and
    the message names the threshold, min_area and the largest blob. A perfectly flat grey
    image has a constant yellowness: 'no target', with moment_threshold's 'constant' error naming the value."""
    rng = np.random.default_rng(3)
    grey = np.clip(128 + rng.normal(0, 3, (120, 160, 3)), 0, 255).astype(np.uint8)
    with pytest.raises(ValueError, match=r"no target: .*threshold -?\d+\.\d.*min_area = 1000 "
                                         r"pixels \(largest \d+\)"):
        measure_targets(grey)
    with pytest.raises(ValueError, match=r"no target: the yellowness min\(R, G\) − B has one "
                                         r"value .*constant \(all grey values 0\)"):
        measure_targets(np.full((50, 60, 3), 128, np.uint8))


def test_measure_targets_min_area_above_every_blob():
    biggest = max(tg.area for tg in _photo()[1])
    with pytest.raises(ValueError, match=rf"min_area = {biggest + 1} pixels \(largest {biggest}\)"):
        measure_targets(_photo()[0], min_area=biggest + 1)


@pytest.mark.parametrize("points, message", [
    (np.zeros((5, 3)), r"\(N, 2\) with N ≥ 3, got shape \(5, 3\)"),
    (np.zeros((2, 2)), r"got shape \(2, 2\)"),
    (np.zeros(6), r"got shape \(6,\)"),
    (np.ones((4, 2)), r"the points coincide"),
    ([[0.0, 0.0], [1.0, 1.0], [2.0, np.nan]], r"points contains a non-finite value nan at index "
                                               r"\(2, 1\)"),
    ([[0.0, 0.0], [np.inf, 1.0], [2.0, 2.0]], r"points contains a non-finite value inf"),
])
def test_fit_line_tls_bad_points(points, message):
    with pytest.raises(ValueError, match=message):
        fit_line_tls(points)
