"""Chapter 10-bundle-adjustment: graded exercises on the bundle adjustment of a block.

* ``bun.redundancy`` (number): redundancy of a block, with control points or as a free
  network, with or without self-calibration;
* ``bun.sigma0`` (number): σ0 from the residuals of a small adjustment;
* ``bun.redundancy-sum`` (choice): what the redundancy numbers of a free network sum to;
* ``bun.critical-t`` (number): the two-sided critical value of Student's t (Luhmann p. 90,
  ``luhmann:p90-t-distribution``: the tail probability *rises* as the degrees of freedom fall);
* ``bun.normal-contribution`` (function): one observation's contribution aᵀ·p·a to N;
* ``bun.gauss-newton-step`` (function): one Gauss–Newton iteration of a tiny block from its
  design matrix, with a datum defect (free network, singular N) as the degenerate case;
* ``bun.sigma0-redundancy`` (function): σ̂0 and the redundancy numbers from A, σ and v, with
  r = n − u ≤ 0 as the degenerate case;
* scenario ``bun.count-n`` (three steps, numbers): observations n → unknowns u → redundancy r
  of a block;
* scenario ``bun.snoop-sigma0`` (three steps, numbers): σ̂0 from the residuals → Baarda's w of
  one observation → Pope's τ of it.

References: :func:`photolib.derive.adjustment.block_redundancy` (counts),
:func:`photolib.bundle.critical_value` (SciPy's distributions, checked against mpmath in the tests).

>>> [ex.id for ex in EXERCISES]
['bun.redundancy', 'bun.sigma0', 'bun.redundancy-sum', 'bun.critical-t', 'bun.normal-contribution', 'bun.gauss-newton-step', 'bun.sigma0-redundancy', 'bun.count-n', 'bun.count-u', 'bun.count-r', 'bun.snoop-sigma0', 'bun.snoop-w', 'bun.snoop-tau']
"""

from __future__ import annotations

import math

import numpy as np

from photolib.grading.judge import rounding_tolerance
from photolib.grading.spec import PRINTED, Exercise, Mistake
from photolib.grading.variants import CHOICE_KEYS, permuted_options

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
              "{interior_text}. How large is the redundancy $r = n - u + d$ of the bundle "
              "adjustment ($n$ observations, $u$ unknowns, $d$ datum defect)?",
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
    statement="An adjustment with equal weights has $n = {n}$ observations and $u = {u}$ "
              "unknowns (no datum defect). Its residuals are $v = {v}$ µm. Compute the "
              "a-posteriori standard deviation $\\hat\\sigma_0$ in µm (to 0.01 µm).",
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
    text, order = permuted_options(rng, [values[name] for name in _SUMS])
    letter = {name: CHOICE_KEYS[order.index(k)] for k, name in enumerate(_SUMS)}
    return {"n": n, "images": images, "points": points, "options": text,
            "correct": letter["n − u + d"], "forgot_d": letter["n − u"], "all_one": letter["n"],
            "unknowns": letter["u"]}


redundancy_sum = Exercise(
    params_name="p_rsum",
    id="bun.redundancy-sum",
    few_variants="a multiple choice of four options: four correct answers at most", points=1, kind="choice", answer="choice_sum",
    title="Redundancy numbers / Redundanzanteile",
    statement="A free network (no control points, inner constraints) of {images} images and "
              "{points} new points has $n = {n}$ observations and fixed interior orientation. "
              "Its redundancy numbers $r_i = (Q_{{vv}}P)_{{ii}}$ sum to {options}. Set the "
              "answer to the letter.",
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
    statement="$\\hat\\sigma_0$ of a small adjustment is estimated with $r = {dof}$ degrees "
              "of freedom. A residual is tested two-sided at significance level "
              "$\\alpha = {alpha}$ with Student's t: give the critical value $k$ with "
              "$P(|T| > k) = \\alpha$ (three decimals suffice).",
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
    statement="An image coordinate with standard deviation $\\sigma$ (mm, a priori; "
              "$\\sigma_0 = 1$ mm) has the row $a$ of the design matrix $A$ ({u} unknowns here, "
              "typically $\\sigma \\approx {sigma_um}$ µm). Write `contribution(a, sigma)` "
              "returning its contribution $a^T p\\, a$ to $N = A^TPA$, a NumPy array of shape "
              "$(u, u)$, to $10^{{-6}}$. It is tested on rows you do not see.",
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


# -- 6. one Gauss–Newton iteration of a tiny block (function) -------------------------------------
_C_TINY = 35.0  #: camera constant of the tiny blocks, mm


def tiny_block(rng, points=8, control=3, images=3, noise=True):
    """A tiny block linearised at its approximate values: ``(x, A, l, sigma)``.

    ``images`` near-nadir images (c = 35 mm) 18–22 m above ``points`` points in a
    10 m × 10 m × 3 m box, every point in every image; the first ``control`` points are fixed
    control points (0: a free network, datum defect 7). ``x`` (u,) holds the approximate
    ``X0, Y0, Z0`` (m), ``ω, φ, κ`` (rad) of each image, then ``X, Y, Z`` (m) of each new point;
    ``A`` (n, u) is the design matrix ∂(x′, y′)/∂x at x from :func:`photolib.collinearity_jacobian`
    (rows x′, y′ per image point, image by image), ``l`` (n,) observed − computed (mm) and
    ``sigma`` (n,) the a-priori standard deviations (mm) with which the observations were
    simulated (2, 3 or 5 µm per image point; no noise with ``noise=False``).

    >>> x, A, l, sigma = tiny_block(np.random.default_rng(0))
    >>> x.shape, A.shape, l.shape, sigma.shape
    ((33,), (48, 33), (48,), (48,))
    """
    import photolib as pl
    X = np.column_stack([rng.uniform(-5, 5, points), rng.uniform(-5, 5, points),
                         rng.uniform(-1.5, 1.5, points)])
    ext = np.column_stack([rng.uniform(-3, 3, images), rng.uniform(-3, 3, images),
                           rng.uniform(18, 22, images), rng.normal(0, 0.03, (images, 3))])
    sigma = np.repeat(rng.choice([0.002, 0.003, 0.005], points * images), 2)
    new = np.arange(points) >= control
    ext0 = ext + rng.normal(0, 1, ext.shape) * np.r_[0.3, 0.3, 0.3, 0.01, 0.01, 0.01]
    X0 = X.copy()
    X0[new] += rng.normal(0, 0.2, (int(new.sum()), 3))
    u = 6 * images + 3 * int(new.sum())
    slot = np.cumsum(new) - 1
    A = np.zeros((2 * points * images, u))
    ell = np.zeros(2 * points * images)
    for j, e in enumerate(ext0):
        R = pl.rotation_opk(*e[3:])
        J = pl.collinearity_jacobian(X0, e[:3], R, _C_TINY, angles=tuple(e[3:]))
        rows = slice(2 * points * j, 2 * points * (j + 1))
        A[rows, 6 * j:6 * j + 6] = J[:, :, :6].reshape(-1, 6)
        for i in np.flatnonzero(new):
            cols = slice(6 * images + 3 * slot[i], 6 * images + 3 * slot[i] + 3)
            A[2 * points * j + 2 * i:2 * points * j + 2 * i + 2, cols] = J[i, :, 6:]
        observed = pl.project(X, ext[j, :3], pl.rotation_opk(*ext[j, 3:]), _C_TINY)
        ell[rows] = (observed - pl.project(X0, e[:3], R, _C_TINY)).ravel()
    if noise:
        ell += rng.normal(0.0, 1.0, ell.shape) * sigma
    return np.r_[ext0.ravel(), X0[new].ravel()], A, ell, sigma


def _weights(sigma, weight):
    return {"inverse": 1.0 / sigma**2, "squared": sigma**2, "none": np.ones_like(sigma)}[weight]


def _step(update=True, weight="inverse", sign=1.0):
    def make(p):
        def gauss_newton_step(x, A, l, sigma):  # noqa: E741 - l as in the statement
            x, A, ell, sigma = (np.asarray(v, float) for v in (x, A, l, sigma))
            w = _weights(sigma, weight)
            u = A.shape[1]
            rank = int(np.linalg.matrix_rank(A * np.sqrt(w)[:, None]))
            if rank < u:
                raise ValueError(f"singular normal matrix: rank {rank} < u = {u} unknowns "
                                 f"(datum defect {u - rank})")
            N = A.T @ (w[:, None] * A)
            dx = np.linalg.solve(N, A.T @ (w * ell))
            return x + sign * dx if update else dx
        return gauss_newton_step
    return make


def _step_params(rng):
    return {"points": int(rng.integers(7, 13)), "images": int(rng.integers(3, 5)), "control": 3}


def _step_cases(rng, p):
    n = p["points"]
    return [tiny_block(rng, n, p["control"], p["images"], noise=False),   # clean
            tiny_block(rng, n, p["control"], p["images"]),                # noisy
            tiny_block(rng, n + 2, p["control"] + 1, p["images"]),        # noisy, larger
            tiny_block(rng, n, 0, p["images"])]                           # free network


gauss_newton_step = Exercise(
    params_name="p_step",
    id="bun.gauss-newton-step", points=4, kind="function", answer="gauss_newton_step",
    few_variants="a function of its arguments alone: one answer, tested on blocks drawn "
                 "per student",
    title="One Gauss–Newton iteration of a block / Eine Iteration der Bündelausgleichung",
    statement=r"A tiny block: {images} images, {points} points, {control} of them fixed "
              r"control points. Write `gauss_newton_step(x, A, l, sigma)`: `x` $(u,)$ the "
              r"current approximate unknowns (per image $X_0, Y_0, Z_0$ in m and "
              r"$\omega, \varphi, \kappa$ in rad, then $X, Y, Z$ in m per new point), `A` "
              r"$(n, u)$ the design matrix at `x`, `l` $(n,)$ observed − computed image "
              r"coordinates (mm), `sigma` $(n,)$ their a-priori standard deviations (mm, "
              r"$\sigma_0 = 1$). Return the **updated unknowns** "
              r"$\hat x = x + (A^TPA)^{{-1}}A^TPl$ with $P = \mathrm{{diag}}(1/\sigma_i^2)$, to "
              r"0.2 mm and 0.2 mrad (float32 work suffices). If the normal matrix is singular (a datum defect: "
              r"`np.linalg.matrix_rank` of $P^{{1/2}}A$ or of $N$ below $u$), raise `ValueError` "
              r"naming the rank. It is tested on blocks you do not see, one of them a free "
              r"network.",
    # float32 work on these blocks moves x̂ by up to 3e-5 (m, rad); the nearest mistake
    # (unweighted) stays more than 0.01 away
    parameters=_step_params, reference=_step(), cases=_step_cases,
    rtol=1e-6, atol=2e-4,
    mistakes=(
        Mistake("no-update", "that is the correction dx; the iteration returns the updated "
                             "unknowns x + dx", _step(update=False)),
        Mistake("weight-inverted", "the weight is p = σ0²/σ² = 1/σ², not σ²: precise "
                                   "observations weigh more", _step(weight="squared")),
        Mistake("weight", "the observations have different σ: weight them with "
                          "P = diag(1/σ²)", _step(weight="none")),
        Mistake("sign", "l is observed − computed, so the correction is added: "
                        "x + (AᵀPA)⁻¹AᵀPl", _step(sign=-1.0)),
    ))


# -- 7. σ0 and the redundancy numbers (function) --------------------------------------------------
def _sigma0_rn(divisor="r", weight="inverse", matrix="qvv-p"):
    def make(p):
        def sigma0_redundancy(A, sigma, v):
            A, sigma, v = (np.asarray(a, float) for a in (A, sigma, v))
            n, u = A.shape
            if n - u <= 0:
                raise ValueError(f"redundancy r = n − u = {n} − {u} = {n - u} ≤ 0: σ0 is not "
                                 f"determined")
            w = _weights(sigma, weight)
            Q = np.linalg.inv(A.T @ (w[:, None] * A))
            h = np.einsum("ia,ab,ib->i", A, Q, A)          # diag(A Q_xx Aᵀ)
            rn = {"qvv-p": 1.0 - h * w, "hat": h * w, "qvv": 1.0 / w - h}[matrix]
            s0 = math.sqrt(float(v @ (w * v)) / {"r": n - u, "n": n}[divisor])
            return np.r_[s0, rn]
        return sigma0_redundancy
    return make


def _sigma0_rn_case(rng, points, control, images, rows=None):
    _, A, ell, sigma = tiny_block(rng, points, control, images)
    w = 1.0 / sigma**2
    if rows is not None:
        keep = np.sort(rng.choice(len(ell), rows, replace=False))
        A, ell, sigma, w = A[keep], ell[keep], sigma[keep], w[keep]
    dx = np.linalg.lstsq(A * np.sqrt(w)[:, None], ell * np.sqrt(w), rcond=None)[0]
    return A, sigma, A @ dx - ell                           # v = A·dx − l (mm)


def _sigma0_rn_cases(rng, p):
    n, m = p["points"], p["images"]
    u = 6 * m + 3 * (n - 3)
    return [_sigma0_rn_case(rng, n, 3, m), _sigma0_rn_case(rng, n + 1, 4, m),
            _sigma0_rn_case(rng, n + 2, 3, m), _sigma0_rn_case(rng, n, 3, m, rows=u)]


sigma0_redundancy = Exercise(
    params_name="p_s0rn",
    id="bun.sigma0-redundancy", points=4, kind="function", answer="sigma0_redundancy",
    few_variants="a function of its arguments alone: one answer, tested on adjustments drawn "
                 "per student",
    title="σ0 and redundancy numbers / σ0 und Redundanzanteile",
    statement=r"An adjusted tiny block ({points} points in {images} images, 3 control points; no "
              r"datum defect). Write `sigma0_redundancy(A, sigma, v)`: `A` $(n, u)$ the design "
              r"matrix, `sigma` $(n,)$ the a-priori standard deviations (mm, $\sigma_0 = 1$, "
              r"$P = \mathrm{{diag}}(1/\sigma_i^2)$), `v` $(n,)$ the residuals (mm). Return "
              r"`np.r_[s0, r]`: first $\hat\sigma_0 = \sqrt{{v^TPv/(n-u)}}$ (dimensionless, "
              r"near 1 when the $\sigma_i$ are right), then the $n$ redundancy numbers "
              r"$r_i = (Q_{{vv}}P)_{{ii}} = 1 - (A Q_{{xx}} A^T P)_{{ii}}$, "
              r"$Q_{{xx}} = (A^TPA)^{{-1}}$, to $10^{{-4}}$. If the redundancy "
              r"$r = n - u \le 0$, raise `ValueError` naming it.",
    # float32 work moves the entries by up to 5e-6; the nearest mistake stays 0.4 away
    parameters=_step_params, reference=_sigma0_rn(), cases=_sigma0_rn_cases,
    rtol=1e-6, atol=1e-4,
    mistakes=(
        Mistake("divisor", "divide vᵀPv by the redundancy r = n − u, not by n",
                _sigma0_rn(divisor="n")),
        Mistake("weight-inverted", "the weight is p = σ0²/σ² = 1/σ², not σ²",
                _sigma0_rn(weight="squared")),
        Mistake("weight", "the observations have different σ: weight them with "
                          "P = diag(1/σ²) in Q_xx, in vᵀPv and in Q_vv·P",
                _sigma0_rn(weight="none")),
        Mistake("redundancy-matrix", "that is diag(A Q_xx Aᵀ P), the share of the unknowns; "
                                     "the redundancy numbers are diag(I − A Q_xx Aᵀ P)",
                _sigma0_rn(matrix="hat")),
        Mistake("redundancy-p", "r_i = (Q_vv P)_ii: the diagonal of Q_vv = P⁻¹ − A Q_xx Aᵀ "
                                "times the weight p_i", _sigma0_rn(matrix="qvv")),
    ))


# -- 8. scenario: observations → unknowns → redundancy of a block (three numbers) ------------------
def _count_params(rng):
    p = _block_params(rng)
    p["n"] = 2 * p["rays"]
    p["u"] = 6 * p["images"] + 3 * (p["points"] - p["control"]) + p["k"]
    p["d"] = 7 if p["datum"] == "free" else 0
    return p


def _count_u(p, per_image=6, control_fixed=True, interior=True):
    return float(per_image * p["images"] + 3 * (p["points"] - (p["control"] if control_fixed
                                                              else 0)) + (p["k"] if interior
                                                                          else 0))


_COUNT_TEXT = ("A block of {images} images and {points} object points; {rays} image points "
               "are measured (each point in two or more images). Datum: {datum_text}; "
               "{interior_text}. ")

count_n = Exercise(
    params_name="p_cn", scenario="bun.count-n",
    id="bun.count-n", points=1, kind="number", answer="n_obs",
    title="Step 1 of 3: observations of a block / Beobachtungen",
    statement=_COUNT_TEXT + "How many observations $n$ does the bundle adjustment have?",
    parameters=_count_params, reference=lambda p: float(p["n"]), rtol=0.0, atol=1e-9,
    mistakes=(
        Mistake("observations", "each image point gives two observations, x′ and y′",
                lambda p: float(p["rays"])),
        Mistake("points", "the observations are the measured image points (x′, y′ each), "
                          "not the object points", lambda p: float(2 * p["points"])),
    ))

count_u = Exercise(
    params_name="p_cu", scenario="bun.count-n",
    id="bun.count-u", points=1, kind="number", answer="u_unknowns",
    title="Step 2 of 3: unknowns of the block / Unbekannte",
    statement=_COUNT_TEXT + "How many unknowns $u$ does the bundle adjustment have?",
    parameters=_count_params, reference=_count_u, rtol=0.0, atol=1e-9,
    mistakes=(
        Mistake("control", "the coordinates of fixed control points are not unknowns",
                lambda p: _count_u(p, control_fixed=False) if p["control"] else None),
        Mistake("interior", "the interior orientation parameters estimated by "
                            "self-calibration are unknowns too (once for the block)",
                lambda p: _count_u(p, interior=False) if p["k"] else None),
        Mistake("exterior", "each image has six exterior orientation unknowns: "
                            "X0, Y0, Z0, ω, φ, κ", lambda p: _count_u(p, per_image=3)),
    ))

count_r = Exercise(
    params_name="p_cr", scenario="bun.count-n",
    id="bun.count-r", points=1, kind="number", answer="r_block",
    title="Step 3 of 3: redundancy of the block / Redundanz",
    statement=_COUNT_TEXT + "With $n = {n}$ observations and $u = {u}$ unknowns (steps 1 "
              "and 2), how large is the redundancy $r = n - u + d$ ($d$ the datum defect)?",
    parameters=_count_params, reference=lambda p: float(p["n"] - p["u"] + p["d"]),
    rtol=0.0, atol=1e-9,
    mistakes=(
        Mistake("datum-defect", "a free network has a datum defect d = 7 (3 translations, "
                                "3 rotations, 1 scale): r = n − u + 7",
                lambda p: float(p["n"] - p["u"]) if p["d"] else None),
        Mistake("datum-defect", "with control points fixing the datum there is no datum "
                                "defect: d = 0", lambda p: float(p["n"] - p["u"] + 7)
                if not p["d"] else None),
        Mistake("order", "the redundancy is observations minus unknowns, r = n − u + d",
                lambda p: float(p["u"] - p["n"] + p["d"])),
    ))


# -- 9. scenario: residuals → σ0 → w and τ of one observation (three numbers) ---------------------
def _snoop_params(rng):
    n = int(rng.integers(12, 19))
    u = int(rng.integers(3, 7))
    spread = float(rng.uniform(2.0, 5.0))          # the residuals' actual spread, µm
    v = [round(float(x), 1) + 0.0 for x in rng.normal(0.0, spread, n)]
    k = int(rng.integers(0, n))
    v[k] = round(float(rng.choice([-1, 1]) * rng.uniform(2.5, 5.0) * spread), 1) + 0.0
    vv = np.array(v)
    s0 = round(math.sqrt(float(vv @ vv) / (n - u)), 3)
    while True:
        # the a-priori σ differs from σ̂0 by 25 % or more, and v_k over σ or σ̂0 times 1,
        # √q or q (the answers of both steps and their mistakes) stay 10 % apart
        q = round(float(rng.uniform(0.35, 0.75)), 3)
        sigma = round(s0 * float(rng.choice([-1, 1]) * rng.uniform(0.25, 0.45) + 1.0), 1)
        d = sorted(s * f for s in (sigma, s0) for f in (1.0, math.sqrt(q), q))
        if min(y / x for x, y in zip(d, d[1:])) > 1.1:
            break
    return {"n": n, "u": u, "v": v, "k": k + 1, "vk": v[k], "sigma": sigma, "q": q,
            "s0": s0}


def _snoop_s0(p, divisor=None, root=True):
    v = np.array(p["v"])
    s2 = float(v @ v) / (p["n"] - p["u"] if divisor is None else divisor)
    return math.sqrt(s2) if root else s2


def _snoop_stat(p, scale, root=True, use_q=True):
    q = (math.sqrt(p["q"]) if root else p["q"]) if use_q else 1.0
    return p["vk"] / (scale * q)


_SNOOP_TEXT = (r"An adjustment with equal weights has $n = {n}$ observations and $u = {u}$ "
               r"unknowns (no datum defect); its residuals are $v = {v}$ µm. ")

snoop_sigma0 = Exercise(
    params_name="p_s1", scenario="bun.snoop-sigma0",
    id="bun.snoop-sigma0", points=1, kind="number", answer="s0_snoop",
    title="Step 1 of 3: σ0 from the residuals / σ0 aus den Verbesserungen",
    statement=_SNOOP_TEXT + r"Compute $\hat\sigma_0 = \sqrt{{v^Tv/r}}$ in µm (to 0.01 µm).",
    parameters=_snoop_params, reference=_snoop_s0, tolerance=PRINTED,
    mistakes=(
        Mistake("divisor", "divide vᵀv by the redundancy r = n − u, not by n",
                lambda p: _snoop_s0(p, divisor=p["n"])),
        Mistake("divisor", "divide vᵀv by the redundancy r = n − u, not by n − 1",
                lambda p: _snoop_s0(p, divisor=p["n"] - 1)),
        Mistake("variance", "that is σ0², the variance: take the square root",
                lambda p: _snoop_s0(p, root=False)),
    ))

snoop_w = Exercise(
    params_name="p_s2", scenario="bun.snoop-sigma0",
    id="bun.snoop-w", points=1, kind="number", answer="w_k",
    title="Step 2 of 3: Baarda's w test of one observation / w-Test",
    statement=_SNOOP_TEXT + r"The a-priori standard deviation of an observation is "
              r"$\sigma = {sigma:.1f}$ µm, and observation {k} has the residual $v_{{k}} = {vk:.1f}$ µm "
              r"and $q_{{vv,kk}} = {q:.3f}$. Compute Baarda's test statistic "
              r"$w_k = v_k/(\sigma\sqrt{{q_{{vv,kk}}}})$ (to 0.01).",
    parameters=_snoop_params, reference=lambda p: _snoop_stat(p, p["sigma"]),
    tolerance=PRINTED, exact=("s0",),
    mistakes=(
        Mistake("sqrt-qvv", "divide by σ·√q_vv, the standard deviation of the residual, "
                            "not by σ·q_vv", lambda p: _snoop_stat(p, p["sigma"], root=False)),
        Mistake("qvv", "the residual's standard deviation is σ·√q_vv, not σ: v_k/σ "
                       "ignores how well the observation is controlled",
                lambda p: _snoop_stat(p, p["sigma"], use_q=False)),
        Mistake("sigma-posteriori", "Baarda's w uses the a-priori σ; with σ̂0 it is Pope's τ "
                                    "(step 3)", lambda p: _snoop_stat(p, p["s0"])),
    ))

snoop_tau = Exercise(
    params_name="p_s3", scenario="bun.snoop-sigma0",
    id="bun.snoop-tau", points=1, kind="number", answer="tau_k",
    title="Step 3 of 3: Pope's τ test of the observation / τ-Test",
    statement=_SNOOP_TEXT + r"Observation {k} has $v_{{k}} = {vk:.1f}$ µm and "
              r"$q_{{vv,kk}} = {q:.3f}$; the a-posteriori $\hat\sigma_0 = {s0:.3f}$ µm (step 1). "
              r"Compute Pope's test statistic $\tau_k = v_k/(\hat\sigma_0\sqrt{{q_{{vv,kk}}}})$ "
              r"(to 0.01).",
    parameters=_snoop_params, reference=lambda p: _snoop_stat(p, p["s0"]),
    tolerance=PRINTED, exact=("sigma",),
    mistakes=(
        Mistake("sigma-priori", "Pope's τ uses the a-posteriori σ̂0 of step 1; with the "
                                "a-priori σ it is Baarda's w (step 2)",
                lambda p: _snoop_stat(p, p["sigma"])),
        Mistake("sqrt-qvv", "divide by σ̂0·√q_vv, not by σ̂0·q_vv",
                lambda p: _snoop_stat(p, p["s0"], root=False)),
        Mistake("qvv", "the residual's standard deviation is σ̂0·√q_vv, not σ̂0",
                lambda p: _snoop_stat(p, p["s0"], use_q=False)),
    ))


EXERCISES = (redundancy, sigma0, redundancy_sum, critical_t, normal_contribution,
             gauss_newton_step, sigma0_redundancy, count_n, count_u, count_r,
             snoop_sigma0, snoop_w, snoop_tau)
