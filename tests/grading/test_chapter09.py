"""The exercises of chapter 09 (stereo), judged as the grader does.

The same checks as for chapter 08 (reference accepted, every declared mistake recognised
with its hint, variants differ, functions judged on hidden cases, untouched answers not
answered), plus checks of the references by independent routes: SymPy (the normal-case
derivation), Monte Carlo (σ_Z), OpenCV (triangulatePoints, the essential matrix of its poses).
"""

from __future__ import annotations

import numpy as np
import pytest
import sympy as sp

from photolib.derive import stereo as ds
from photolib.grading.exercises import ch09_stereo as ch09
from photolib.grading.notebook import parameters_for
from photolib.grading.variants import rng_for

from .chapter_checks import ChapterChecks
from .chapter_checks import judge_as_grader as _judge

cv2 = pytest.importorskip("cv2")

EXERCISES = ch09.EXERCISES
BY_ID = {ex.id: ex for ex in EXERCISES}
STUDENTS = ("s1000001", "s1000002", "s1000003", "s2345678", "s3000003", "s3000004",
            "s3000005", "s3000006")
D = np.diag([1.0, -1.0, -1.0])


class TestChapter09(ChapterChecks):
    module = ch09
    chapter_name = "09-stereo"
    kinds = {"number", "array", "function", "choice"}
    students = STUDENTS
    scalar_cases = False            # st.rays and st.ro-step take image points and arrays


def test_intersection_cases_have_a_positive_parallax():
    # that they are scalar and the hidden ones differ: ChapterChecks
    ex = BY_ID["st.intersection"]
    params = parameters_for(ex, STUDENTS[0])
    for purpose in ("public", "hidden"):
        for case in ex.cases(rng_for(STUDENTS[0], ex.id, purpose), params):
            assert case[0] > case[2]                                            # px' > 0


def test_a_slightly_wrong_function_is_wrong_without_a_hint():
    ex = BY_ID["st.intersection"]
    f = ex.reference(parameters_for(ex, STUDENTS[0]))
    verdict = _judge(ex, STUDENTS[0], lambda *a: f(*a) + 0.01)
    assert verdict.status == "wrong" and verdict.mistake == "other"


def test_a_student_solution_written_from_the_formulas_is_correct():
    ex = BY_ID["st.intersection"]
    p = parameters_for(ex, STUDENTS[1])

    def point(x1, y1, x2, y2):
        px = x1 - x2
        return np.array([p.B_m * (x1 - p.x0_mm) / px, p.B_m * (y1 - p.y0_mm) / px,
                         -p.c_mm * p.B_m / px])
    assert _judge(ex, STUDENTS[1], point).status == "correct"


# -- the references by an independent route -------------------------------------------------------

@pytest.mark.parametrize("sid", STUDENTS[:4])
def test_height_reference_is_the_sympy_derivation(sid):
    p = parameters_for(BY_ID["st.height"], sid)
    Z = ds.height_from_parallax().subs({ds.c: sp.Float(p.c_mm, 30), ds.B: sp.Float(p.B_m, 30),
                                        ds.px: sp.Float(p.px_mm, 30)})
    assert ch09._height(p) == pytest.approx(float(Z), rel=1e-13)
    assert ch09._height(p) < 0


@pytest.mark.parametrize("sid", STUDENTS[:2])
def test_sigma_z_reference_by_monte_carlo(sid):
    p = parameters_for(BY_ID["st.sigma-z"], sid)
    rng = np.random.default_rng(3)
    n = 200_000
    X = np.array([p.B_m / 2, 0.0, -p.h_m])
    x1 = p.c_mm * X[0] / p.h_m + p.s_x_um * 1e-3 * rng.standard_normal(n)
    x2 = p.c_mm * (X[0] - p.B_m) / p.h_m + p.s_x_um * 1e-3 * rng.standard_normal(n)
    Z = -p.c_mm * p.B_m / (x1 - x2)
    assert np.std(Z) * 1e3 == pytest.approx(ch09._sigma_z(p), rel=0.01)


@pytest.mark.parametrize("sid", STUDENTS[:3])
def test_intersection_reference_agrees_with_opencv(sid):
    ex = BY_ID["st.intersection"]
    p = parameters_for(ex, sid)
    f = ex.reference(p)
    cases = np.array(ex.cases(rng_for(sid, ex.id, "public"), p))
    K = np.array([[p.c_mm, 0, p.x0_mm], [0, p.c_mm, -p.y0_mm], [0, 0, 1.0]])
    P1 = K @ np.column_stack([D, np.zeros(3)])
    P2 = K @ np.column_stack([D, -D @ [p.B_m, 0.0, 0.0]])
    H = cv2.triangulatePoints(P1, P2, (cases[:, :2] * [1, -1]).T, (cases[:, 2:] * [1, -1]).T)
    np.testing.assert_allclose(np.array([f(*case) for case in cases]), (H[:3] / H[3]).T,
                               rtol=1e-8, atol=1e-8)


@pytest.mark.parametrize("sid", STUDENTS[:3])
def test_essential_reference_is_opencvs_essential_matrix(sid):
    import photolib as pl
    p = parameters_for(BY_ID["st.essential"], sid)
    R1 = pl.rotation_opk(*np.radians([p[n] for n in ch09._ANGLES[:3]]))
    R2 = pl.rotation_opk(*np.radians([p[n] for n in ch09._ANGLES[3:]]))
    (Ra, ta), (Rb, tb) = (pl.opencv_pose_from_exterior(p.X01, R1),
                          pl.opencv_pose_from_exterior(p.X02, R2))
    Rr, tr = Rb @ Ra.T, tb - Rb @ Ra.T @ ta
    E_cv = np.array([[0, -tr[2], tr[1]], [tr[2], 0, -tr[0]], [-tr[1], tr[0], 0]]) @ Rr
    ours = ch09._essential(p)
    mapped = D @ E_cv.T @ D          # p2ᵀ E_cv p1 = 0 with p = D·x*/c
    assert min(np.abs(ours - mapped).max(), np.abs(ours + mapped).max()) < 1e-9
    # and the coplanarity of a projected point
    X = np.array(p.X01) + [20.0, 3.0, -100.0]
    xs = [(X - np.array(X0)) @ R for X0, R in ((p.X01, R1), (p.X02, R2))]
    xs = [k * (-50.0 / k[2]) for k in xs]          # image vectors with c = 50
    assert abs(xs[0] @ ours @ xs[1]) < 1e-9 * np.abs(ours).max() * 2500


def test_unknown_counts_are_the_derived_ones():
    counts = ds.orientation_unknowns()
    by_start = {start: ch09._TASKS[next(t for t in ch09._TASKS if t.startswith(start))][0]
                for start in ("the dependent", "the absolute", "the exterior")}
    assert by_start == {"the dependent": counts["relative"], "the absolute": counts["absolute"],
                        "the exterior": counts["exterior"]}
    ex = BY_ID["st.unknowns"]
    seen = {ex.reference(parameters_for(ex, f"s{i}")) for i in range(60)}
    assert seen == set("abcde")


def _printed_options(statement):
    """``{count: letter}`` read from the printed "(a) 5, (b) 6, …" of a statement."""
    import re
    return {int(n): k for k, n in re.findall(r"\(([a-e])\) (\d+)", statement)}


def test_unknowns_question_counts_what_the_answer_counts():
    # the forward intersection has 3 unknowns: the object coordinates, so the question must not
    # say "orientation parameters, not object coordinates" for it (and must for the others)
    ex = BY_ID["st.unknowns"]
    counts = ds.orientation_unknowns()
    expected_by_word = {"relative": counts["relative"], "absolute": counts["absolute"],
                        "exterior": counts["exterior"], "resection": 6,
                        "intersection": 3}            # X, Y, Z of one point
    seen = set()
    for i in range(300):
        sid = f"s{4000000 + i}"
        p = parameters_for(ex, sid)
        text = ex.statement.format(**p)
        intersection = "forward intersection" in p["task"]
        assert ("not the object coordinates" in text) is not intersection
        assert ("coordinates of that point" in text) is intersection
        # the lead-in fits the question: no tie points of the pair for one intersected point
        assert ("tie points" in text) is not intersection
        expected = next(v for w, v in expected_by_word.items() if w in p["task"])
        assert ex.reference(p) == _printed_options(text)[expected]
        seen.add(p["task"])
    assert len(seen) == len(ch09._TASKS)


def test_unknowns_variant_does_not_carry_the_answer():
    ex = BY_ID["st.unknowns"]
    for sid in STUDENTS:
        p = parameters_for(ex, sid)
        assert set(p) == {"task", "n", "counted", "lead"}
        assert not set(str(v) for v in p.values()) & set("abcde")


# -- the chapter's notebook helpers of the orientation sections (photolib.nb.stereo) -------------
# (T6: orientation by epipolar rays; T12: Luhmann 4.76), each against an independent route

def _opencv_epiline_in_image_2(X01, R1, X02, R2, c, xy1):
    """OpenCV's epipolar line in image 2 of the image-1 point xy1 (mm), as (a, b, d) in (x', y')."""
    import photolib as pl
    (Ra, ta), (Rb, tb) = (pl.opencv_pose_from_exterior(X01, R1),
                          pl.opencv_pose_from_exterior(X02, R2))
    Rr, tr = Rb @ Ra.T, tb - Rb @ Ra.T @ ta
    tx = np.array([[0, -tr[2], tr[1]], [tr[2], 0, -tr[0]], [-tr[1], tr[0], 0]])
    Ki = np.linalg.inv(np.diag([c, c, 1.0]))
    F_cv = Ki.T @ tx @ Rr @ Ki
    a, b, d = cv2.computeCorrespondEpilines(np.array([[[xy1[0], -xy1[1]]]]), 1, F_cv).ravel()
    return np.array([a, -b, d])                     # (u, v) = (x', −y')


def test_transferred_principal_points_lie_on_opencvs_epipolar_lines():
    from photolib.nb import stereo as ns
    s = ns.pair_scene()
    o = ns.epipolar_ray_orientation(s["X01"], s["R1"], s["X02"], s["R2"], ns.C_MM, 3.0)
    # H1'' is the image of a point on the axis of image 1: on the epipolar line of H1'
    a, b, d = _opencv_epiline_in_image_2(s["X01"], s["R1"], s["X02"], s["R2"], ns.C_MM, [0, 0])
    assert abs(a * o["H1_in_2"][0] + b * o["H1_in_2"][1] + d) < 1e-6      # OpenCV: float32
    # and H2'' (the origin of image 2) is on the epipolar line, in image 1, of H2' (swap roles)
    a, b, d = _opencv_epiline_in_image_2(s["X02"], s["R2"], s["X01"], s["R1"], ns.C_MM, [0, 0])
    assert abs(a * o["H2_in_1"][0] + b * o["H2_in_1"][1] + d) < 1e-6


@pytest.mark.parametrize("kappas, base", [((10.0, -5.0), (12.0, 5.0)), ((-40.0, 170.0), (-3.0, 9.0))])
def test_epipolar_ray_orientation_of_vertical_images_is_the_normal_case(kappas, base):
    # independent route: cameras turned about the vertical onto the base direction (κ = heading)
    import photolib as pl
    from photolib.nb import stereo as ns
    R1, R2 = (pl.rotation_opk(0.0, 0.0, np.radians(k)) for k in kappas)
    X01, X02 = np.array([0.0, 0.0, 100.0]), np.array([base[0], base[1], 100.0])
    o = ns.epipolar_ray_orientation(X01, R1, X02, R2, 50.0, 0.0)
    heading = pl.rotation_opk(0.0, 0.0, np.arctan2(base[1], base[0]))
    X = np.random.default_rng(2).uniform([-20, -20, -5], [20, 20, 5], (12, 3))
    for i, (X0, R) in enumerate(((X01, R1), (X02, R2))):
        np.testing.assert_allclose(pl.project(X, X0, R, 50.0) @ o["turn"][i].T,
                                   pl.project(X, X0, heading, 50.0), atol=1e-10)


def test_epipolar_ray_orientation_refuses_a_ray_without_direction():
    import photolib as pl
    from photolib.nb import stereo as ns
    with pytest.raises(ValueError, match="principal point"):
        ns.epipolar_ray_orientation([0, 0, 10.0], np.eye(3), [0, 0, 20.0], np.eye(3), 50.0, 0.0)
    with pytest.raises(ValueError, match="finite"):
        ns.epipolar_ray_orientation([0, 0, 10.0], np.eye(3), [5, 0, 10.0], np.eye(3), 50.0,
                                    float("nan"))
    assert pl is not None


def test_object_orientations_agree_with_the_space_resection():
    # 4.76 composed (R_i = R·A_i) against the resection of each image on the object points
    import photolib as pl
    from photolib.nb import stereo as ns
    s = ns.pair_scene(noise_um=0.0)
    ro = pl.relative_orientation(s["xy1"], s["xy2"], ns.C_MM, bx=1.0)
    X0, R = ns.object_orientations(ro, pl.absolute_orientation(ro.model[:6], s["X"][:6]))
    for i, (xy, X0t, Rt) in enumerate(((s["xy1"], s["X01"], s["R1"]), (s["xy2"], s["X02"], s["R2"]))):
        start = np.r_[X0t + 1.0, np.array(pl.opk_from_rotation(Rt)) + 0.02]
        res = pl.space_resection(s["X"], xy, ns.C_MM, initial=start)
        np.testing.assert_allclose(X0[i], res.X0, atol=1e-7)
        np.testing.assert_allclose(R[i], pl.rotation_opk(res.omega, res.phi, res.kappa), atol=1e-9)


# -- the new exercises by independent routes ------------------------------------------------------

@pytest.mark.parametrize("sid", STUDENTS[:3])
def test_rays_reference_agrees_with_opencv(sid):
    import photolib as pl
    ex = BY_ID["st.rays"]
    p = parameters_for(ex, sid)
    f = ex.reference(p)
    R1, R2 = ch09._ray_rotations(p)
    cases = ex.cases(rng_for(sid, ex.id, "public"), p)
    Ps = []
    for X0, R in ((np.zeros(3), R1), (np.array(p.X02), R2)):
        Rc, t = pl.opencv_pose_from_exterior(X0, R)
        Ps.append(np.diag([p.c_mm, p.c_mm, 1.0]) @ np.column_stack([Rc, t]))
    for a, b in cases[:3]:                                   # the exact cases: rays meet
        H = cv2.triangulatePoints(Ps[0], Ps[1], np.array([[a[0]], [-a[1]]]),
                                  np.array([[b[0]], [-b[1]]]))
        np.testing.assert_allclose(f(a, b), (H[:3] / H[3]).ravel(), rtol=1e-6, atol=1e-6)
    with pytest.raises(ValueError, match="parallel"):
        f(*cases[-1])


@pytest.mark.parametrize("sid", STUDENTS[:3])
def test_ro_step_reference_is_photolibs_first_iteration(sid):
    import photolib as pl
    ex = BY_ID["st.ro-step"]
    p = parameters_for(ex, sid)
    f = ex.reference(p)
    cases = ex.cases(rng_for(sid, ex.id, "public"), p)
    for a, b, q0 in cases[:-1]:
        ro = pl.relative_orientation(a, b, p.c_mm, bx=p.bx, initial=q0, max_iter=1, check=False)
        np.testing.assert_allclose(f(a, b, q0), ro.params, rtol=1e-9, atol=1e-12)
        # iterating the step converges to photolib's adjustment
        q = np.array(q0)
        for _ in range(12):
            q = f(a, b, q)
        np.testing.assert_allclose(q, pl.relative_orientation(a, b, p.c_mm, bx=p.bx).params,
                                   atol=1e-9)
    with pytest.raises(ValueError, match="at least 5"):
        f(*cases[-1])


def test_moto_references_by_the_ground_truth():
    # the measured disparity of every variant lies within 2σ_d of the structured-light truth,
    # and the depth is Middlebury's Z = f·B/(d + doffs) (as a distance)
    pts, d, d_true, sigma_d = ch09.moto_samples()
    assert len(pts) >= 100 and 0.05 < sigma_d < 0.5
    assert np.all(np.abs(d - d_true) < 2 * sigma_d)
    for sid in STUDENTS[:4]:
        p = parameters_for(BY_ID["st.moto-depth"], sid)
        Z = ch09._moto_depth(p)
        assert Z == pytest.approx(-p.f_px * p.B_mm / (p.d_px + p.doffs_px), rel=1e-12)
        s = parameters_for(BY_ID["st.moto-sigma"], sid)
        # σ_Z by a numerical derivative of Z(d)
        h = 1e-4
        dZ = (ch09._moto_depth({**p, "d_px": p.d_px + h}) - ch09._moto_depth({**p, "d_px": p.d_px - h})) / (2 * h)
        assert ch09._moto_sigma(s) == pytest.approx(abs(dZ) * s.sigma_d_px, rel=1e-4)


def test_moto_tolerance_is_three_sigma_d():
    ex = BY_ID["st.moto"]
    p = parameters_for(ex, STUDENTS[0])
    assert ex.tolerance(p)[1] == pytest.approx(3 * ch09.moto_samples()[3], abs=0.006)
    d = ch09._moto_disparity(p)
    assert _judge(ex, STUDENTS[0], d + 0.9 * ex.tolerance(p)[1]).status == "correct"


@pytest.mark.parametrize("sid", STUDENTS[:3])
def test_iro_reference_by_the_projection(sid):
    # independent route: the pair is projected from known cameras; the orientation found must
    # reproject: x'2 of each point from the model matches the printed one (coplanarity exact
    # up to the 0.1 µm rounding of the print)
    import photolib as pl
    p = parameters_for(BY_ID["st.iro-model"], sid)
    q = parameters_for(BY_ID["st.iro"], sid)
    ang = ch09._iro(q)
    np.testing.assert_allclose(ang, [p[f"{n}_deg"] for n in ch09._IRO], atol=5e-7)
    R1, R2 = pl.rotation_opk(0.0, *np.radians(ang[:2])), pl.rotation_opk(*np.radians(ang[2:]))
    E = pl.essential_matrix(np.zeros(3), R1, [1.0, 0, 0], R2)
    for a, b in zip(q.xy1, q.xy2):
        r = np.array([*a, -q.c_mm]) @ E @ np.array([*b, -q.c_mm])
        assert abs(r) < 1e-3 * q.c_mm                      # mm², the print's rounding
    P = ch09._iro_model(p)
    for xy, X0, R in ((p.P1, np.zeros(3), R1), (p.P2, np.array([1.0, 0, 0]), R2)):
        np.testing.assert_allclose(pl.project(P, X0, R, p.c_mm), xy, atol=1e-3)
