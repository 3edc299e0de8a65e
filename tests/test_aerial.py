"""Earth curvature and refraction corrections against independent routes.

The SymPy derivations of :mod:`photolib.derive.aerial` (lambdified); the exact image of a point
on a sphere (no series); a ray traced through the ICAO atmosphere by Snell's law in layers
(``n(z)·sin θ(z)`` constant, the horizontal run integrated by SciPy's quad), no first-order step.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
import sympy as sp
from scipy import integrate

import photolib.aerial as pa
from photolib.derive import aerial as da


@pytest.mark.slow
def test_the_derivations_give_the_textbook_forms():
    assert sp.simplify(da.earth_curvature_displacement()
                       + da.r**3 * da.H / (2 * da.R * da.c**2)) == 0
    assert sp.simplify(da.refraction_displacement() - da.K * (da.r + da.r**3 / da.c**2)) == 0
    mean_excess, from_the_run = da.refraction_constant_first_order()
    assert sp.simplify(mean_excess - from_the_run) == 0


def test_curvature_correction_is_the_derived_one():
    rng = np.random.default_rng(5)
    xy = rng.uniform(-110, 110, (50, 2))
    c, H = 153.0, 2500.0
    dr = sp.lambdify((da.r, da.H, da.R, da.c), da.earth_curvature_displacement())
    r = np.hypot(*xy.T)
    expected = xy * (1 - dr(r, H, pa.EARTH_RADIUS, c) / r)[:, None]
    np.testing.assert_allclose(pa.earth_curvature_correction(xy, c, H), expected, rtol=1e-13)


@pytest.mark.parametrize("H, D", [(1500.0, 900.0), (3000.0, 2000.0), (8000.0, 5500.0)])
def test_curvature_correction_recovers_the_flat_image_of_the_exact_sphere(H, D):
    """A point on the sphere at arc distance D is imaged exactly; corrected it is the flat one."""
    c, R = 153.0, pa.EARTH_RADIUS
    theta = D / R
    exact = c * R * math.sin(theta) / (H + R * (1 - math.cos(theta)))
    flat = c * D / H
    corrected = pa.earth_curvature_correction([exact, 0.0], c, H)[0]
    assert exact < flat                                           # displaced towards the nadir
    assert abs(corrected - flat) < 0.01 * (flat - exact)           # second order left


def _ray_traced(H, h, theta_H):
    """dα of a ray arriving at the camera (height H) under the nadir angle θ_H, from ground h."""
    n_H = 1 + pa.refractive_index_icao(H)
    inv = n_H * math.sin(theta_H)

    def tan_theta(z):
        s = inv / (1 + pa.refractive_index_icao(z))
        return s / math.sqrt(1 - s * s)
    run, _ = integrate.quad(tan_theta, h, H, epsabs=1e-12, epsrel=1e-13)
    return theta_H - math.atan(run / (H - h))


@pytest.mark.parametrize("H, h", [(1000.0, 0.0), (3000.0, 0.0), (6000.0, 500.0), (12000.0, 0.0)])
@pytest.mark.parametrize("angle_deg", [10.0, 30.0, 45.0])
def test_icao_constant_matches_a_ray_traced_through_the_layers(H, h, angle_deg):
    theta = math.radians(angle_deg)
    traced = _ray_traced(H, h, theta)
    K = pa.refraction_constant(H, h)
    assert traced > 0                                             # farther from the nadir
    assert K * math.tan(theta) == pytest.approx(traced, rel=2e-3)  # first order in n − 1


@pytest.mark.parametrize("H", [1000.0, 2000.0, 4000.0, 6000.0, 10000.0])
def test_ardc_formula_is_within_the_stated_bounds_of_the_ray_trace(H):
    traced = _ray_traced(H, 0.0, math.radians(30.0)) / math.tan(math.radians(30.0))
    ardc = pa.refraction_constant(H, model="ardc")
    bound = 0.25 if H < 4000.0 else 0.10                          # as the docstring states
    assert abs(ardc / traced - 1) < bound


def test_ardc_formula_by_hand():
    # H = 3 km, h = 0: 2410·3/(9 − 18 + 250) = 7230/241 = 30 exactly
    assert pa.refraction_constant(3000.0, model="ardc") == pytest.approx(30e-6, rel=1e-14)
    # H = 2 km, h = 1 km: 2410·2/(4 − 12 + 250) − 2410·1/((1 − 6 + 250)·2)
    expected = (4820 / 242 - 2410 / 490) * 1e-6
    assert pa.refraction_constant(2000.0, 1000.0, model="ardc") == pytest.approx(expected,
                                                                                  rel=1e-14)


def test_refraction_correction_undoes_the_exact_angular_displacement():
    c, K = 153.0, 4e-5
    for alpha in np.radians([5.0, 20.0, 35.0, 45.0]):
        true_r = c * math.tan(alpha)
        seen_r = c * math.tan(alpha + K * math.tan(alpha))        # the exact shifted image
        corrected = pa.refraction_correction([0.0, seen_r], c, K)[1]
        assert abs(corrected - true_r) < 1e-3 * (seen_r - true_r)


def test_icao_index_against_the_standard_atmosphere_table():
    # ICAO table: 1013.25 hPa, 288.15 K at 0 m; 794.95 hPa at 2000 m (T = 275.15 K)
    assert pa.refractive_index_icao(0.0) == pytest.approx(77.6e-6 * 1013.25 / 288.15, rel=1e-12)
    assert pa.refractive_index_icao(2000.0) == pytest.approx(77.6e-6 * 794.95 / 275.15, rel=1e-4)
    below, above = pa.refractive_index_icao([11000.0 - 1e-6, 11000.0 + 1e-6])
    assert above == pytest.approx(below, rel=1e-6)               # continuous at the tropopause


@pytest.mark.parametrize("call, match", [
    (lambda: pa.refraction_constant(500.0, 800.0), "above the ground"),
    (lambda: pa.refraction_constant(3000.0, model="bertram"), "model must be"),
    (lambda: pa.refraction_constant(float("nan")), "H"),
    (lambda: pa.refraction_correction([1.0, 2.0], 153.0, 0.01), "refraction constant K"),
    (lambda: pa.refraction_correction([1.0, 2.0, 3.0], 153.0, 1e-5), "shape"),
    (lambda: pa.earth_curvature_correction([1.0, 2.0], -153.0, 3000.0), "camera constant"),
    (lambda: pa.earth_curvature_correction([1.0, 2.0], 153.0, 0.0), "flying height"),
    (lambda: pa.refractive_index_icao(30000.0), "between -500 m and 20 km"),
])
def test_bad_input_is_named(call, match):
    with pytest.raises(ValueError, match=match):
        call()


# -- direct georeferencing ------------------------------------------------------------------------

@pytest.mark.parametrize("roll, pitch, heading", [(0.0, 0.0, 0.0), (0.03, -0.02, 1.2),
                                                  (-0.1, 0.05, -2.8)])
def test_body_to_ned_is_scipys_zyx(roll, pitch, heading):
    from scipy.spatial.transform import Rotation
    expected = Rotation.from_euler("ZYX", [heading, pitch, roll]).as_matrix()
    np.testing.assert_allclose(pa.rotation_body_to_ned(roll, pitch, heading), expected,
                               atol=1e-15)


def test_direct_georeferencing_reproduces_the_camera_that_took_the_image():
    """An aircraft pose → antenna and IMU readings → (X0, R): the same image of ground points."""
    from scipy.spatial.transform import Rotation

    import photolib as pl
    rng = np.random.default_rng(8)
    roll, pitch, heading = 0.02, -0.015, 0.7
    lever = np.array([0.35, -0.1, -1.8])               # antenna forward, left, above the camera
    bore = np.array([0.002, -0.001, 0.003])
    camera = np.array([1200.0, -300.0, 950.0])
    R_nb = Rotation.from_euler("ZYX", [heading, pitch, roll]).as_matrix()
    ned_to_enu = np.array([[0, 1, 0], [1, 0, 0], [0, 0, -1.0]])
    antenna = camera + ned_to_enu @ R_nb @ lever        # where the GNSS sees the antenna
    # the real camera frame, built here: x' forward, y' left, z up, then the small misalignment
    bore_R = Rotation.from_euler("XYZ", bore).as_matrix()   # intrinsic X-Y-Z = R_ω·R_φ·R_κ
    R_true = ned_to_enu @ R_nb @ np.diag([1.0, -1, -1]) @ bore_R
    X0, R = pa.exterior_from_navigation(antenna, roll, pitch, heading, lever, bore)
    np.testing.assert_allclose(X0, camera, atol=1e-9)
    np.testing.assert_allclose(R, R_true, atol=1e-14)
    ground = np.column_stack([rng.uniform(900, 1500, 30), rng.uniform(-600, 0, 30),
                              rng.uniform(0, 40, 30)])
    np.testing.assert_allclose(pl.project(ground, X0, R, 100.0),
                               pl.project(ground, camera, R_true, 100.0), atol=1e-12)


def test_a_boresight_error_shifts_the_ground_by_H_delta():
    import photolib as pl
    exact, first = da.boresight_ground_shift()
    assert [str(f) for f in first] == ["-H*delta_phi", "H*delta_omega"]
    H, d = 1000.0, np.radians(0.01)
    X0, R = pa.exterior_from_navigation([0.0, 0.0, H], 0.0, 0.0, 0.0)
    X0e, Re = pa.exterior_from_navigation([0.0, 0.0, H], 0.0, 0.0, 0.0, boresight=(d, 0, 0))
    principal = pl.monoplot([0.0, 0.0], X0, R, 100.0, 0.0)
    shifted = pl.monoplot([0.0, 0.0], X0e, Re, 100.0, 0.0)
    shift = np.linalg.norm(shifted - principal)
    assert shift == pytest.approx(H * d, rel=1e-6)            # 17 cm, as the docstring says
    assert round(shift, 2) == 0.17


@pytest.mark.parametrize("kw, match", [
    (dict(antenna=[1.0, 2.0]), "antenna"),
    (dict(lever_arm=[0.0, np.nan, 0.0]), "lever_arm"),
    (dict(mount=np.diag([1.0, 1.0, -1.0])), "mount must be a 3×3 rotation"),
    (dict(roll=float("inf")), "roll"),
])
def test_georeferencing_bad_input_is_named(kw, match):
    args = dict(antenna=[0.0, 0.0, 1000.0], roll=0.0, pitch=0.0, heading=0.0)
    args.update(kw)
    with pytest.raises(ValueError, match=match):
        pa.exterior_from_navigation(**args)
