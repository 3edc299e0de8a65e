"""The church (mvtb-data ``church.png``) rectified from its measured window corners: the
committed measurements are reproduced, the residuals and the cross ratio agree with the
façade within the bounds the measuring precision gives (Monte Carlo propagation here, linear
propagation in the notebook), and OpenCV's warpPerspective agrees with photolib's resampling
within the quantisation OpenCV documents (interpolation tables of 1/32 px, uint8 output)."""

from __future__ import annotations

import numpy as np
import pytest

from photolib.rectify import rectify_image
from photolib.transforms import ProjectiveTransform, cross_ratio

pytest.importorskip("mvtbdata")
cv2 = pytest.importorskip("cv2")

from photolib import data  # noqa: E402
from photolib.nb import realplane  # noqa: E402

HEIGHT = 0.67          # glass height in window spacings, as chapter 07 derives it
N_MC = 500


@pytest.fixture(scope="module")
def photo():
    return data.church().images[0]


@pytest.fixture(scope="module")
def fit():
    _, measured = realplane.measurements()
    facade = realplane.facade_points(HEIGHT)
    return facade, measured, ProjectiveTransform.from_estimate(facade, measured)


def test_committed_corners_are_reproduced_by_cornersubpix(photo):
    approx, refined = realplane.measurements()
    again = realplane.measure(photo)
    # committed rounded to 0.01 px: half a unit, and float32 inside OpenCV
    assert np.abs(again - refined).max() <= 0.005 + 1e-3
    # the refinement moved each corner by less than the half-width of its search window (3 px)
    assert np.abs(refined - approx).max() < 3.0


def test_the_corners_are_measured_to_subpixel_precision(fit):
    facade, measured, T = fit
    assert T.redundancy == 2 * 10 - 8
    # the measuring precision of the chapter: σ0 of the image residuals, below a pixel
    # (cornerSubPix on sharp corners); and no residual beyond 3.5 σ0 (no gross error, r = 12)
    assert 0.0 < T.sigma0 < 1.0
    assert np.abs(T.residuals).max() < 3.5 * T.sigma0


def _monte_carlo(measured, sigma, func, seed=1):
    rng = np.random.default_rng(seed)
    return np.array([func(measured + rng.normal(0.0, sigma, measured.shape))
                     for _ in range(N_MC)])


@pytest.mark.parametrize("window", range(5))
def test_check_window_agrees_within_its_propagated_precision(fit, window):
    # leave one window out, predict its corners' image positions from the other eight
    # corners: the deviation is bounded by 3.5 σ of (measurement + prediction)
    facade, measured, T = fit
    sigma = T.sigma0
    keep = [i for i in range(10) if i // 2 != window]
    out = [2 * window, 2 * window + 1]

    def predict(m):
        return ProjectiveTransform.from_estimate(facade[keep], m[keep])(facade[out])
    spread = _monte_carlo(measured, sigma, predict).std(axis=0)
    deviation = predict(measured) - measured[out]
    bound = 3.5 * np.sqrt(sigma ** 2 + spread ** 2)
    assert np.all(np.abs(deviation) <= bound), (deviation, bound)


@pytest.mark.parametrize("idx", [[1, 3, 5, 7], [3, 5, 7, 9], [0, 2, 4, 6], [2, 4, 6, 8],
                                 [1, 3, 5, 9]])
def test_cross_ratio_of_a_row_of_windows_is_the_facades(fit, idx):
    facade, measured, T = fit
    sigma = T.sigma0
    lam = cross_ratio(*measured[idx], atol=0.01)
    lam_facade = cross_ratio(*facade[idx])
    samples = _monte_carlo(measured[idx], sigma, lambda m: cross_ratio(*m, atol=0.01))
    sigma_lam = samples.std()
    # linear propagation (as in the notebook) agrees with the Monte Carlo σ
    grad = [(cross_ratio(*(measured[idx].ravel() + e).reshape(4, 2), atol=0.01)
             - cross_ratio(*(measured[idx].ravel() - e).reshape(4, 2), atol=0.01)) / 2e-3
            for e in 1e-3 * np.eye(8)]
    assert sigma * np.linalg.norm(grad) == pytest.approx(sigma_lam, rel=0.1)
    assert abs(lam - lam_facade) <= 3.0 * sigma_lam


def test_rectified_corners_lie_on_the_facade_within_their_precision(fit):
    facade, measured, T = fit
    back = T.inverse
    spread = _monte_carlo(measured, T.sigma0, lambda m: ProjectiveTransform.from_estimate(
        facade, m).inverse(measured)).std(axis=0)
    # each corner's own measurement error also moves it: σ0 through the local scale
    scale = np.abs(back.jacobian(measured)).sum(axis=2)             # spacings per px
    bound = 3.5 * np.sqrt(spread ** 2 + (T.sigma0 * scale) ** 2)
    assert np.all(np.abs(back(measured) - facade) <= bound)


def test_opencv_warp_agrees_with_photolib_within_its_quantisation(fit, photo):
    facade, measured, T = fit
    shape, origin, d = (110, 560), (-0.6, 0.86), 0.01
    ours = rectify_image(photo, T, shape, origin=origin, pixel_size=d)
    to_output = np.array([[1 / d, 0, -origin[0] / d], [0, -1 / d, origin[1] / d], [0, 0, 1]])
    H = T.matrix @ np.linalg.inv(to_output)                          # output pixel → photo
    theirs = cv2.warpPerspective(photo, H, shape[::-1],
                                 flags=cv2.INTER_LINEAR | cv2.WARP_INVERSE_MAP).astype(float)
    # OpenCV rounds the source position to 1/32 px (an error ≤ 1/64 in each of u, v) and the
    # result to uint8 (≤ 0.5): |Δg| ≤ 0.5 + (|g10 − g00| + |g11 − g01| + |g01 − g00| +
    # |g11 − g10|)/64 at the source pixel; plus the fixed-point weights (2^-15) and a margin
    grid = np.stack(np.meshgrid(origin[0] + d * np.arange(shape[1]),
                                origin[1] - d * np.arange(shape[0])), axis=-1).reshape(-1, 2)
    c, r = T(grid).T
    c0, r0 = np.floor(c).astype(int), np.floor(r).astype(int)
    g = photo.astype(float)
    g00, g10, g01, g11 = g[r0, c0], g[r0, c0 + 1], g[r0 + 1, c0], g[r0 + 1, c0 + 1]
    local = (np.abs(g10 - g00) + np.abs(g11 - g01) + np.abs(g01 - g00) + np.abs(g11 - g10)).max(-1)
    bound = (0.5 + local / 64.0 + 0.02).reshape(shape)
    diff = np.abs(theirs - ours).max(axis=-1)
    assert np.all(diff[1:-1, 1:-1] <= bound[1:-1, 1:-1] + 1e-9)
