"""Independent relative orientation (unabhängige Bildpaare) against independent routes.

The SymPy gradient of the coplanarity determinant (:func:`photolib.derive.stereo.
independent_coplanarity`, lambdified) for the Jacobian; SciPy's least_squares on the determinant
written out here; the dependent form (:func:`photolib.relative_orientation`), which must see the
same model up to a rotation about image 1 and the scale; the critical cylinder and zero parallax.
"""

from __future__ import annotations

import numpy as np
import pytest
import sympy as sp
from scipy import optimize

from photolib import (PointBehindCameraError, independent_relative_orientation, project,
                      relative_orientation)
from photolib.derive import stereo as ds
from photolib.stereo import independent_coplanarity_residuals
from photolib.transforms import DegenerateGeometryError


def _rot(w, p, k):
    """R_ω·R_φ·R_κ written out here, independent of photolib."""
    Rx = np.array([[1, 0, 0], [0, np.cos(w), -np.sin(w)], [0, np.sin(w), np.cos(w)]])
    Ry = np.array([[np.cos(p), 0, np.sin(p)], [0, 1, 0], [-np.sin(p), 0, np.cos(p)]])
    Rz = np.array([[np.cos(k), -np.sin(k), 0], [np.sin(k), np.cos(k), 0], [0, 0, 1]])
    return Rx @ Ry @ Rz


ANGLES = np.array([0.03, -0.02, 0.015, -0.04, 0.05])       # φ1, κ1, ω2, φ2, κ2
C = 50.0


def _pair(rng, n=15, noise=0.0, bx=10.0):
    X = rng.uniform([-4, -4, -22], [14, 4, -18], (n, 3))
    R1, R2 = _rot(0.0, *ANGLES[:2]), _rot(*ANGLES[2:])
    xy1 = project(X, np.zeros(3), R1, C) + noise * rng.standard_normal((n, 2))
    xy2 = project(X, [bx, 0.0, 0.0], R2, C) + noise * rng.standard_normal((n, 2))
    return X, xy1, xy2


def test_jacobian_is_the_sympy_gradient():
    v, grad = ds.independent_coplanarity()
    y2 = sp.Symbol("y2", real=True)
    args = (*ds.ro_angles, ds.x1, ds.y1, ds.x2, y2, ds.c, sp.Symbol("b_x", positive=True))
    f_sym = sp.lambdify(args, v, "numpy")
    g_sym = sp.lambdify(args, grad, "numpy")
    rng = np.random.default_rng(11)
    q = rng.uniform(-0.3, 0.3, 5)
    xy1, xy2 = rng.uniform(-20, 20, (8, 2)), rng.uniform(-20, 20, (8, 2))
    x1 = np.column_stack([xy1, np.full(8, -C)])
    x2 = np.column_stack([xy2, np.full(8, -C)])
    f, J = independent_coplanarity_residuals(q, x1, x2, C)
    at = (*q, xy1[:, 0], xy1[:, 1], xy2[:, 0], xy2[:, 1], C, 7.0)
    np.testing.assert_allclose(f, f_sym(*at), rtol=1e-12, atol=1e-12)
    np.testing.assert_allclose(J, np.column_stack(g_sym(*at)), rtol=1e-12, atol=1e-12)


def test_exact_pair_is_recovered():
    X, xy1, xy2 = _pair(np.random.default_rng(3))
    ro = independent_relative_orientation(xy1, xy2, C, bx=10.0)
    np.testing.assert_allclose(ro.params, ANGLES, atol=1e-11)
    np.testing.assert_allclose(ro.model, X, atol=1e-8)          # bx = the true base
    assert ro.converged and ro.redundancy == 10 and np.max(np.abs(ro.residuals)) < 1e-10


def test_agrees_with_scipy_least_squares_on_the_determinant():
    _, xy1, xy2 = _pair(np.random.default_rng(4), 20, noise=0.003)
    ro = independent_relative_orientation(xy1, xy2, C, bx=10.0)

    def det_form(q):
        b = np.array([10.0, 0.0, 0.0])
        R1, R2 = _rot(0.0, q[0], q[1]), _rot(*q[2:])
        return np.array([np.linalg.det(np.column_stack([b, R1 @ np.r_[p, -C], R2 @ np.r_[r, -C]]))
                         for p, r in zip(xy1, xy2)]) / (10.0 * C)

    sol = optimize.least_squares(det_form, np.zeros(5), xtol=1e-15, ftol=1e-15, gtol=1e-15)
    np.testing.assert_allclose(ro.params, sol.x, atol=1e-9)
    assert ro.sigma0 == pytest.approx(np.sqrt(2 * sol.cost / 15), rel=1e-6)


def _both_forms(noise):
    rng = np.random.default_rng(5)
    X = rng.uniform([-4, -4, -22], [14, 4, -18], (25, 3))
    b_true, R2_true = np.array([10.0, 0.4, -0.3]), _rot(0.02, -0.03, 0.05)
    xy1 = project(X, np.zeros(3), np.eye(3), C) + noise * rng.standard_normal((25, 2))
    xy2 = project(X, b_true, R2_true, C) + noise * rng.standard_normal((25, 2))
    return relative_orientation(xy1, xy2, C, bx=10.0), independent_relative_orientation(
        xy1, xy2, C, bx=4.0)


def test_dependent_and_independent_forms_give_the_same_model():
    """Exact pair, both forms: X_ind = s·R1·X_dep with s = bx/|b_dep|, and R2_ind = R1·R2_dep."""
    dep, ind = _both_forms(0.0)
    s = 4.0 / np.linalg.norm(dep.base)
    np.testing.assert_allclose(ind.R1 @ dep.base * s, [4.0, 0.0, 0.0], atol=1e-9)
    np.testing.assert_allclose(ind.R2, ind.R1 @ dep.R2, atol=1e-9)
    np.testing.assert_allclose(ind.model, s * dep.model @ ind.R1.T, atol=1e-8)


def test_with_noise_the_forms_agree_far_within_their_precision():
    """The dependent residual is the independent one times |b|/bx, which varies with by, bz:
    with noise the two least-squares solutions differ, at second order, far below σ."""
    dep, ind = _both_forms(0.004)
    s = 4.0 / np.linalg.norm(dep.base)
    sigma_angles = np.sqrt(np.diag(ind.covariance))
    off_axis = np.linalg.norm((ind.R1 @ dep.base * s)[1:]) / 4.0          # radians
    assert off_axis < 0.05 * sigma_angles[:2].min()
    rel = ind.R2.T @ ind.R1 @ dep.R2                                       # I if equal
    assert np.arccos(np.clip((np.trace(rel) - 1) / 2, -1, 1)) < 0.05 * sigma_angles[2:].min()
    assert ind.sigma0 == pytest.approx(dep.sigma0 * 10.0 / np.linalg.norm(dep.base), rel=1e-4)


def test_critical_cylinder_and_degenerate_pairs_raise():
    rng = np.random.default_rng(1)
    # points on a circular cylinder with its axis parallel to the base, through both centres
    t, xs = rng.uniform(1.3 * np.pi, 1.7 * np.pi, 20), rng.uniform(-3, 13, 20)
    yc, zc = 2.0, -15.0
    X = np.column_stack([xs, yc + np.hypot(yc, zc) * np.cos(t), zc + np.hypot(yc, zc) * np.sin(t)])
    xy1, xy2 = project(X, np.zeros(3), np.eye(3), C), project(X, [10.0, 0, 0], np.eye(3), C)
    with pytest.raises(DegenerateGeometryError, match="critical surface"):
        independent_relative_orientation(xy1, xy2, C, bx=10.0)
    # the same points off the cylinder (shifted 2 m down) orient
    X2 = X + [0.0, 0.0, -2.0]
    ro = independent_relative_orientation(project(X2, np.zeros(3), np.eye(3), C),
                                          project(X2, [10.0, 0, 0], np.eye(3), C), C, bx=10.0)
    np.testing.assert_allclose(ro.params, 0.0, atol=1e-10)
    with pytest.raises(DegenerateGeometryError, match="zero parallax"):
        independent_relative_orientation(xy1, xy1, C)
    _, a, b = _pair(np.random.default_rng(6))
    with pytest.raises(PointBehindCameraError, match="Flip the sign of bx"):
        independent_relative_orientation(a, b, C, bx=-10.0)
    with pytest.raises(ValueError, match="bx must be ≠ 0"):
        independent_relative_orientation(a, b, C, bx=0.0)
    with pytest.raises(ValueError, match="5"):
        independent_relative_orientation(a[:4], b[:4], C)
    with pytest.raises(ValueError, match="initial must be 5 finite"):
        independent_relative_orientation(a, b, C, initial=[0, 0, 0, np.nan, 0])
