"""Chapter 11's teaching code (the weighted centroid and the least-squares matching written out
in the notebook) agrees with photolib to 1e-9 on targets and textures of this test's own (not
the notebook's), and both are as accurate as derived here.
"""

from __future__ import annotations

import numpy as np
import pytest
from scipy.special import erf

import photolib as pl

from .teaching import teaching_functions

STEM = "11-image-measurement"
CODE = teaching_functions(STEM)


def test_the_teaching_cells_define_centroid_and_lsm():
    assert set(CODE) == {"centroid", "lsm"}


# -- weighted centroid ------------------------------------------------------------------------

SIZE = 31            # window 31 × 31 px
S = 1.5              # Gaussian σ of the blob, px
VOLUME = 20000.0     # Σ of the blob's grey values (peak VOLUME/(2π S²) ≈ 1400)
B = 50.0             # background grey value
SIGMA_N = 2.0        # grey-value noise


def _pixel_gaussian(x0, y0):
    """A Gaussian blob integrated over each pixel (erf), centre (x0, y0) = (col, row)."""
    k = np.arange(SIZE)

    def p(c):
        return 0.5 * (erf((k + 0.5 - c) / (S * np.sqrt(2))) - erf((k - 0.5 - c) / (S * np.sqrt(2))))
    return VOLUME * np.outer(p(y0), p(x0))


POSITIONS = [(15.0, 15.0), (15.37, 14.81), (14.62, 15.5), (15.13, 16.44)]


@pytest.mark.parametrize("x0, y0", POSITIONS)
@pytest.mark.parametrize("t", [B - 12 * SIGMA_N, B - 5 * SIGMA_N, B + 3 * SIGMA_N, B + 150.0])
def test_teaching_centroid_is_photolibs(x0, y0, t):
    rng = np.random.default_rng(int(100 * x0 + y0))
    img = B + _pixel_gaussian(x0, y0) + rng.normal(0, SIGMA_N, (SIZE, SIZE))
    mine = CODE["centroid"](img, t)
    assert np.allclose(mine, pl.weighted_centroid(img, t).colrow, rtol=0, atol=1e-9)


@pytest.mark.parametrize("x0, y0", POSITIONS)
@pytest.mark.parametrize("depth", [5, 8, 12])
def test_centroid_below_the_background_is_the_derived_mean(x0, y0, depth):
    """With t = B − δ, δ = depth·σ_n ≥ 5σ_n, no pixel is clipped (P(n < −5σ) = 3e-7), so every
    pixel of the window has the weight w = G + δ + n. The pixel-integrated Gaussian's weighted
    mean is (x0, y0) to ~e^(−2π²S²) ≈ 1e-19 (Poisson summation) and its tail beyond the window
    (≥ 9.6 S away) is < 1e-20 of its volume, so E[Σx·w] = V·x0 + δ·N·x̄ and
    E[Σw] = V + δ·N with x̄ = (SIZE − 1)/2 the window's mid-pixel: the pedestal δ pulls the
    centroid towards x̄ by δN/(V + δN) of the way. Noise: σ = σ_n/Σw·sqrt(Σ(x − x_c)²); the
    test allows 4.5σ (two-sided probability 7e-6 per coordinate)."""
    rng = np.random.default_rng(int(1000 * x0 + 10 * y0) + depth)
    img = B + _pixel_gaussian(x0, y0) + rng.normal(0, SIGMA_N, (SIZE, SIZE))
    delta, N, mid = depth * SIGMA_N, SIZE * SIZE, (SIZE - 1) / 2
    expected = (VOLUME * np.array([x0, y0]) + delta * N * mid) / (VOLUME + delta * N)
    rows, cols = np.indices(img.shape)
    total = VOLUME + delta * N
    sigma = SIGMA_N / total * np.sqrt([np.sum((cols - expected[0]) ** 2),
                                       np.sum((rows - expected[1]) ** 2)])
    mine = CODE["centroid"](img, B - delta)
    theirs = pl.weighted_centroid(img, B - delta, sigma_g=SIGMA_N)
    for c in (mine, theirs.colrow):
        assert np.all(np.abs(c - expected) <= 4.5 * sigma)
    # photolib's stated σ is this σ but with the observed Σw (relative scatter σ_n·√N/Σw
    # ≈ 1.5e-3 from the noise) and its own centre (a 0.05 px shift changes Σ(x − x_c)² by
    # ~3e-5 relative): 4.5 times the first plus 1e-4
    assert np.allclose(theirs.std, sigma, rtol=4.5 * SIGMA_N * np.sqrt(N) / total + 1e-4, atol=0)
    # the derivation matters: off the mid-pixel the true centre itself lies outside this bound
    assert np.any(np.abs(expected - [x0, y0]) > 4.5 * sigma) or (x0, y0) == (mid, mid)


@pytest.mark.parametrize("t", [B + 150.0, B + 500.0])
@pytest.mark.parametrize("x0, y0", [(15.0, 15.0), (15.5, 15.0), (14.5, 15.5), (15.0, 16.5)])
def test_centroid_above_the_background_is_exact_on_lattice_symmetric_centres(x0, y0, t):
    """Noise-free, with a threshold that clips the blob's rim: at centres on pixel centres or
    pixel corners the clipped weights are mirror-symmetric on the pixel grid, so the centroid is
    the centre exactly (to rounding, ~1e-13 px). (At other sub-pixel positions the clipped
    rim is not symmetric on the grid and the centroid is biased by up to ~0.05 px for this
    blob; no closed-form bound is claimed for those.)"""
    img = B + _pixel_gaussian(x0, y0)
    for c in (CODE["centroid"](img, t), pl.weighted_centroid(img, t).colrow):
        assert np.allclose(c, [x0, y0], rtol=0, atol=1e-9)


def test_empty_window_raises_clear_valueerrors():
    img = B + np.random.default_rng(0).normal(0, SIGMA_N, (SIZE, SIZE))
    t = float(img.max()) + 1.0
    with pytest.raises(ValueError, match=rf"target is empty: no pixel above t = {t}"):
        CODE["centroid"](img, t)
    with pytest.raises(ValueError, match=rf"target is empty: no pixel is above the background "
                                         rf"{t:g} \(maximum grey value {float(img.max()):g}\)"):
        pl.weighted_centroid(img, t)


# -- least-squares matching -----------------------------------------------------------------

WAVES = [(30.0, 0.35, 0.20, 0.0), (25.0, -0.15, 0.40, 1.0), (15.0, 0.45, 0.30, 0.5)]
HALF = 10            # 21 × 21 template
GRID = 61            # 61 × 61 search image


def _F(c, r):
    return 100.0 + sum(a * np.sin(u * c + v * r + p) for a, u, v, p in WAVES)


def _F_grad(c, r):
    cos = [a * np.cos(u * c + v * r + p) for a, u, v, p in WAVES]
    return (sum(k * u for k, (_, u, _, _) in zip(cos, WAVES)),
            sum(k * v for k, (_, _, v, _) in zip(cos, WAVES)))


def _template_xy():
    y, x = np.mgrid[-HALF:HALF + 1, -HALF:HALF + 1].astype(float)
    return x.ravel(), y.ravel()


def _search():
    r, c = np.mgrid[:GRID, :GRID].astype(float)
    return _F(c, r)


def _bilinear(img, c, r):
    """Bilinear interpolation of img's samples at (c, r) (this test's own)."""
    c0, r0 = np.floor(c).astype(int), np.floor(r).astype(int)
    u, v = c - c0, r - r0
    return ((1 - u) * (1 - v) * img[r0, c0] + u * (1 - v) * img[r0, c0 + 1]
            + (1 - u) * v * img[r0 + 1, c0] + u * v * img[r0 + 1, c0 + 1])


CASES = [(30.37, 29.81, 0.0, 1.0), (29.62, 30.15, 5.0, 0.9), (30.5, 30.0, 0.0, 1.0),
         (31.13, 28.77, -3.0, 1.1)]


def _case(a0, b0, r0, r1, noise=0.0, seed=0):
    """Template f = r0 + r1·F(a0 + x, b0 + y) from the analytic texture (no interpolation)."""
    x, y = _template_xy()
    f = r0 + r1 * _F(a0 + x, b0 + y)
    if noise:
        f = f + np.random.default_rng(seed).normal(0, noise, f.shape)
    return f.reshape(2 * HALF + 1, 2 * HALF + 1), _search(), (round(a0), round(b0))


@pytest.mark.parametrize("a0, b0, r0, r1", CASES)
def test_teaching_lsm_is_photolibs(a0, b0, r0, r1):
    f, g, start = _case(a0, b0, r0, r1)
    q, iterations = CODE["lsm"](f, g, start)
    res = pl.least_squares_matching(f, g, start)
    assert iterations == res.iterations
    assert np.allclose(q, res.params, rtol=0, atol=1e-9)


def _first_order(a0, b0, r1):
    """The matcher's model samples g bilinearly, so at the true parameters its residual is
    e = r1·(F − bilinear F) ≠ 0 and the fixed point moves by Δq ≈ A⁺e (A: the analytic
    Jacobian at the truth). Returns (Δq, the rows' norms of A⁺, the Cauchy–Schwarz bound
    ‖row(A⁺)‖·√n·e_max with e_max = r1/8·(max|F_cc| + max|F_rr|), the bilinear error bound)."""
    x, y = _template_xy()
    c, r = a0 + x, b0 + y
    Fx, Fy = _F_grad(c, r)
    A = np.column_stack([r1 * Fx, r1 * Fx * x, r1 * Fx * y, r1 * Fy, r1 * Fy * x, r1 * Fy * y,
                         np.ones_like(x), _F(c, r)])
    Ap = np.linalg.pinv(A)
    e = r1 * (_F(c, r) - _bilinear(_search(), c, r))
    e_max = r1 / 8 * (sum(a * u * u for a, u, _, _ in WAVES) + sum(a * v * v for a, _, v, _ in WAVES))
    assert np.abs(e).max() <= e_max
    rows = np.linalg.norm(Ap, axis=1)
    return Ap @ e, rows, rows * np.sqrt(len(x)) * e_max


@pytest.mark.parametrize("a0, b0, r0, r1", CASES)
def test_lsm_recovers_the_subpixel_shift(a0, b0, r0, r1):
    """Both matchers recover (a0, b0): (1) within the rigorous first-order bound
    |Δq_i| ≤ ‖row_i(A⁺)‖·‖e‖ ≤ ‖row_i(A⁺)‖·√n·e_max (Cauchy–Schwarz; ≈ 0.2 px here, loose);
    (2) to the first-order prediction A⁺e itself within 10 % of it (second order: the
    matcher's central-difference gradients instead of the analytic ones) plus the stopping
    tolerance 1e-4 px (the last step is below it and Gauss–Newton converges at least linearly
    with factor < ½ here, so the remaining error is below one more step)."""
    f, g, start = _case(a0, b0, r0, r1)
    pred, _, bound = _first_order(a0, b0, r1)
    truth = np.array([a0, 1, 0, b0, 0, 1, r0, r1])
    q, _ = CODE["lsm"](f, g, start)
    res = pl.least_squares_matching(f, g, start)
    for params in (q, res.params):
        err = params - truth
        assert np.all(np.abs(err[[0, 3]]) <= bound[[0, 3]])
        assert np.all(np.abs(err[[0, 3]] - pred[[0, 3]]) <= 0.1 * np.abs(pred[[0, 3]]) + 1e-4)
    # the prediction is not trivially 0: the interpolation bias is resolved
    assert np.abs(pred[[0, 3]]).max() > 5e-4


@pytest.mark.parametrize("seed", range(3))
def test_lsm_with_noise_recovers_the_shift_within_its_derived_sigma(seed):
    """σ_n = 2 grey values of independent noise on the template: the shift also scatters by
    σ_n·‖row(A⁺)‖; allowed: the noise-free tolerance plus 4.5 of that σ."""
    a0, b0, r0, r1 = CASES[seed]
    f, g, start = _case(a0, b0, r0, r1, noise=2.0, seed=seed)
    pred, rows, _ = _first_order(a0, b0, r1)
    q, iterations = CODE["lsm"](f, g, start)
    res = pl.least_squares_matching(f, g, start)
    assert iterations == res.iterations
    assert np.allclose(q, res.params, rtol=0, atol=1e-9)
    tol = 0.1 * np.abs(pred[[0, 3]]) + 1e-4 + 4.5 * 2.0 * rows[[0, 3]]
    assert np.all(np.abs(q[[0, 3]] - [a0, b0] - pred[[0, 3]]) <= tol)
    # photolib's stated σ(a0), σ(b0) is that σ: its σ0 from n − 8 = 433 residuals scatters by
    # 1/sqrt(2·433) = 3.4 % (plus the interpolation residual, ~1 grey value beside σ_n = 2,
    # and A at the estimate, not the truth); 20 % allowed
    assert np.allclose(res.std[[0, 3]], 2.0 * rows[[0, 3]], rtol=0.2, atol=0)


def test_flat_template_is_refused_by_both():
    """A flat template has no position: photolib and the teaching lsm both say so. Without the
    check the teaching code's first step (the design matrix holds the *search* image's
    gradients, so it is solvable) explained the template by the radiometry alone (r1 → 0) and
    returned the start position as 'converged'."""
    f = np.full((2 * HALF + 1, 2 * HALF + 1), 80.0)
    g = _search()
    with pytest.raises(ValueError, match="the template is flat"):
        pl.least_squares_matching(f, g, (30, 30))
    with pytest.raises(ValueError, match="the template is flat"):
        CODE["lsm"](f, g, (30, 30))


@pytest.mark.parametrize("start", [(3, 30), (30, 3), (57, 30), (30, 57)])
def test_a_patch_outside_the_search_image_is_refused_by_both(start):
    """A start that puts the 21 × 21 template beyond an edge of the 61 × 61 search image:
    photolib names the start; the teaching lsm says the patch is not inside (without the check
    NumPy's negative indices wrapped around to the opposite edge and matched garbage)."""
    f, g, _ = _case(*CASES[0])
    with pytest.raises(pl.StartOutsideImageError, match="does not lie inside the search image"):
        pl.least_squares_matching(f, g, start)
    with pytest.raises(ValueError, match=r"iteration 1: the patch .* is not inside the search"):
        CODE["lsm"](f, g, start)
