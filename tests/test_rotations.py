"""Rotations against SciPy's Rotation (an independent implementation) and the SymPy derivation."""

from __future__ import annotations

import numpy as np
import pytest
import sympy as sp
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.spatial.transform import Rotation

import photolib as pl
from photolib.derive import rotation as drot
from photolib.testing import assert_angles_equal, assert_rotation_equal

angle = st.floats(-np.pi, np.pi, allow_nan=False)
secondary = st.floats(-np.pi / 2 + 1e-3, np.pi / 2 - 1e-3, allow_nan=False)


def test_opk_equals_scipy_intrinsic_xyz():
    # R_ω·R_φ·R_κ: intrinsic rotations about x, then the new y, then the new z ("XYZ" in SciPy)
    rng = np.random.default_rng(1)
    for w, p, k in rng.uniform(-3, 3, (50, 3)):
        want = Rotation.from_euler("XYZ", [w, p, k]).as_matrix()
        np.testing.assert_allclose(pl.rotation_opk(w, p, k), want, atol=1e-14)


def test_pok_equals_scipy_intrinsic_yxz():
    rng = np.random.default_rng(2)
    for w, p, k in rng.uniform(-3, 3, (50, 3)):
        want = Rotation.from_euler("YXZ", [p, w, k]).as_matrix()
        np.testing.assert_allclose(pl.rotation_pok(w, p, k), want, atol=1e-14)


def test_elementary_rotations_are_right_handed_exponentials():
    # exp(t[e]×) applied to the next axis turns it towards the one after (right-hand rule)
    t = sp.pi / 2
    assert drot.R_omega(t) * sp.Matrix([0, 1, 0]) == sp.Matrix([0, 0, 1])
    assert drot.R_phi(t) * sp.Matrix([0, 0, 1]) == sp.Matrix([1, 0, 0])
    assert drot.R_kappa(t) * sp.Matrix([1, 0, 0]) == sp.Matrix([0, 1, 0])


def test_angle_rates_match_differentiation():
    R = drot.rotation_opk()
    rates = drot.angle_rates()
    vals = {drot.omega: 0.3, drot.phi: -0.7, drot.kappa: 1.1}
    for name, sym in (("omega", drot.omega), ("phi", drot.phi), ("kappa", drot.kappa)):
        diff = (rates[name] - R.diff(sym)).subs(vals).evalf()
        assert max(abs(float(v)) for v in diff) < 1e-14


def test_broadcasting_gives_stack():
    w = np.linspace(-1, 1, 5)
    Rs = pl.rotation_opk(w, 0.2, 0.3)
    assert Rs.shape == (5, 3, 3)
    np.testing.assert_allclose(Rs[2], pl.rotation_opk(w[2], 0.2, 0.3))


@settings(max_examples=200, deadline=None)
@given(angle, secondary, angle)
def test_opk_round_trip(w, p, k):
    got = pl.opk_from_rotation(pl.rotation_opk(w, p, k))
    assert_angles_equal(got, (w, p, k), atol=1e-8)


@settings(max_examples=200, deadline=None)
@given(secondary, angle, angle)
def test_pok_round_trip(w, p, k):
    got = pl.pok_from_rotation(pl.rotation_pok(w, p, k))
    assert_angles_equal(got, (w, p, k), atol=1e-8)


@pytest.mark.parametrize("phi", [np.pi / 2, -np.pi / 2])
def test_gimbal_lock_raises_and_splits(phi):
    R = pl.rotation_opk(0.3, phi, 0.2)
    with pytest.raises(pl.GimbalLockError, match="gimbal lock: phi"):
        pl.opk_from_rotation(R)
    for split in ("kappa-zero", "omega-zero"):
        w, p, k = pl.opk_from_rotation(R, split=split)
        assert (k if split == "kappa-zero" else w) == 0.0
        assert_rotation_equal(pl.rotation_opk(w, p, k), R, atol=1e-12)
    with pytest.raises(ValueError, match="split must be"):
        pl.opk_from_rotation(R, split="sideways")


def test_opk_from_rotation_rejects_bad_matrices():
    with pytest.raises(ValueError, match=r"shape \(2, 2\)"):
        pl.opk_from_rotation(np.eye(2))
    with pytest.raises(ValueError, match="non-finite value nan"):
        pl.opk_from_rotation(np.full((3, 3), np.nan))
    with pytest.raises(ValueError, match="not orthonormal"):
        pl.opk_from_rotation(2 * np.eye(3))
    with pytest.raises(ValueError, match="reflection"):
        pl.opk_from_rotation(np.diag([1.0, -1.0, 1.0]))


def test_rotation_opk_rejects_nan():
    with pytest.raises(ValueError, match="phi contains a non-finite value"):
        pl.rotation_opk(0.0, np.nan, 0.0)


def test_wolf_m_is_transpose_and_maps_object_to_image():
    R = pl.rotation_opk(0.1, 0.2, 0.3)
    M = pl.wolf_m_from_rotation(R)
    v = np.array([0.3, -0.2, 0.9])
    np.testing.assert_allclose(M @ (R @ v), v, atol=1e-15)
    np.testing.assert_allclose(pl.rotation_from_wolf_m(M), R)


def test_opencv_pose_round_trip_and_projection_frame():
    X0 = np.array([10.0, -5.0, 100.0])
    R = pl.rotation_opk(0.05, -0.1, 2.0)
    Rcv, t = pl.opencv_pose_from_exterior(X0, R)
    assert np.linalg.det(Rcv) == pytest.approx(1.0)
    X = np.array([12.0, -3.0, 1.0])
    cam = Rcv @ X + t
    assert cam[2] > 0  # in front for OpenCV ⇔ N < 0 for us
    kx, ky, N = R.T @ (X - X0)
    np.testing.assert_allclose(cam, [kx, -ky, -N], atol=1e-12)
    X0b, Rb = pl.exterior_from_opencv_pose(Rcv, t)
    np.testing.assert_allclose(X0b, X0, atol=1e-12)
    assert_rotation_equal(Rb, R, atol=1e-12)


def test_rotation_2d_is_counter_clockwise():
    np.testing.assert_allclose(pl.rotation_2d(np.pi / 2) @ [0.0, 1.0], [-1.0, 0.0], atol=1e-15)


def test_angle_helpers_against_numpy():
    a = np.linspace(-7, 7, 29)
    np.testing.assert_allclose(pl.rad2deg(a), np.degrees(a))
    np.testing.assert_allclose(pl.deg2rad(a), np.radians(a))
    np.testing.assert_allclose(pl.gon2rad(pl.rad2gon(a)), a)
    np.testing.assert_allclose(pl.gon2deg(400.0), 360.0)
    np.testing.assert_allclose(pl.deg2gon(pl.gon2deg(a)), a)
    w = pl.wrap_angle(a)
    assert np.all((w >= -np.pi) & (w < np.pi))
    np.testing.assert_allclose(np.cos(w), np.cos(a), atol=1e-12)


def test_testing_helpers_detect_degrees_and_transpose():
    with pytest.raises(AssertionError, match="degrees"):
        assert_angles_equal(np.degrees(0.1), 0.1)
    R = pl.rotation_opk(0.2, 0.1, 0.4)
    with pytest.raises(AssertionError, match="transposed"):
        assert_rotation_equal(R.T, R)


# -- input handling (red-team audit) --------------------------------------------------------------

@pytest.mark.parametrize("call, text", [
    (lambda: pl.rotation_opk("a", 0.0, 0.0), "omega must be numeric, got 'a'"),
    (lambda: pl.rotation_pok(0.0, 0.0, [1.0, "x"]), r"kappa must be numeric, got 'x' at index \(1,\)"),
    (lambda: pl.rotation_opk(0.0, 1 + 1j, 0.0), r"phi must be real, got complex values"),
    (lambda: pl.rotation_opk([0.1, 0.2], [0.1, 0.2, 0.3], 0.0),
     r"omega, phi, kappa have shapes \[\(2,\), \(3,\), \(\)\], which do not broadcast"),
    (lambda: pl.rotation_2d(np.nan), r"alpha contains a non-finite value nan"),
    (lambda: pl.rotation_2d("x"), "alpha must be numeric, got 'x'"),
    (lambda: pl.opk_from_rotation("abc"), r"R must be numeric with shape \(3, 3\), got 'abc'"),
    (lambda: pl.opencv_pose_from_exterior("abc", np.eye(3)),
     r"X0 must be numeric with shape \(3,\), got 'abc'"),
    (lambda: pl.opencv_pose_from_exterior(np.array([1j, 0, 0]), np.eye(3)),
     r"X0 must be real with shape \(3,\), got complex values \(e.g. 1j\)"),
])
def test_bad_angles_and_matrices_are_named(call, text):
    with pytest.raises(ValueError, match=text):
        call()


# -- angle helpers: range and bad input (audit A1, A2) ---------------------------------------------

def test_wrap_angle_never_returns_plus_pi():
    """(a + π) mod 2π rounds to 2π just below −π (and its odd multiples): that gave +π."""
    below = np.nextafter(-np.pi, -4.0)
    assert float(pl.wrap_angle(below)) == -np.pi
    k = np.arange(-7, 8)
    edges = (2 * k + 1) * np.pi
    a = np.concatenate([np.nextafter(edges, -np.inf), edges, np.nextafter(edges, np.inf),
                        np.linspace(-50, 50, 2001)])
    w = pl.wrap_angle(a)
    assert np.all((w >= -np.pi) & (w < np.pi))
    np.testing.assert_allclose(np.cos(w), np.cos(a), atol=1e-12)
    np.testing.assert_allclose(np.sin(w), np.sin(a), atol=1e-12)


@pytest.mark.parametrize("name", ["deg2rad", "rad2deg", "gon2rad", "rad2gon", "deg2gon",
                                  "gon2deg", "wrap_angle"])
def test_angle_helpers_name_their_bad_input(name):
    f = getattr(pl, name)
    with pytest.raises(ValueError, match=r"a must (not be NaN|be finite), got NaN"):
        f(np.nan)
    with pytest.raises(ValueError, match=r"a must (not be NaN|be finite), got NaN"):
        f([0.0, np.nan])
    with pytest.raises(ValueError, match="a must be numeric"):
        f("abc")
    with pytest.raises(ValueError, match="a must be real"):
        f(1 + 2j)
    assert isinstance(f(1.0), float) and f(np.ones((2, 3))).shape == (2, 3)


def test_unit_conversions_keep_infinity_but_wrap_angle_refuses_it():
    assert pl.deg2rad(np.inf) == np.inf and pl.gon2deg(-np.inf) == -np.inf
    with pytest.raises(ValueError, match="a must be finite, got inf"):
        pl.wrap_angle(np.inf)
