"""photolib.optics against independent routes.

SymPy derivations of :mod:`photolib.derive.optics` (lambdified), Bessel's integral by
quadrature (the library takes J0, J1 from ``scipy.special``), Fermat's principle minimised
with ``scipy.optimize``, root finding on the cone geometry, and glass-catalogue values
(Schott N-BK7, N-SF11, F2 data sheets; Malitson 1965).
"""

from __future__ import annotations

import math

import numpy as np
import pytest
import sympy as sp
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy import integrate, optimize, special

import photolib.optics as po
from photolib.derive import optics as do


@pytest.fixture(scope="module")
def rng():
    return np.random.default_rng(2)


def _lam(expr, *symbols):
    return sp.lambdify(symbols, expr, "numpy")


# -- thin lens -----------------------------------------------------------------------------------

def test_image_distance_matches_the_ray_construction(rng):
    f_ = rng.uniform(8.0, 300.0, 50)
    a_ = f_ * rng.uniform(1.01, 500.0, 50)
    derived = _lam(do.thin_lens_image_distance(do.a), do.a, do.f)
    np.testing.assert_allclose(po.image_distance(a_, f_), derived(a_, f_), rtol=1e-13)
    assert po.image_distance(np.inf, 35.0) == 35.0


@settings(max_examples=60, deadline=None, derandomize=True)
@given(st.floats(5.0, 500.0), st.floats(1.001, 1e4))
def test_imaging_equation_round_trip(f, ratio):
    a = f * ratio
    ap = po.image_distance(a, f)
    assert math.isclose(1 / a + 1 / ap, 1 / f, rel_tol=1e-12)
    # object and image are conjugate: exchanging them gives the object back
    assert math.isclose(po.image_distance(ap, f), a, rel_tol=1e-8)


def test_image_scale_number_matches_derivation(rng):
    f_ = rng.uniform(8.0, 300.0, 20)
    a_ = f_ * rng.uniform(1.5, 500.0, 20)
    derived = _lam(do.image_scale_number(do.a), do.a, do.f)
    np.testing.assert_allclose(po.image_scale_number(a_, f_), derived(a_, f_), rtol=1e-12)


def test_angles_and_f_number_by_triangles():
    s, c = np.hypot(36.0, 24.0), 50.0
    half = po.half_field_angle(s, c)
    # the corner of the format seen from the projection centre: law of cosines on the
    # two rays to opposite corners gives the full angle
    u, w = np.array([18.0, 12.0, -c]), np.array([-18.0, -12.0, -c])
    full = math.acos(u @ w / (np.linalg.norm(u) * np.linalg.norm(w)))
    assert math.isclose(2 * half, full, rel_tol=1e-12)
    tan_half = _lam(do.half_aperture_angle_tan(), do.d_pupil, do.f)
    assert math.isclose(math.tan(po.half_aperture_angle(12.5, 50.0)), tan_half(12.5, 50.0))
    assert po.f_number(50.0, 12.5) == 4.0


# -- depth of field -----------------------------------------------------------------------------

def _cone_blur(a_x, a, f, k, u=0.0):
    """Blur of the cone minus u, from the lens equation typed out (not the library)."""
    apx = 1.0 / (1.0 / f - 1.0 / a_x)
    ap = 1.0 / (1.0 / f - 1.0 / a)
    return f / k * abs(apx - ap) / apx - u


def test_depth_of_field_limits_are_where_the_cone_blur_reaches_u(rng):
    for _ in range(20):
        f, k, u = rng.uniform(20, 200), rng.uniform(1.4, 22), rng.uniform(0.005, 0.05)
        H = f + f * f / (k * u)
        a = rng.uniform(2 * f, 0.9 * H)
        dof = po.depth_of_field(a, f, k, u)
        near = optimize.brentq(_cone_blur, 1.0001 * f, a, args=(a, f, k, u))
        far = optimize.brentq(_cone_blur, a, 1e3 * H, args=(a, f, k, u))
        assert math.isclose(dof.near, near, rel_tol=1e-9)
        assert math.isclose(dof.far, far, rel_tol=1e-8)
        assert math.isclose(dof.depth, far - near, rel_tol=1e-7)
        assert math.isclose(po.blur_diameter(near, a, f, k), u, rel_tol=1e-10)


def test_depth_of_field_matches_sympy_limits_and_hyperfocal(rng):
    near_e, far_e = do.dof_limits()
    args = (do.a, do.f, do.k, do.up)
    near_f, far_f = _lam(near_e, *args), _lam(far_e, *args)
    H_f = _lam(do.hyperfocal_distance(), do.f, do.k, do.up)
    for _ in range(10):
        f, k, u = rng.uniform(20, 200), rng.uniform(1.4, 22), rng.uniform(0.005, 0.05)
        a = rng.uniform(2 * f, 0.9 * (f + f * f / (k * u)))
        dof = po.depth_of_field(a, f, k, u)
        assert math.isclose(dof.near, near_f(a, f, k, u), rel_tol=1e-12)
        assert math.isclose(dof.far, far_f(a, f, k, u), rel_tol=1e-11)
        assert math.isclose(dof.hyperfocal, H_f(f, k, u), rel_tol=1e-13)
        assert math.isclose(po.hyperfocal_distance(f, k, u), H_f(f, k, u), rel_tol=1e-13)


def test_focused_at_the_hyperfocal_distance_the_near_limit_is_half_of_it():
    f, k, u = 35.0, 11.0, 0.03
    H = po.hyperfocal_distance(f, k, u)
    dof = po.depth_of_field(H, f, k, u)
    assert dof.far == np.inf and dof.depth == np.inf
    # near = H f²/(f² + u k (H − f)) = H/2 exactly, since u k (H − f) = f²
    assert math.isclose(dof.near, H / 2, rel_tol=1e-12)


def test_focus_at_infinity_near_limit_is_where_the_blur_is_u():
    f, k, u = 50.0, 8.0, 0.03
    dof = po.depth_of_field(np.inf, f, k, u)
    # sensor at f: an object at a_x blurs by d·(a'_x − f)/a'_x
    near = optimize.brentq(lambda x: f / k * (x * f / (x - f) - f) / (x * f / (x - f)) - u,
                           1.001 * f, 1e9)
    assert math.isclose(dof.near, near, rel_tol=1e-9) and dof.far == np.inf
    arr = po.depth_of_field(np.array([5000.0, np.inf]), f, k, u)
    assert math.isclose(arr.near[0], po.depth_of_field(5000.0, f, k, u).near)
    assert math.isclose(arr.near[1], near, rel_tol=1e-9) and np.isinf(arr.far[1])


def test_depth_in_scale_number_and_the_printed_wrong_formula():
    f, k, u, mb = 50.0, 8.0, 0.03, 40.0
    a = f * (1 + mb)
    t = po.depth_of_field(a, f, k, u).depth
    derived = _lam(do.dof_depth_in_scale_number(), do.m_b, do.f, do.k, do.up)
    assert math.isclose(t, derived(mb, f, k, u), rel_tol=1e-11)
    printed = 2 * u * k * (1 + mb) / (mb**2 - (u * k / f) ** 2)   # de-summary:depth-of-field-t
    assert not math.isclose(t, printed, rel_tol=1e-2)
    # right if m_b is read as the magnification 1/m_b (the record's note)
    beta = 1 / mb
    assert math.isclose(t, 2 * u * k * (1 + beta) / (beta**2 - (u * k / f) ** 2), rel_tol=1e-11)


def test_depth_of_field_arrays_broadcast():
    dof = po.depth_of_field(np.array([2000.0, 5000.0, 50000.0]), 50.0, 8.0, 0.03)
    assert dof.near.shape == (3,) and np.isinf(dof.far[2]) and np.all(np.diff(dof.near) > 0)


# -- diffraction ---------------------------------------------------------------------------------

def _bessel_integral(n, x):
    """Bessel's integral J_n(x) = (1/π)∫₀^π cos(nτ − x·sin τ) dτ by adaptive quadrature (QUADPACK),
    the route independent of ``scipy.special`` that the library's J0, J1 are checked by."""
    return integrate.quad(lambda tau: math.cos(n * tau - x * math.sin(tau)), 0.0, math.pi,
                          epsabs=1e-13, epsrel=1e-12, limit=200)[0] / math.pi


def test_airy_formulas_use_bessels_integral():
    lam, k = 0.55, 8.0
    r = np.array([0.3, 1.0, 2.0, po.airy_radius(lam, k), 7.5, 12.0, 40.0, -2.0])
    v = np.pi * np.abs(r) / (lam * k)
    j0 = np.array([_bessel_integral(0, x) for x in v])
    j1 = np.array([_bessel_integral(1, x) for x in v])
    np.testing.assert_allclose(po.airy_psf(r, lam, k), (2 * j1 / v) ** 2, rtol=0, atol=1e-13)
    np.testing.assert_allclose(po.airy_encircled_energy(r, lam, k), 1 - j0**2 - j1**2,
                               rtol=0, atol=1e-13)


@pytest.mark.parametrize("module", ["photolib", "photolib.optics"])
def test_bessel_jn_is_deprecated_and_delegates_to_scipy(module):
    import importlib

    mod = importlib.import_module(module)
    assert "bessel_jn" not in mod.__all__
    x = [0.0, 0.5, 3.0, 25.0, -7.0]
    for n in (0, 1, 2, 5):
        with pytest.warns(DeprecationWarning, match=r"bessel_jn is deprecated.*scipy\.special\.jv"):
            got = mod.bessel_jn(n, x)
        np.testing.assert_allclose(got, [_bessel_integral(n, xi) for xi in x], rtol=0, atol=1e-13)
    with pytest.warns(DeprecationWarning):
        assert isinstance(mod.bessel_jn(1, 2.0), float)


def test_bessel_j1_zero_and_airy_radius_against_scipy():
    z1 = special.jn_zeros(1, 1)[0]
    assert math.isclose(po.J1_FIRST_ZERO, z1, rel_tol=1e-15)
    assert math.isclose(float(do.airy_first_zero()), z1, rel_tol=1e-15)
    assert math.isclose(po.airy_radius(0.55, 8.0), z1 / math.pi * 0.55 * 8.0, rel_tol=1e-15)
    assert abs(po.airy_radius(0.55, 8.0) - 1.22 * 0.55 * 8.0) < 0.003  # the rounded 1.22


def test_airy_psf_is_the_fraunhofer_integral_of_the_pupil():
    # amplitude of a circular pupil: A(v) = 2∫₀¹ J0(vρ) ρ dρ (Hankel transform), I = A²
    lam, k = 0.55, 4.0
    r = np.linspace(0.0, 8.0, 17)
    v = np.pi * r / (lam * k)
    amp = [2 * integrate.quad(lambda rho, vv=vv: _bessel_integral(0, vv * rho) * rho, 0, 1,
                              epsabs=1e-14)[0] for vv in v]
    np.testing.assert_allclose(po.airy_psf(r, lam, k), np.square(amp), atol=1e-12)
    np.testing.assert_allclose(po.airy_psf(-r, lam, k), po.airy_psf(r, lam, k))


def test_encircled_energy_integrates_the_psf():
    lam, k = 0.55, 8.0
    assert do.encircled_energy_rate_residual() == 0
    for r in (1.0, po.airy_radius(lam, k), 12.0):
        v = np.pi * r / (lam * k)
        direct = 0.5 * integrate.quad(
            lambda t: (2 * _bessel_integral(1, t) / t) ** 2 * t if t else 0.0, 0, v, limit=200)[0]
        assert math.isclose(po.airy_encircled_energy(r, lam, k), direct, rel_tol=1e-9)


# -- vignetting ----------------------------------------------------------------------------------

def test_natural_vignetting_is_the_derived_cos4(rng):
    c = 24.0
    xy = rng.uniform(-18.0, 18.0, (30, 2))
    tau = np.arctan(np.hypot(*xy.T) / c)
    derived = _lam(do.relative_irradiance(), do.tau)
    np.testing.assert_allclose(po.natural_vignetting(xy, c), derived(tau), rtol=1e-13)
    assert po.natural_vignetting([0.0, 0.0], c) == 1.0


# -- refraction and reflection -------------------------------------------------------------------

def _fermat_angle(alpha, n1, n2):
    """Refraction angle by minimising the travel time between two points (scipy)."""
    h1, h2 = 1.0, 1.0
    x_target = h1 * math.tan(alpha) + 2.0  # a point below the interface, to the right
    T = lambda u: n1 * math.hypot(h1, u) + n2 * math.hypot(h2, x_target - u)  # noqa: E731
    res = optimize.minimize_scalar(T, bounds=(0.0, x_target), method="bounded",
                                   options={"xatol": 1e-12})
    u = res.x
    alpha_found = math.atan2(u, h1)
    beta = math.atan2(x_target - u, h2)
    return alpha_found, beta


@pytest.mark.parametrize("n1, n2", [(1.0, 1.5), (1.0, 1.333), (1.5, 1.0), (1.33, 1.52)])
def test_refraction_angle_is_fermats_stationary_path(n1, n2):
    a_f, b_f = _fermat_angle(0.3, n1, n2)
    assert math.isclose(po.refraction_angle(a_f, n1, n2), b_f, abs_tol=1e-6)


@settings(max_examples=60, deadline=None, derandomize=True)
@given(st.floats(0.0, 1.5), st.floats(1.0, 2.0), st.floats(1.0, 2.0), st.floats(0.0, 6.28))
def test_vector_refraction_obeys_snell_and_stays_in_the_plane(alpha, n1, n2, azimuth):
    nrm = np.array([0.0, 0.0, 1.0])
    d = np.array([math.sin(alpha) * math.cos(azimuth), math.sin(alpha) * math.sin(azimuth),
                  -math.cos(alpha)])
    t, valid = po.refract(d, nrm, n1, n2, on_total_reflection="flag")
    assert math.isclose(np.linalg.norm(t), 1.0, rel_tol=1e-12)
    assert abs(np.linalg.det(np.array([d, t, nrm]))) < 1e-9       # coplanar
    if n1 * math.sin(alpha) <= n2:
        assert valid and t[2] < 0 or alpha == 0.0
        assert math.isclose(n1 * math.sin(alpha), n2 * np.hypot(t[0], t[1]), abs_tol=1e-12)
    else:
        assert not valid
        np.testing.assert_allclose(t, po.reflect(d, nrm), atol=1e-12)


def test_refract_normal_on_either_side_and_many_rays(rng):
    d = rng.normal(size=(20, 3))
    d[:, 2] = -np.abs(d[:, 2]) - 0.5
    up = po.refract(d, [0.0, 0.0, 1.0], 1.0, 1.5)
    down = po.refract(d, [0.0, 0.0, -1.0], 1.0, 1.5)
    np.testing.assert_allclose(up, down)
    sin_a = np.hypot(*d[:, :2].T) / np.linalg.norm(d, axis=1)
    np.testing.assert_allclose(np.hypot(*up[:, :2].T), sin_a / 1.5, atol=1e-13)


def test_reflect_is_the_householder_mirror(rng):
    nrm = rng.normal(size=3)
    nrm /= np.linalg.norm(nrm)
    d = rng.normal(size=(10, 3))
    H = np.eye(3) - 2 * np.outer(nrm, nrm)
    expected = (d / np.linalg.norm(d, axis=1, keepdims=True)) @ H.T
    np.testing.assert_allclose(po.reflect(d, nrm), expected, atol=1e-14)


def test_fermat_derivation_gives_snell_and_reflection():
    dT, sa, sb = do.snell_from_fermat()
    assert sp.simplify(dT - (do.n1 * sa - do.n2 * sb)) == 0


def test_total_internal_reflection_and_critical_angle():
    ac = po.critical_angle(1.5, 1.0)
    assert math.isclose(ac, math.asin(1 / 1.5))
    assert math.isclose(po.refraction_angle(ac * (1 - 1e-12), 1.5, 1.0), math.pi / 2, abs_tol=1e-5)
    with pytest.raises(po.TotalInternalReflectionError, match="total internal reflection"):
        po.refraction_angle(ac + 0.01, 1.5, 1.0)
    d = [math.sin(ac + 0.01), 0.0, -math.cos(ac + 0.01)]
    with pytest.raises(po.TotalInternalReflectionError, match="flag"):
        po.refract(d, [0, 0, 1], 1.5, 1.0)
    with pytest.raises(ValueError, match="n1 > n2"):
        po.critical_angle(1.0, 1.5)


# -- dispersion and chromatic aberration ---------------------------------------------------------

@pytest.mark.parametrize("glass, nd, vd", [("N-BK7", 1.51680, 64.17), ("N-SF11", 1.78472, 25.68),
                                           ("F2", 1.62004, 36.37),
                                           ("fused silica", 1.45846, 67.8)])
def test_refractive_index_against_the_catalogue(glass, nd, vd):
    assert math.isclose(po.refractive_index(po.D_LINE, glass), nd, abs_tol=2e-5)
    assert math.isclose(po.abbe_number(glass), vd, abs_tol=0.1)


def test_refractive_index_matches_the_sympy_sellmeier(rng):
    B, C = do.SELLMEIER_B, do.SELLMEIER_C
    f = _lam(do.sellmeier_index(B, C), do.lam, *B, *C)
    lam = rng.uniform(0.4, 0.8, 10)
    np.testing.assert_allclose(po.refractive_index(lam, "N-BK7"), f(lam, *po.GLASSES["N-BK7"]),
                               rtol=1e-14)
    assert np.all(np.diff(po.refractive_index(np.linspace(0.4, 0.8, 9))) < 0)  # normal dispersion


def test_chromatic_focal_shift_is_the_lensmaker_equation():
    f_ref = 50.0
    n0 = po.refractive_index(po.D_LINE)
    R = 2 * f_ref * (n0 - 1)                       # symmetric biconvex lens R1 = −R2 = R
    lensmaker = _lam(do.lensmaker_focal_length(), do.n_glass, do.R1, do.R2)
    assert math.isclose(lensmaker(n0, R, -R), f_ref, rel_tol=1e-14)
    for lam in (po.F_LINE, po.C_LINE, 0.45):
        n = po.refractive_index(lam)
        assert math.isclose(po.chromatic_focal_shift(f_ref, lam), lensmaker(n, R, -R) - f_ref,
                            rel_tol=1e-11)
    # f_C − f_F ≈ f/V_d (the thin-lens rule of thumb)
    shift = po.chromatic_focal_shift(f_ref, po.C_LINE) - po.chromatic_focal_shift(f_ref, po.F_LINE)
    assert math.isclose(shift, f_ref / po.abbe_number(), rel_tol=0.02)


# -- stereoscopic vision ------------------------------------------------------------------------

def test_stereo_depth_acuity_exact_and_first_order():
    b, eps = 65.0, math.radians(10 / 3600)
    exact = _lam(do.stereo_depth_acuity_exact(), do.Z_obj, do.base, do.eps)
    gamma = lambda Z: 2 * math.atan(b / (2 * Z))  # noqa: E731
    for Z in (250.0, 1000.0, 20000.0):
        dz = po.stereo_depth_acuity(Z, b, eps)
        root = optimize.brentq(lambda x, z=Z: gamma(z) - gamma(z + x) - eps, 0.0, 10 * Z)
        assert math.isclose(dz, root, rel_tol=1e-8)
        assert math.isclose(dz, exact(Z, b, eps), rel_tol=1e-10)
        assert math.isclose(dz, Z * Z * eps / b, rel_tol=0.05)
    assert po.stereo_depth_acuity(1e7, b, eps) == np.inf       # γ < ε: no depth seen


def test_acuity_arc_lengths_of_the_lecture_summary():
    # 5'' and 10'' at 25 cm are about 6 and 12 µm (de-summary:stereo-acuity)
    um = [250.0 * math.tan(math.radians(s / 3600)) * 1e3 for s in (5, 10, 30)]
    assert abs(um[0] - 6.0) < 0.5 and abs(um[1] - 12.0) < 0.5 and abs(um[2] - 40.0) > 3


# -- bad input ------------------------------------------------------------------------------------

@pytest.mark.parametrize("call, match", [
    (lambda: po.image_distance(40.0, 50.0), "no real image"),
    (lambda: po.image_distance(50.0, 50.0), "no real image"),
    (lambda: po.image_distance(100.0, 0.0), "focal length f must be > 0"),
    (lambda: po.image_distance(100.0, -5.0), "focal length f must be > 0"),
    (lambda: po.image_distance(np.nan, 50.0), "NaN"),
    (lambda: po.image_distance(100.0, np.inf), "finite"),
    (lambda: po.depth_of_field(5000.0, 50.0, 0.0, 0.03), "f-number k must be > 0"),
    (lambda: po.depth_of_field(5000.0, 50.0, 8.0, np.nan), "NaN"),
    (lambda: po.depth_of_field(30.0, 50.0, 8.0, 0.03), "no real image"),
    (lambda: po.airy_radius(0.55, -2.0), "f-number k must be > 0"),
    (lambda: po.airy_psf([0.0, np.nan], 0.55, 8.0), "NaN"),
    (lambda: po.f_number(50.0, 0.0), "pupil diameter d must be > 0"),
    (lambda: po.natural_vignetting([[1.0, 2.0, 3.0]], 50.0), "shape"),
    (lambda: po.natural_vignetting([1.0, 2.0], 0.0), "camera constant c must be > 0"),
    (lambda: po.refract([0, 0, 0], [0, 0, 1], 1.0, 1.5), "zero vector"),
    (lambda: po.refract([0, 0, -1], [0, 0, 1], 1.0, 1.5, on_total_reflection="x"), "raise"),
    (lambda: po.refraction_angle(2.0, 1.0, 1.5), "±π/2"),
    (lambda: po.refractive_index(0.55, "unobtainium"), "unknown glass"),
    (lambda: po.refractive_index(0.55, (1.0, 2.0)), "6 numbers"),
    (lambda: po.refractive_index(-0.55), "must be > 0"),
    (lambda: po.stereo_depth_acuity(1000.0, 65.0, 0.0), "acuity must be > 0"),
    (lambda: po.image_distance("far", 50.0), "numeric"),
])
def test_bad_input_is_refused_with_a_clear_message(call, match):
    with pytest.raises(ValueError, match=match):
        call()


def test_no_real_image_is_a_value_error_subclass():
    with pytest.raises(po.NoRealImageError):
        po.image_scale_number(20.0, 50.0)


# -- the chapter's other derivations, evaluated -------------------------------------------------

def test_derived_chromatic_focal_length_is_the_library_shift():
    f_of = _lam(do.chromatic_focal_length(), do.f_ref, do.n_ref, do.n_glass)
    n0 = po.refractive_index(po.D_LINE)
    for lam in (0.45, po.F_LINE, po.C_LINE):
        n = po.refractive_index(lam)
        assert math.isclose(f_of(50.0, n0, n) - 50.0, po.chromatic_focal_shift(50.0, lam),
                            rel_tol=1e-12)


def test_stereo_first_order_is_the_linear_term_of_the_exact_acuity():
    first = _lam(do.stereo_depth_acuity_first_order(), do.Z_obj, do.base, do.eps)
    Z, b = 2000.0, 65.0
    for arcsec in (1.0, 5.0, 10.0):
        eps = math.radians(arcsec / 3600)
        exact = po.stereo_depth_acuity(Z, b, eps)
        # the remainder is of second order in ε: relative error ∝ ε
        assert abs(first(Z, b, eps) / exact - 1) < 2 * eps * Z / b


def test_pinhole_optimum_minimises_the_blur():
    d_star = _lam(do.pinhole_optimum(), do.lam, do.c_cam)
    blur = _lam(do.pinhole_blur(), do.d_pin, do.lam, do.c_cam)
    lam, c = 550e-6, 100.0
    res = optimize.minimize_scalar(blur, bounds=(0.01, 2.0), args=(lam, c), method="bounded",
                                   options={"xatol": 1e-10})
    assert math.isclose(d_star(lam, c), res.x, rel_tol=1e-6)


# -- names of the distances, orders and indices (audit O1, O2) -------------------------------------

def test_blur_diameter_blames_the_distance_that_is_wrong():
    with pytest.raises(po.NoRealImageError, match=r"object distance a_x = 30.0 is not beyond"):
        po.blur_diameter(30.0, 5000.0, 50.0, 8.0)
    with pytest.raises(ValueError, match=r"object distance a_x must not be NaN"):
        po.blur_diameter(np.nan, 5000.0, 50.0, 8.0)
    with pytest.raises(po.NoRealImageError, match=r"focus distance a = 30.0 is not beyond"):
        po.blur_diameter(5000.0, 30.0, 50.0, 8.0)
    with pytest.raises(ValueError, match=r"focus distance a must be > 0"):
        po.blur_diameter(5000.0, -1.0, 50.0, 8.0)
    with pytest.raises(po.NoRealImageError, match=r"object distance a = 30.0 is not beyond"):
        po.image_distance(30.0, 50.0)   # image_distance keeps its own name


@pytest.mark.parametrize("n", [np.inf, np.nan, np.array([1, 2]), "1", True, 1.5, -1])
def test_bessel_order_is_checked_as_an_integer(n):
    with pytest.warns(DeprecationWarning), pytest.raises(ValueError,
                                                         match="order n must be an integer"):
        po.bessel_jn(n, 2.0)


def test_bessel_accepts_integral_orders_of_any_type():
    with pytest.warns(DeprecationWarning):
        assert po.bessel_jn(np.int64(2), 2.0) == po.bessel_jn(2.0, 2.0) == po.bessel_jn(2, 2.0)


def test_refract_broadcasts_indices_over_the_rays_like_refraction_angle():
    alpha = np.array([0.2, 0.5, 0.9])
    d = np.column_stack([np.sin(alpha), np.zeros(3), -np.cos(alpha)])
    n1 = np.array([1.0, 1.2, 1.33])
    t = po.refract(d, [0.0, 0.0, 1.0], n1, 1.5)
    np.testing.assert_allclose(np.arcsin(t[:, 0]), po.refraction_angle(alpha, n1, 1.5), atol=1e-13)
    one = po.refract(d[1], [0.0, 0.0, 1.0], n1, 1.5)            # one ray, three media
    np.testing.assert_allclose(np.arcsin(one[:, 0]), po.refraction_angle(0.5, n1, 1.5), atol=1e-13)
    assert po.refract(d[1], [0.0, 0.0, 1.0], 1.2, 1.5).shape == (3,)


@pytest.mark.parametrize("n1, n2, match", [
    (np.array([1.0, 1.2]), 1.5, r"refractive index n1 has shape \(2,\)"),
    (1.0, np.ones((3, 1)), r"refractive index n2 has shape \(3, 1\)"),
    (np.array([1.0, np.nan, 1.0]), 1.5, "refractive index n1 must not be NaN"),
    (1.0, np.array([1.5, np.inf, 1.5]), "refractive index n2 must be finite"),
    (1.0, np.array([1.5, -1.0, 1.5]), "refractive index n2 must be > 0"),
])
def test_refract_names_bad_indices(n1, n2, match):
    d = np.array([[0.0, 0.6, -0.8]] * 3)
    with pytest.raises(ValueError, match=match):
        po.refract(d, [0.0, 0.0, 1.0], n1, n2)


def test_refract_flags_total_reflection_per_ray_with_array_indices():
    d = np.array([[0.0, 0.6, -0.8]] * 2)          # sin α = 0.6
    t, valid = po.refract(d, [0.0, 0.0, 1.0], np.array([1.5, 2.0]), 1.0,
                          on_total_reflection="flag")
    assert valid.tolist() == [True, False]        # 1.5·0.6 < 1, 2·0.6 > 1
    with pytest.raises(po.TotalInternalReflectionError, match=r"n1 = 2.0, n2 = 1.0"):
        po.refract(d, [0.0, 0.0, 1.0], np.array([1.5, 2.0]), 1.0)
