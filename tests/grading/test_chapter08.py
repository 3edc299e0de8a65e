"""The exercises of chapter 08 (space resection and DLT), judged as the grader does.

The same checks as ``test_chapter_exercises.py`` runs for chapters 04-06 (reference
accepted, every declared mistake recognised with its hint, variants differ, functions judged
on hidden cases, untouched answers not answered), plus checks of the references by an
independent route: OpenCV's ``projectPoints`` and ``decomposeProjectionMatrix``.

OpenCV's camera looks along +z with y down; ours along −z with y up. With
``(kx, ky, N) = Rᵀ(X − X0)`` the OpenCV camera coordinates are ``(kx, −ky, −N)``, so
``u = c·kx/(−N) + x'0 = x'`` and ``v = c·(−ky)/(−N) = y'0 − y'`` (OpenCV's c_y set to 0).
"""

from __future__ import annotations

import math

import cv2
import numpy as np
import pytest
import sympy as sp

from photolib.grading.exercises import ch08_resection_dlt as ch08
from photolib.grading.notebook import parameters_for
from photolib.grading.spec import Params
from photolib.grading.variants import rng_for

from .chapter_checks import BatchGradedChecks, ChapterChecks
from .chapter_checks import judge_as_grader as _judge

EXERCISES = ch08.EXERCISES
BY_ID = {ex.id: ex for ex in EXERCISES}
STUDENTS = ("s1000001", "s1000002", "s1000003", "s2345678")


def _opencv_project(X, p):
    """Image coordinates (x', y') in mm of the camera of a variant, by cv2.projectPoints."""
    R = ch08._rotation(p)
    R_cv = np.diag([1.0, -1.0, -1.0]) @ R.T          # object → OpenCV camera
    t = -R_cv @ ch08._centre(p)
    K = np.array([[p["c_mm"], 0.0, p["x0_mm"]], [0.0, p["c_mm"], 0.0], [0.0, 0.0, 1.0]])
    uv, _ = cv2.projectPoints(np.asarray(X, float).reshape(-1, 1, 3), cv2.Rodrigues(R_cv)[0],
                              t, K, np.zeros(5))
    uv = uv.reshape(-1, 2)
    return np.column_stack([uv[:, 0], p["y0_mm"] - uv[:, 1]])


def _dlt_ratio(L, X):
    L = np.asarray(L, float)
    h = np.column_stack([X, np.ones(len(X))])
    den = h[:, :3] @ L[8:11] + 1.0
    return np.column_stack([h @ L[0:4], h @ L[4:8]]) / den[:, None]


def _points_in_front(p, n=8, seed=0):
    rng = np.random.default_rng(seed)
    R = ch08._rotation(p)
    rays = R @ np.vstack([rng.uniform(-0.3, 0.3, (2, n)), -np.ones(n)])
    return ch08._centre(p) + (rays * rng.uniform(2.0, 40.0, n)).T


# -- the same checks as for chapters 04-06 --------------------------------------------------------

class TestChapter08(ChapterChecks, BatchGradedChecks):
    module = ch08
    chapter_name = "08-resection-dlt"
    kinds = {"number", "array", "expression", "function"}
    students = STUDENTS
    slow_mistakes = frozenset({'rdl.dlt-coefficient'})
    scalar_cases = False            # rdl.resection-step and rdl.dlt-estimate take point arrays
    grade_timeout = 120             # the real photograph: the chapter-05 calibration, ~2 s


def test_a_slightly_wrong_function_is_wrong_without_a_hint():
    ex = BY_ID["rdl.image-point"]
    f = ex.reference(parameters_for(ex, STUDENTS[0]))
    verdict = _judge(ex, STUDENTS[0], lambda X, Y, Z: f(X, Y, Z) + 0.01)
    assert verdict.status == "wrong" and verdict.mistake == "other"
    assert verdict.message == "not correct"


# -- the references by an independent route -------------------------------------------------------

@pytest.mark.parametrize("sid", STUDENTS)
def test_redundancy_counts_observations_minus_unknowns(sid):
    p = parameters_for(BY_ID["rdl.redundancy"], sid)
    unknowns = {"space resection": 6, "DLT": 11}[p["method"]]
    assert ch08._redundancy(p) == 2 * p["n"] - unknowns > 0


@pytest.mark.parametrize("sid", STUDENTS)
def test_dlt_vector_reproduces_opencv_projection(sid):
    p = parameters_for(BY_ID["rdl.dlt-vector"], sid)
    X = _points_in_front(p)
    np.testing.assert_allclose(_dlt_ratio(ch08._dlt_vector(p), X), _opencv_project(X, p),
                               atol=1e-9)


@pytest.mark.parametrize("sid", STUDENTS)
def test_dlt_interior_agrees_with_opencv_decomposition(sid):
    p = parameters_for(BY_ID["rdl.dlt-interior"], sid)
    P = np.append(p["L"], 1.0).reshape(3, 4)
    K, _, _, *_ = cv2.decomposeProjectionMatrix(P)
    K = K / K[2, 2]
    x0, y0, c = ch08._interior(p)
    assert abs(K[0, 1]) < 1e-6 * abs(K[0, 0])          # no shear
    np.testing.assert_allclose([K[0, 2], K[1, 2], abs(K[0, 0])], [x0, y0, c], atol=1e-6)


@pytest.mark.parametrize("sid", STUDENTS[:2])
def test_dlt_interior_recovers_the_camera_it_was_drawn_from(sid):
    rng = rng_for(sid, "rdl.dlt-interior")
    camera = ch08._close_range_orientation(rng)
    p = parameters_for(BY_ID["rdl.dlt-interior"], sid)
    np.testing.assert_allclose(ch08._interior(p), [camera["x0_mm"], camera["y0_mm"],
                                                   camera["c_mm"]], atol=1e-6)


@pytest.mark.parametrize("sid", STUDENTS[:2])
def test_dlt_coefficients_reproduce_opencv_projection(sid):
    p = Params(ch08._close_range_orientation(np.random.default_rng(len(sid))))
    from photolib.derive import collinearity as dc
    R = ch08._rotation(p)
    values = dict(zip(dc.r, R.ravel())) | {dc.X0: p["X0"], dc.Y0: p["Y0"], dc.Z0: p["Z0"],
                                           dc.c: p["c_mm"], dc.x0: p["x0_mm"], dc.y0: p["y0_mm"]}
    L = [float(ch08._coefficient(Params(k=k)).xreplace(values)) for k in range(1, 12)]
    X = _points_in_front(p, seed=3)
    np.testing.assert_allclose(_dlt_ratio(L, X), _opencv_project(X, p), atol=1e-9)


def test_dlt_coefficient_accepts_a_plain_symbol_derivation():
    ex = BY_ID["rdl.dlt-coefficient"]
    r = sp.Matrix(3, 3, sp.symbols("r11 r12 r13 r21 r22 r23 r31 r32 r33"))
    X0, Y0, Z0, c, x0 = sp.symbols("X0 Y0 Z0 c x0")
    D = -(r[0, 2] * X0 + r[1, 2] * Y0 + r[2, 2] * Z0)
    L1 = (x0 * r[0, 2] - c * r[0, 0]) / D
    sid = next(s for s in (f"s{i}" for i in range(100))
               if parameters_for(ex, s)["k"] == 1)
    assert _judge(ex, sid, L1).status == "correct"
    assert _judge(ex, sid, "(x0*r13 - c*r11)/(-(r13*X0 + r23*Y0 + r33*Z0))").status == "correct"


@pytest.mark.parametrize("sid", STUDENTS[:2])
def test_image_point_reference_agrees_with_opencv(sid):
    ex = BY_ID["rdl.image-point"]
    p = parameters_for(ex, sid)
    P = np.append(p["L"], 1.0).reshape(3, 4)
    K, R_cv, C, *_ = cv2.decomposeProjectionMatrix(P)
    K = K / K[2, 2]
    C = (C[:3] / C[3]).ravel()
    f = ex.reference(p)
    X = np.array(ex.cases(rng_for(sid, ex.id, "public"), p))
    uv, _ = cv2.projectPoints(X.reshape(-1, 1, 3), cv2.Rodrigues(R_cv)[0], -R_cv @ C, K,
                              np.zeros(5))
    ours = np.array([f(*x) for x in X])
    np.testing.assert_allclose(ours, uv.reshape(-1, 2), atol=1e-6)
    assert math.isclose(abs(K[0, 0]), abs(K[1, 1]), rel_tol=1e-7)


# -- fairness and hints of the audit (float32, OpenCV, rounded answers) ---------------------------

def _rotation_scipy(p):
    from scipy.spatial.transform import Rotation
    return Rotation.from_euler("XYZ", [math.radians(p[n]) for n in ch08._ANGLES]).as_matrix()


def _dlt_by_hand(p, dtype=float):
    R = _rotation_scipy(p).astype(dtype)
    K = np.array([[-p["c_mm"], 0, p["x0_mm"]], [0, -p["c_mm"], p["y0_mm"]], [0, 0, 1]], dtype)
    X0 = np.array([p["X0"], p["Y0"], p["Z0"]], dtype)
    M = K @ R.T @ np.column_stack([np.eye(3, dtype=dtype), -X0])
    return (M / M[2, 3]).ravel()[:11]


@pytest.mark.parametrize("sid", STUDENTS)
def test_dlt_vector_accepts_float32_and_seven_digits(sid):
    ex = BY_ID["rdl.dlt-vector"]
    p = parameters_for(ex, sid)
    L = _dlt_by_hand(p)
    assert _judge(ex, sid, _dlt_by_hand(p, np.float32)).status == "correct"
    assert _judge(ex, sid, [float(f"{v:.6g}") for v in L]).status == "correct"
    assert _judge(ex, sid, L * 1.001).status == "wrong"


@pytest.mark.parametrize("sid", STUDENTS)
def test_dlt_interior_opencv_negative_c_has_a_hint(sid):
    ex = BY_ID["rdl.dlt-interior"]
    p = parameters_for(ex, sid)
    K = cv2.decomposeProjectionMatrix(np.append(p["L"], 1.0).reshape(3, 4))[0]
    K = K / K[2, 2]
    assert _judge(ex, sid, np.array([K[0, 2], K[1, 2], abs(K[0, 0])])).status == "correct"
    verdict = _judge(ex, sid, np.array([K[0, 2], K[1, 2], K[0, 0]]))   # K[0, 0] = −c
    assert verdict.mistake == "sign-c" and "OpenCV" in verdict.message


@pytest.mark.parametrize("sid", STUDENTS)
def test_dlt_interior_accepts_a_float32_decomposition(sid):
    ex = BY_ID["rdl.dlt-interior"]
    L = np.array(parameters_for(ex, sid)["L"], np.float32)
    D2 = 1 / (L[8:11] @ L[8:11])
    x0, y0 = D2 * (L[0:3] @ L[8:11]), D2 * (L[4:7] @ L[8:11])
    c = np.sqrt(D2 * (L[0:3] @ L[0:3]) - x0**2)
    assert _judge(ex, sid, np.array([x0, y0, c], np.float32)).status == "correct"


def test_dlt_coefficient_reversed_principal_point_has_a_hint():
    ex = BY_ID["rdl.dlt-coefficient"]
    r = sp.Matrix(3, 3, sp.symbols("r11 r12 r13 r21 r22 r23 r31 r32 r33"))
    X0, Y0, Z0, c, x0 = sp.symbols("X0 Y0 Z0 c x0")
    D = -(r[0, 2] * X0 + r[1, 2] * Y0 + r[2, 2] * Z0)
    sid = next(s for s in (f"s{i}" for i in range(100)) if parameters_for(ex, s)["k"] == 1)
    verdict = _judge(ex, sid, (-x0 * r[0, 2] - c * r[0, 0]) / D)
    assert verdict.mistake == "principal-point"


@pytest.mark.parametrize("sid", STUDENTS)
def test_image_point_accepts_float32_and_rounded_coordinates(sid):
    ex = BY_ID["rdl.image-point"]
    L = np.array(parameters_for(ex, sid)["L"])
    L32 = L.astype(np.float32)

    def f32(X, Y, Z):
        h = np.array([X, Y, Z, 1.0], np.float32)
        return np.array([L32[:4] @ h, L32[4:8] @ h]) / (L32[8:] @ h[:3] + np.float32(1))

    def rounded(X, Y, Z):
        h = np.array([X, Y, Z, 1.0])
        return np.round(np.array([L[:4] @ h, L[4:8] @ h]) / (L[8:] @ h[:3] + 1), 4)
    assert _judge(ex, sid, f32).status == "correct"
    assert _judge(ex, sid, rounded).status == "correct"


# -- the exercises of issues 15/16: functions, scenarios, the real photograph ---------------------

def _hidden_cases(ex, sid):
    return ex.cases(rng_for(sid, ex.id, "hidden"), parameters_for(ex, sid))


@pytest.mark.parametrize("sid", STUDENTS[:2])
def test_resection_step_agrees_with_a_numerical_jacobian_and_converges(sid):
    ex = BY_ID["rdl.resection-step"]
    p = parameters_for(ex, sid)
    step, numeric = ex.reference(p), ch08._gn_wrong()(p)     # no mistake: a numerical Jacobian
    X, xy, q = _hidden_cases(ex, sid)[0]                     # the clean case
    np.testing.assert_allclose(step(X, xy, q), numeric(X, xy, q), atol=1e-6)
    import photolib as pl
    full = pl.space_resection(X, xy, p["c_mm"], initial=q).params
    for _ in range(8):
        q = step(X, xy, q)
    # iterated from its start, the step reaches the adjusted orientation
    np.testing.assert_allclose(q, full, atol=1e-9)


@pytest.mark.parametrize("sid", STUDENTS[:2])
def test_resection_step_and_dlt_refuse_the_degenerate_cases(sid):
    step = BY_ID["rdl.resection-step"].reference(parameters_for(BY_ID["rdl.resection-step"], sid))
    cases = _hidden_cases(BY_ID["rdl.resection-step"], sid)
    with pytest.raises(ValueError, match="collinear"):
        step(*cases[3])
    with pytest.raises(ValueError, match="≥ 3"):
        step(*cases[4])
    dlt = BY_ID["rdl.dlt-estimate"].reference(parameters_for(BY_ID["rdl.dlt-estimate"], sid))
    with pytest.raises(ValueError, match="coplanar"):
        dlt(*_hidden_cases(BY_ID["rdl.dlt-estimate"], sid)[3])


def test_dlt_estimate_recovers_the_camera_on_the_clean_case():
    import photolib as pl
    ex = BY_ID["rdl.dlt-estimate"]
    camera = Params(ch08._close_range_orientation(np.random.default_rng(5)))
    X = _points_in_front(camera, n=9, seed=5)
    xy = pl.project(X, ch08._centre(camera), ch08._rotation(camera), camera["c_mm"],
                    camera["x0_mm"], camera["y0_mm"])
    L_true = _dlt_by_hand(camera)                # K·Rᵀ·[I | −X0] with SciPy's rotation
    np.testing.assert_allclose(ex.reference(Params())(X, xy), L_true, rtol=1e-8, atol=1e-12)


@pytest.mark.parametrize("sid", STUDENTS)
def test_dlt_chain_steps_share_the_points_and_carry_the_estimate(sid):
    steps = [BY_ID[i] for i in ("rdl.dlt-chain", "rdl.dlt-chain-estimate", "rdl.dlt-chain-interior")]
    p1, p2, p3 = (parameters_for(ex, sid) for ex in steps)
    assert p1["n"] == p2["n"] == p3["n"] == len(p2["X"])
    L = steps[1].reference(p2)
    np.testing.assert_allclose(p3["L"], L, rtol=1e-9)
    # the decomposition gives back the drawn camera within the rounding of the points
    rng = rng_for(sid, "rdl.dlt-chain")
    camera = ch08._close_range_orientation(rng)
    x0, y0, c = steps[2].reference(p3)
    assert abs(x0 - camera["x0_mm"]) < 0.05 and abs(y0 - camera["y0_mm"]) < 0.05
    assert abs(c - camera["c_mm"]) < 0.05


@pytest.mark.parametrize("sid", STUDENTS[:2])
def test_real_resection_agrees_with_solvepnp_and_the_precision_with_the_covariance(sid):
    import photolib as pl
    from photolib.nb import project as pj
    ex1, ex2 = BY_ID["rdl.real-resection"], BY_ID["rdl.real-precision"]
    p1, p2 = parameters_for(ex1, sid), parameters_for(ex2, sid)
    assert (p1["view"], p1["unused"]) == (p2["view"], p2["unused"])
    q = ex1.reference(p1)
    control = [k for k in range(54) if k not in p1["unused"]]
    r = pj.calibration().result
    K = np.array([[r.c, 0, r.x0 + 319.5], [0, r.c, 239.5 - r.y0], [0, 0, 1.0]])
    px = pl.pixel_from_image(pj.image_coordinates(p1["view"])[control], 640, 480, 1.0)
    X = pj.board_points()[control]
    ok, rvec, tvec = cv2.solvePnP(X, px, K, None, flags=cv2.SOLVEPNP_ITERATIVE)
    rvec, tvec = cv2.solvePnPRefineLM(X, px, K, None, rvec, tvec,
                                      (cv2.TERM_CRITERIA_COUNT + cv2.TERM_CRITERIA_EPS, 200, 1e-15))
    X0, R = pl.exterior_from_opencv_pose(cv2.Rodrigues(rvec)[0], tvec.ravel())
    assert ok
    np.testing.assert_allclose(q[:3], X0, atol=1e-5)
    np.testing.assert_allclose(pl.rotation_opk(*q[3:]), R, atol=1e-7)
    # step 2 at the printed q: the adjustment's own covariance, to the 3 digits asked
    std = pj.resect(p1["view"], control).std[:3]
    np.testing.assert_allclose(ex2.reference(p2), std, rtol=2e-3)
    # the tolerance of step 1 is one σ of each unknown, a fraction of a mm for X0
    _, atol = ex1.tolerances(p1)
    assert np.all(atol[:3] < 1.5) and _judge(ex1, sid, q + 0.5 * atol).status == "correct"
