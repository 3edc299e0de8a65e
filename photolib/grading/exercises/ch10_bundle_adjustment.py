"""Chapter 10-bundle-adjustment: graded exercises on the bundle adjustment of a block.

* ``bun.redundancy`` (number): redundancy of a block, with control points or as a free
  network, with or without self-calibration;
* ``bun.sigma0`` (number): σ0 from the residuals of a small adjustment;
* ``bun.redundancy-sum`` (choice): what the redundancy numbers of a free network sum to;
* ``bun.critical-t`` (number): the two-sided critical value of Student's t (Luhmann p. 90,
  ``luhmann:p90-t-distribution``: the tail probability *rises* as the degrees of freedom fall);
* ``bun.normal-contribution`` (function): one observation's contribution aᵀ·p·a to N.

References: :func:`photolib.derive.adjustment.block_redundancy` (counts),
:func:`photolib.bundle.critical_value` (NumPy/math, checked against SciPy in the tests).

>>> [ex.id for ex in EXERCISES]
['bun.redundancy', 'bun.sigma0', 'bun.redundancy-sum', 'bun.critical-t', 'bun.normal-contribution']
"""

from __future__ import annotations

import math

import numpy as np

from photolib.grading.judge import rounding_tolerance
from photolib.grading.spec import PRINTED, Exercise, Mistake

CHAPTER = "10-bundle-adjustment"

_INTERIOR = {0: "the interior orientation is known (fixed)",
             3: "self-calibration of c, x'0, y'0 (common to all images)",
             5: "self-calibration of c, x'0, y'0, A1, A2 (common to all images)"}


# -- 1. redundancy of a block (number) ------------------------------------------------------------
def _block_params(rng):
    images = int(rng.integers(6, 41))
    points = int(rng.integers(8, 25)) * images
    rays = int(points * rng.uniform(2.3, 3.6))
    datum = str(rng.choice(["control", "free"]))
    control = int(rng.integers(4, 13)) if datum == "control" else 0
    k = int(rng.choice([0, 3, 5]))
    text = (f"{control} control points with known, fixed X, Y, Z (they are among the points)"
            if datum == "control" else "no control points: a free network with inner constraints")
    return {"images": images, "points": points, "rays": rays, "control": control, "k": k,
            "datum": datum, "datum_text": text, "interior_text": _INTERIOR[k]}


def _redundancy(p, per_ray=2, interior=True, defect=True, control_fixed=True):
    from photolib.derive import adjustment as da
    counts = da.block_redundancy(p["images"], p["points"], p["rays"],
                                 control=p["control"] if control_fixed else 0,
                                 interior=p["k"] if interior else 0, datum=p["datum"])
    n = per_ray * p["rays"]
    return float(n - counts["u"] + (counts["d"] if defect else 0))


redundancy = Exercise(
    params_name="p_redundancy",
    id="bun.redundancy", points=2, kind="number", answer="r",
    title="Unknowns and redundancy of a block / Redundanz eines Bildverbands",
    statement="A block of {images} images and {points} object points; {rays} image points "
              "are measured (each point in two or more images). Datum: {datum_text}; "
              "{interior_text}. How large is the redundancy r = n − u + d of the bundle "
              "adjustment (n observations, u unknowns, d datum defect)?",
    parameters=_block_params, reference=_redundancy, rtol=0.0, atol=1e-9,
    mistakes=(
        Mistake("interior", "the interior orientation parameters estimated by "
                            "self-calibration are unknowns too (once for the block)",
                lambda p: _redundancy(p, interior=False) if p["k"] else None),
        Mistake("datum-defect", "a free network has a datum defect d = 7 (3 translations, "
                                "3 rotations, 1 scale): r = n − u + 7",
                lambda p: _redundancy(p, defect=False) if p["datum"] == "free" else None),
        Mistake("control", "the coordinates of fixed control points are not unknowns",
                lambda p: _redundancy(p, control_fixed=False) if p["control"] else None),
        Mistake("observations", "each image point gives two observations, x′ and y′",
                lambda p: _redundancy(p, per_ray=1)),
    ))


# -- 2. σ0 from residuals (number) ----------------------------------------------------------------
def _sigma0_params(rng):
    n = int(rng.integers(10, 17))
    u = int(rng.integers(3, 7))
    v = [round(float(x), 1) + 0.0 for x in rng.normal(0.0, rng.uniform(2.0, 6.0), n)]
    return {"n": n, "u": u, "v": v}


def _sigma0(p, divisor=None, root=True):
    v = np.array(p["v"])
    s2 = float(v @ v) / (p["n"] - p["u"] if divisor is None else divisor(p))
    return math.sqrt(s2) if root else s2


sigma0 = Exercise(
    params_name="p_sigma0",
    id="bun.sigma0", points=2, kind="number", answer="s0",
    title="σ0 from the residuals / Standardabweichung der Gewichtseinheit",
    statement="An adjustment with equal weights has n = {n} observations and u = {u} "
              "unknowns (no datum defect). Its residuals are v = {v} µm. Compute the "
              "a-posteriori standard deviation σ0 (µm).",
    # the rounding of the printed residuals (0.1 µm); the old 1e-6 rejected σ0 given to
    # 0.001 µm. The divisor mistakes stay ≥ 0.1 µm away and keep their hints.
    parameters=_sigma0_params, reference=_sigma0,
    tolerance=lambda p: _SIGMA0_TOLERANCE(p),
    mistakes=(
        Mistake("divisor", "divide vᵀv by the redundancy r = n − u, not by n",
                lambda p: _sigma0(p, divisor=lambda q: q["n"])),
        Mistake("divisor", "divide vᵀv by the redundancy r = n − u, not by n − 1",
                lambda p: _sigma0(p, divisor=lambda q: q["n"] - 1)),
        Mistake("variance", "that is σ0², the variance: take the square root",
                lambda p: _sigma0(p, root=False)),
    ))


_SIGMA0_TOLERANCE = rounding_tolerance(_sigma0, {"v": 0.05},
                                       mistakes=[m.wrong for m in sigma0.mistakes])


# -- 3. redundancy numbers sum (choice) -----------------------------------------------------------
_SUMS = ("n − u + d", "n − u", "n", "u")


def _sum_params(rng):
    rays = int(rng.integers(300, 2000))
    images = int(rng.integers(6, 30))
    points = int(rays / rng.uniform(2.4, 3.5))
    n = 2 * rays
    while True:   # four different numbers, else two options would both be right or wrong
        u = 6 * images + 3 * points
        values = {"n − u + d": n - u + 7, "n − u": n - u, "n": n, "u": u}
        if len(set(values.values())) == len(values):
            break
        points += 1
    order = [int(i) for i in rng.permutation(len(_SUMS))]
    keys = "abcd"
    text = "; ".join(f"({keys[i]}) {values[_SUMS[j]]}" for i, j in enumerate(order))
    letter = {name: keys[order.index(k)] for k, name in enumerate(_SUMS)}
    return {"n": n, "images": images, "points": points, "options": text,
            "correct": letter["n − u + d"], "forgot_d": letter["n − u"], "all_one": letter["n"],
            "unknowns": letter["u"]}


redundancy_sum = Exercise(
    params_name="p_rsum",
    id="bun.redundancy-sum",
    few_variants="a multiple choice of four options: four correct answers at most", points=1, kind="choice", answer="choice_sum",
    title="Redundancy numbers / Redundanzanteile",
    statement="A free network (no control points, inner constraints) of {images} images and "
              "{points} new points has n = {n} observations and fixed interior orientation. "
              "Its redundancy numbers r_i = (Q_vv P)_ii sum to {options}. Set the answer to "
              "the letter.",
    parameters=_sum_params, reference=lambda p: p["correct"],
    choices={"a": "first option", "b": "second option", "c": "third option",
             "d": "fourth option"},
    mistakes=(
        Mistake("datum-defect", "the sum is the redundancy r = n − u + d, and a free network "
                                "has d = 7", lambda p: p["forgot_d"]),
        Mistake("redundancy-number", "0 ≤ r_i ≤ 1 and they sum to the redundancy, not one "
                                     "per observation", lambda p: p["all_one"]),
        Mistake("unknowns", "the r_i sum to the redundancy; the unknowns are what the "
                            "other part, trace(A Q_xx Aᵀ P), sums to (u − d)",
                lambda p: p["unknowns"]),
    ))


# -- 4. critical value of t (number) --------------------------------------------------------------
def _critical_params(rng):
    return {"alpha": float(rng.choice([0.1, 0.05, 0.01, 0.001])), "dof": int(rng.integers(2, 31))}


def _critical(p, test="t", alpha=None):
    from photolib.bundle import critical_value
    return critical_value(p["alpha"] if alpha is None else alpha, test, p["dof"])


critical_t = Exercise(
    params_name="p_t",
    id="bun.critical-t", points=2, kind="number", answer="k",
    title="Critical value of the t test / Kritischer Wert (t-Verteilung)",
    statement="σ0 of a small adjustment is estimated with r = {dof} degrees of freedom. A "
              "residual is tested two-sided at significance level α = {alpha} with Student's "
              "t: give the critical value k with P(|T| > k) = α (three decimals suffice).",
    # α is one of the conventional levels 0.1, 0.05, 0.01, 0.001: exact as printed
    parameters=_critical_params, reference=_critical, tolerance=PRINTED, exact=("alpha",),
    rtol=0.0, atol=1.5e-3,
    mistakes=(
        Mistake("erratum", "that is the normal quantile: with few degrees of freedom the "
                           "probability of a large deviation rises (Luhmann p. 90 as corrected, "
                           "luhmann:p90-t-distribution), so k is larger than the normal value",
                lambda p: _critical(p, test="normal")),
        Mistake("one-sided", "the test is two-sided: P(|T| > k) = α puts α/2 in each tail",
                lambda p: _critical(p, alpha=2 * p["alpha"])),
    ))


# -- 5. one observation in the normal equations (function) ----------------------------------------
def _contribution_params(rng):
    return {"u": int(rng.integers(4, 10)), "sigma_um": round(float(rng.uniform(1.0, 5.0)), 1)}


def _contribution(weight=True, power=2, scale=1.0):
    def make(p):
        def contribution(a, sigma):
            a = np.asarray(a, float)
            w = 1.0 / (scale * np.asarray(sigma, float)) ** power if weight else 1.0
            return w * np.outer(a, a)
        return contribution
    return make


def _contribution_cases(rng, p):
    return [(np.round(rng.normal(0.0, 50.0, p["u"]), 3),
             round(float(p["sigma_um"] * 1e-3 * rng.uniform(0.5, 2.0)), 5)) for _ in range(5)]


normal_contribution = Exercise(
    params_name="p_con",
    id="bun.normal-contribution", points=3, kind="function", answer="contribution",
    # σ0 = 1 mm is the course's convention (the chapter's tests sum N = AᵀPA with p = 1/σ²
    # and recognise σ in µm as 1000·σ): the function is the same for every student
    few_variants="a function of its arguments alone (σ0 = 1 mm for all): one answer, "
                 "tested on rows drawn per student",
    title="One observation in the normal equations / Beitrag zur Normalgleichungsmatrix",
    statement="An image coordinate with standard deviation σ (mm, a priori; σ0 = 1 mm) has "
              "the row a of the design matrix A ({u} unknowns here, typically "
              "σ ≈ {sigma_um} µm). Write contribution(a, sigma) returning its contribution "
              "to N = AᵀPA, a NumPy array of shape (u, u). It is tested on rows you do not see.",
    parameters=_contribution_params, reference=_contribution(), cases=_contribution_cases,
    # rtol 1e-6 accepts float32 (the old 1e-9 did not)
    rtol=1e-6, atol=1e-6,
    mistakes=(
        Mistake("weight", "the weight p = σ0²/σ² is missing: N = Σ aᵀ·p·a",
                _contribution(weight=False)),
        Mistake("units-um", "σ is given in mm (σ0 = 1 mm): with σ in µm the weights come out "
                            "10⁶ times too small", _contribution(scale=1e3)),
        Mistake("weight", "the weight is p = σ0²/σ², with σ squared", _contribution(power=1)),
        Mistake("weight-inverted", "the weight is inverted: p = σ0²/σ² (divide by σ²), not σ²/σ0²", _contribution(power=-2)),  # noqa: E501
    ))


EXERCISES = (redundancy, sigma0, redundancy_sum, critical_t, normal_contribution)
