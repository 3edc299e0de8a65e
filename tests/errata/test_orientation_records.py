"""The records added from the audit of the German summary (000_*) and the Polish notes (004_*),
re-checked by other routes.

NumPy/SciPy only (no SymPy derivation reused): rays cast through a camera, finite-difference
Jacobians and their singular values, rotation matrices built from cos/sin, a paraxial ray
trace through a stop and a thin lens, pixel counts of a real pyramid, line intersections by
Cramer's rule, and a least-squares DLT fit of a plane homography.
"""

import math

import numpy as np
import pytest
from scipy.spatial.transform import Rotation
import sympy as sp

from photolib import errata

SUMMARY = "000_5cb9d2460e6d5d8e.txt"
NOTES = "004_81219dec3a1f2881.txt"
NEW = {
    "de-summary:normal-case-y2": "right",
    "de-summary:normal-case-Y-from-y2": "right",
    "de-summary:normal-case-simplified-eta": "right-under-condition",
    "de-summary:fusion-limit": "not-checkable",
    "de-summary:image-vector-interior": "right-under-condition",
    "de-summary:image-vector-comment": "wrong",
    "de-summary:exterior-orientation-count": "right-under-condition",
    "de-summary:flight-attitude": "right-under-condition",
    "de-summary:metric-camera-principal-point": "wrong",
    "de-summary:circle-of-confusion": "not-checkable",
    "de-summary:aperture-longitudinal-colour": "right",
    "de-summary:chromatic-aperture": "right-under-condition",
    "pl-notes:projective-orientation": "right-under-condition",
    "pl-notes:palette": "right",
    "pl-notes:pyramid-overhead": "right",
    "pl-notes:camera-constant": "right-under-condition",
    "pl-notes:principal-point-fiducials": "right-under-condition",
    "pl-notes:affine-description": "wrong",
}
#: the ones whose source place is a single line or a line range of the seed
CITED_BY_LINE = [rid for rid in NEW if not rid.startswith("de-summary:normal-case-")
                 or rid.endswith("-eta")]


def kind(rid):
    return errata.get(rid).verdicts["printed"].split(":")[0]


@pytest.mark.parametrize("rid", sorted(NEW))
def test_new_records_registered_claimed_and_decided(rid):
    rec = errata.get(rid)
    assert rec.source.startswith(SUMMARY if rid.startswith("de-summary:") else NOTES)
    assert rec.specs["printed"].claim == "right"
    assert rec.verdicts == rec.stated
    assert kind(rid) == NEW[rid]
    ev = rec.evaluate("printed")
    if NEW[rid] == "wrong":
        assert ev.counterexample, rid          # every wrong carries a counterexample


@pytest.mark.parametrize("rid", CITED_BY_LINE)
def test_new_records_cite_a_line(rid):
    assert "line" in errata.get(rid).source


# -- normal case: camera 2 and the simplified η ---------------------------------------------------

def _project(R, X0, c, x0, y0, X):
    k = R.T @ (np.asarray(X, float) - np.asarray(X0, float))
    return x0 - c * k[0] / k[2], y0 - c * k[1] / k[2]


def test_normal_case_camera2_and_Y_from_eta2():
    c, x0, y0, B = 0.1, 0.003, -0.002, 2.0
    X = np.array([0.7, -1.3, -20.0])
    xi2, eta2 = _project(np.eye(3), [B, 0, 0], c, x0, y0, X)
    assert eta2 == pytest.approx(y0 - c * X[1] / X[2], rel=1e-14)            # η2 (line 582)
    assert X[2] * (eta2 - y0) / (-c) == pytest.approx(X[1], rel=1e-13)       # Y (line 586)
    assert B + X[2] * (xi2 - x0) / (-c) == pytest.approx(X[0], rel=1e-13)


def test_simplified_eta_needs_R_identity_and_Y0_Z0_zero():
    c, y0 = 0.1, 0.0
    X = np.array([0.7, -1.3, -20.0])
    printed = lambda R, Y: y0 - c * R[1, 1] * Y[1] / (R[2, 2] * Y[2])   # noqa: E731
    assert _project(np.eye(3), [0, 0, 0], c, 0, y0, X)[1] == pytest.approx(printed(np.eye(3), X))
    # a camera at Y0 = 1 (not allowed in the normal case) breaks it
    assert _project(np.eye(3), [0, 1.0, 0], c, 0, y0, X)[1] != pytest.approx(printed(np.eye(3), X))


# -- image vectors -------------------------------------------------------------------------------

def _rot(omega, phi, kappa):
    """R = R_ω·R_φ·R_κ by SciPy (intrinsic x-y-z), independent of photolib."""
    return Rotation.from_euler("XYZ", [omega, phi, kappa]).as_matrix()


def test_image_vector_signs_by_ray_casting():
    R, X0, c, x0, y0 = _rot(0.1, -0.2, 0.3), np.array([1.0, 2.0, 50.0]), 0.1, 0.004, -0.003
    X = np.array([3.0, -4.0, 1.0])
    d_xi, d_eta = 2e-4, -1e-4                                 # distortion of the measurement
    xi, eta = (v + d for v, d in zip(_project(R, X0, c, x0, y0, X), (d_xi, d_eta)))
    ray = X - X0
    course = np.array([xi - x0 - d_xi, eta - y0 - d_eta, -c])
    comment = np.array([x0 - xi - d_xi, y0 - eta - d_eta, -c])        # line 520
    cos = lambda a, b: a @ b / np.linalg.norm(a) / np.linalg.norm(b)  # noqa: E731
    assert cos(R @ course, ray) == pytest.approx(1.0, abs=1e-14)
    assert cos(R @ comment, ray) < 0.999                              # not along the ray
    # ξ = 1, ξ0 = 0, no distortion: the printed first component is −1, the ray's +1
    rec = errata.get("de-summary:image-vector-comment")
    at = {sp.Symbol("xi", real=True): 1, sp.Symbol("x0", real=True): 0,
          sp.Symbol("Delta_xi", real=True): 0}
    assert rec.versions["printed"][0].subs(at) == -1 and rec.derived()[0].subs(at) == 1
    # line 385: (ξ, η, 0) + K with K = −(ξ0 + Δξ, η0 + Δη, c) is the course vector
    K = -np.array([x0 + d_xi, y0 + d_eta, c])
    assert np.allclose(np.array([xi, eta, 0.0]) + K, course, atol=1e-15)
    assert kind("de-summary:image-vector-comment") == "wrong"


def test_image_vector_comment_counterexample_reevaluated():
    rec = errata.get("de-summary:image-vector-comment")
    ev = rec.evaluate("printed")
    printed = rec.versions["printed"].subs(ev.counterexample)
    derived = rec.derived().subs(ev.counterexample)
    assert abs(float(printed[0] - derived[0])) > 1e-6
    assert printed[2] == derived[2]


# -- exterior orientation: 6, not 7 ---------------------------------------------------------------

def _image_points(params, points, c=0.15):
    X0, ang = params[:3], params[3:6]                         # params[6] = t, unused
    R = _rot(*ang)
    return np.concatenate([_project(R, X0, c, 0, 0, P) for P in points])


def test_exterior_orientation_rank_by_finite_differences():
    pts = [(0, 0, 0), (3, 1, 0.5), (-2, 2, -0.3), (1, -3, 0.2)]
    p = np.array([0.5, -1 / 3, 10.0, 0.1, -0.2, 0.3, 7.0])
    h = 1e-6
    J = np.column_stack([(_image_points(p + h * e, pts) - _image_points(p - h * e, pts)) / (2 * h)
                         for e in np.eye(7)])
    s = np.linalg.svd(J, compute_uv=False)
    assert s[5] > 1e-5 and s[6] < 1e-12                       # rank 6 of 7
    assert np.all(J[:, 6] == 0)                               # the time column
    assert kind("de-summary:exterior-orientation-count") == "right-under-condition"


# -- attitude angles -----------------------------------------------------------------------------

def test_attitude_axes_and_sequence_numpy():
    for i, axis in enumerate(np.eye(3)):
        ang = np.zeros(3)
        ang[i] = 0.3
        R = _rot(*ang)
        assert np.allclose(R @ axis, axis)                    # ω about X, φ about Y, κ about Z
    rz = lambda k: _rot(0, 0, k)                              # noqa: E731
    ry = lambda p: _rot(0, p, 0)                              # noqa: E731
    rx = lambda w: _rot(w, 0, 0)                              # noqa: E731
    diffs = []
    for eps in (1e-2, 1e-3):
        w, p, k = eps, 2 * eps, 3 * eps
        diffs.append(np.abs(_rot(w, p, k) - rz(k) @ ry(p) @ rx(w)).max())
    assert diffs[0] / diffs[1] == pytest.approx(100, rel=0.05)  # second order
    assert np.abs(_rot(0.1, 0.2, 0.3) - rz(0.3) @ ry(0.2) @ rx(0.1)).max() > 0.05


# -- metric camera: distortion and principal point are independent -------------------------------

def test_distortion_free_camera_with_offset_principal_point():
    c, x0, y0 = 0.1, 0.02, 0.0
    R, X0 = _rot(0.05, -0.1, 0.2), np.array([1.0, 2.0, 30.0])
    on_axis = X0 + R @ np.array([0, 0, -10.0])
    assert np.allclose(_project(R, X0, c, x0, y0, on_axis), (x0, y0), atol=1e-15)
    assert kind("de-summary:metric-camera-principal-point") == "wrong"


# -- chromatic aberration: paraxial trace through a stop and a thin lens -------------------------

def _trace(rho, f_w, a_img, s_stop, tau):
    h = rho + s_stop * math.tan(tau)                          # height at the lens
    slope = math.tan(tau) - h / f_w
    return h + a_img * slope


@pytest.mark.parametrize("k", [2.0, 4.0, 8.0])
def test_stop_shrinks_longitudinal_not_lateral_colour(k):
    f, f1, f2, s_stop, tau = 50.0, 50.0, 50.25, 10.0, math.radians(20)
    d = f / k
    rhos = np.linspace(-d / 2, d / 2, 201)
    spot2 = np.array([_trace(r, f2, f1, s_stop, tau) for r in rhos])
    spot1 = np.array([_trace(r, f1, f1, s_stop, tau) for r in rhos])
    assert np.ptp(spot1) < 1e-12                              # wavelength 1 in focus
    assert np.ptp(spot2) == pytest.approx(d * abs(1 - f1 / f2), rel=1e-12)
    lateral = _trace(0, f2, f1, s_stop, tau) - _trace(0, f1, f1, s_stop, tau)
    assert lateral == pytest.approx(s_stop * math.tan(tau) * (f2 - f1) / f2, rel=1e-12)
    assert lateral * 1000 == pytest.approx(18.108, abs=1e-3)   # µm, the same for every k


def test_chromatic_verdicts():
    assert kind("de-summary:aperture-longitudinal-colour") == "right"
    assert kind("de-summary:chromatic-aperture") == "right-under-condition"
    assert kind("de-summary:circle-of-confusion") == "not-checkable"
    assert math.degrees(1 / 1500) * 60 == pytest.approx(2.29, abs=0.005)
    assert 1.3 * 360 / 400 == pytest.approx(1.17)
    assert kind("de-summary:fusion-limit") == "not-checkable"


# -- Polish notes --------------------------------------------------------------------------------

def test_pyramid_overhead_by_counting_pixels():
    w = h = 10_000
    base, extra = w * h, 0
    while w > 512:
        w, h = -(-w // 2), -(-h // 2)
        extra += w * h
    assert 100 * extra / base == pytest.approx(33.3, abs=0.05)
    assert round(100 * extra / base) == 33
    assert sum(4.0 ** -i for i in range(1, 60)) == pytest.approx(1 / 3, rel=1e-15)


def test_palette_is_eight_bits():
    assert 248 + 8 == 256 == 2**8 == len({format(i, "08b") for i in range(256)})
    assert kind("pl-notes:palette") == "right"


def test_camera_constant_thin_lens():
    f = 0.153
    for a, want in ((10 * f, 10 / 9 * f), (1e6, f)):
        ap = 1 / (1 / f - 1 / a)
        assert ap == pytest.approx(want, rel=1e-6)
    assert (1 / (1 / f - 1 / 1000) - f) * 1e6 == pytest.approx(23.41, abs=0.01)   # µm
    assert kind("pl-notes:camera-constant") == "right-under-condition"


def _intersection(p1, p2, p3, p4):
    A = np.column_stack([p3 - p1, -(p4 - p2)])
    u, _ = np.linalg.solve(A, p2 - p1)
    return p1 + u * (p3 - p1)


def test_fiducial_centre_versus_mean():
    marks = np.array([(0, -100), (100, 0), (0, 110), (-100, 0)], float)
    assert np.allclose(_intersection(*marks), (0, 0))
    assert np.allclose(marks.mean(axis=0), (0, 2.5))
    rng = np.random.default_rng(5)
    for _ in range(20):                                       # random parallelograms agree
        p1, p2, p3 = rng.normal(0, 100, (3, 2))
        par = np.array([p1, p2, p3, p1 + p3 - p2])
        assert np.allclose(_intersection(*par), par.mean(axis=0), atol=1e-9)
    rec = errata.get("pl-notes:principal-point-fiducials")
    ev = rec.evaluate("printed")
    got = rec.versions["printed"].subs(ev.counterexample)
    assert [float(v) for v in got] == [0.0, 2.5]
    assert [float(v) for v in rec.derived().subs(ev.counterexample)] == [0.0, 0.0]


def _fit_homography(src, dst):
    rows = []
    for (x, y), (X, Y) in zip(src, dst):
        rows.append([x, y, 1, 0, 0, 0, -X * x, -X * y, -X])
        rows.append([0, 0, 0, x, y, 1, -Y * x, -Y * y, -Y])
    _, s, Vt = np.linalg.svd(np.array(rows))
    return Vt[-1].reshape(3, 3), s[-1]


def test_plane_image_is_a_homography_and_distortion_is_not():
    R, X0, c = _rot(0.05, -0.08, 0.4), np.array([10.0, -5.0, 100.0]), 0.15
    rng = np.random.default_rng(2)
    ground = np.column_stack([rng.uniform(-40, 40, (30, 2)), np.zeros(30)])
    img = np.array([_project(R, X0, c, 0.001, -0.002, P) for P in ground])
    _, resid = _fit_homography(img * 100, ground[:, :2] / 100)   # conditioned
    assert resid < 1e-10
    r2 = (img**2).sum(axis=1, keepdims=True)
    distorted = img * (1 + 2.0 * r2)                              # strong radial distortion
    _, resid_d = _fit_homography(distorted * 100, ground[:, :2] / 100)
    assert resid_d > 1e3 * resid
    assert kind("pl-notes:projective-orientation") == "right-under-condition"


def test_described_affine_has_five_parameters_and_misses_shear():
    def described(q, xy):
        tx, ty, sx, sy, th = q
        Rm = np.array([[math.cos(th), -math.sin(th)], [math.sin(th), math.cos(th)]])
        return (Rm @ np.diag([sx, sy]) @ xy.T).T + (tx, ty)
    xy = np.array([(0.3, -0.6), (0.8, 1.7), (-1.7, 0.1), (1.5, -2.7), (-0.2, -0.6)])
    q = np.array([0.1, -0.2, 1.1, 0.9, 0.4])
    h = 1e-6
    J = np.column_stack([(described(q + h * e, xy) - described(q - h * e, xy)).ravel() / (2 * h)
                         for e in np.eye(5)])
    assert np.linalg.matrix_rank(J, tol=1e-6) == 5
    shear = np.array([[1, 0.1], [0, 1]])
    # R·D has a diagonal Gram matrix for every θ, the shear has not
    assert abs((shear.T @ shear)[0, 1]) == pytest.approx(0.1)
    for th in np.linspace(0, math.pi, 7):
        Rm = np.array([[math.cos(th), -math.sin(th)], [math.sin(th), math.cos(th)]])
        G = (Rm @ np.diag([1.2, 0.8])).T @ (Rm @ np.diag([1.2, 0.8]))
        assert abs(G[0, 1]) < 1e-14
    rec = errata.get("pl-notes:affine-description")
    assert kind("pl-notes:affine-description") == "wrong"
    assert sp.Rational(1, 10) in rec.evaluate("printed").counterexample.values()
