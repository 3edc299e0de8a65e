"""Chapter 07's teaching code (the homography by normalised DLT and Gauss–Newton, the mapping
by homogeneous coordinates and the rectification with bilinear resampling, written out in the
notebook) agrees with photolib to 1e-9 on inputs of this test's own, not the notebook's."""

from __future__ import annotations

import numpy as np
import pytest

from photolib.rectify import rectify_image
from photolib.transforms import ProjectiveTransform

from .teaching import teaching_functions

CODE = teaching_functions("07-plane-transformations")


def _pairs(seed, n, noise):
    rng = np.random.default_rng(seed)
    truth = ProjectiveTransform(a0=rng.uniform(-50, 50), a1=rng.uniform(80, 120),
                                a2=rng.uniform(-20, 20), b0=rng.uniform(-50, 50),
                                b1=rng.uniform(-20, 20), b2=rng.uniform(80, 120),
                                c1=rng.uniform(-0.05, 0.05), c2=rng.uniform(-0.05, 0.05))
    src = rng.uniform(0.0, 8.0, (n, 2))
    return src, truth(src) + rng.normal(0.0, noise, (n, 2))


def test_the_notebook_defines_the_functions():
    assert {"homography", "apply_homography", "rectify"} <= set(CODE)


@pytest.mark.parametrize("seed, n, noise", [(1, 4, 0.0), (2, 4, 0.3), (3, 9, 0.5), (4, 25, 1.0)])
def test_teaching_homography_is_photolibs(seed, n, noise):
    src, dst = _pairs(seed, n, noise)
    H = CODE["homography"](src, dst)
    lib = ProjectiveTransform.from_estimate(src, dst)
    assert H[2, 2] == 1.0
    # the same matrix (h33 = 1) and so the same mapped points
    assert np.allclose(H, lib.matrix, rtol=1e-9, atol=1e-9 * np.abs(lib.matrix).max())
    assert np.allclose(CODE["apply_homography"](H, src), lib(src), rtol=0, atol=1e-9 * 1000)


def test_teaching_gauss_newton_minimises_the_residuals():
    # with more than four points the result is the least-squares one: no small change of
    # the parameters lowers the sum of squared residuals in dst
    src, dst = _pairs(5, 12, 0.5)
    H = CODE["homography"](src, dst)
    f = lambda M: np.sum((CODE["apply_homography"](M, src) - dst) ** 2)  # noqa: E731
    base = f(H)
    rng = np.random.default_rng(0)
    for _ in range(20):
        dH = np.zeros((3, 3))
        dH.flat[:8] = rng.normal(0.0, 1e-6, 8) * np.abs(H).flat[:8]
        assert f(H + dH) >= base - 1e-9 * base


@pytest.mark.parametrize("colour", [False, True])
def test_teaching_rectify_is_rectify_image(colour):
    rng = np.random.default_rng(11)
    image = rng.integers(0, 256, (60, 80, 3) if colour else (60, 80)).astype(np.uint8)
    obj = np.array([[0.0, 0.0], [4.0, 0.0], [4.0, 3.0], [0.0, 3.0]])
    pix = np.array([[5.0, 55.0], [75.0, 50.0], [70.0, 8.0], [9.0, 3.0]])
    T = ProjectiveTransform.from_estimate(obj, pix)
    shape, origin, d = (37, 51), (-0.2, 3.1), 0.09      # reaches outside the photograph too
    ours = CODE["rectify"](image, T.matrix, shape, origin, d)
    lib = rectify_image(image, T, shape, origin=origin, pixel_size=d)
    assert ours.shape == lib.shape
    assert np.allclose(ours, lib, rtol=0, atol=1e-9)
    assert np.any(lib == 0.0) and np.any(lib > 0.0)
