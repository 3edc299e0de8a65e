"""Inverting strong distortion: ``Distortion.distort`` (Newton) against ``cv2.undistortPoints``.

Both invert a distortion model that is direct in one direction: ours is direct from measured to
ideal (``correct``) and iterative from ideal to measured (``distort``); OpenCV's is direct from
ideal to measured and iterative the other way (``undistortPoints``). The two models are made
equivalent with :meth:`photolib.Distortion.from_opencv`, and each inversion is run with the
iteration budget that brings its own residual (the forward model applied to the result, compared
with the input) below the same accuracy, each with the least work that reaches it (OpenCV's iteration count, our step
tolerance, both searched below). Target (issue 2): ours at least 1.5× faster at equal
accuracy. Run: ``.venv/bin/python -m benchmarks.bench_distortion``.
"""

from __future__ import annotations

import cv2
import numpy as np

import photolib as pl
from benchmarks._timing import best_time

C = 8.0  # mm, a wide-angle lens on a 2/3" sensor: strong distortion in the corners
HALF = (4.4, 3.3)
K_CV = np.array([-0.32, 0.12, 1e-3, -8e-4, -0.02])  # strong barrel distortion
ACCURACY_MM = 1e-7  # 0.1 nm: both inversions must reach this


def _cv_forward(ideal_mm):
    objp = np.column_stack([ideal_mm[:, 0] / C, -ideal_mm[:, 1] / C, np.ones(len(ideal_mm))])
    K = np.array([[C, 0, 0], [0, C, 0], [0, 0, 1.0]])
    p, _ = cv2.projectPoints(objp, np.zeros(3), np.zeros(3), K, K_CV)
    return p.reshape(-1, 2) * [1, -1]


def run(n: int = 100_000) -> dict:
    rng = np.random.default_rng(1)
    ideal = rng.uniform([-HALF[0], -HALF[1]], [HALF[0], HALF[1]], (n, 2))
    ours_model, fit = pl.Distortion.from_opencv(K_CV, C, *HALF)
    K = np.array([[C, 0, 0], [0, C, 0], [0, 0, 1.0]])

    # --- ours: ideal → measured by Newton; residual = |m − Δ(m) − ideal|. Like OpenCV's
    # iteration count below, the step tolerance is the loosest (in decades) whose result
    # reaches the accuracy: Newton's error after a step s is about C·s², far below s.
    def ours_residual(tol):
        m = ours_model.distort(ideal, tol=tol)
        return float(np.max(np.hypot(*(ours_model.correct(m) - ideal).T)))

    tol = 1e-2
    while (err_ours := ours_residual(tol)) > ACCURACY_MM:
        tol /= 10
    t_ours = best_time(lambda: ours_model.distort(ideal, tol=tol))

    # --- OpenCV: measured → ideal by its fixed-point iteration; residual = |forward(u) − measured|
    meas_cv = _cv_forward(ideal)
    src = (meas_cv * [1, -1]).reshape(-1, 1, 2)

    def cv_undistort(iters):
        crit = (cv2.TERM_CRITERIA_COUNT | cv2.TERM_CRITERIA_EPS, iters, 0.0)
        u = cv2.undistortPoints(src, K, K_CV, None, None, None, crit)
        return u.reshape(-1, 2) * C * [1, -1]

    iters, err_cv = 5, np.inf
    while iters <= 400:
        err_cv = float(np.max(np.hypot(*(_cv_forward(cv_undistort(iters)) - meas_cv).T)))
        if err_cv <= ACCURACY_MM:
            break
        iters += 5
    t_cv = best_time(lambda: cv_undistort(iters))
    print(f"N={n:,} points, strong distortion (|Δ| up to "
          f"{np.max(np.hypot(*(meas_cv - ideal).T)) * 1000:.0f} µm; model fit residual "
          f"{fit.max_um:.2f} µm)")
    print(f"  photolib distort (Newton, tol={tol:g} mm): {t_ours * 1e3:8.2f} ms, "
          f"max residual {err_ours:.2e} mm")
    print(f"  cv2.undistortPoints ({iters} iterations): {t_cv * 1e3:8.2f} ms, max residual {err_cv:.2e} mm")
    print(f"  speed-up at equal accuracy (≤ {ACCURACY_MM:g} mm): {t_cv / t_ours:.2f}× (target ≥ 1.5×)")
    return dict(ours=t_ours, cv2=t_cv, tol_ours=tol, iters_cv=iters, err_ours=err_ours, err_cv=err_cv)


if __name__ == "__main__":
    run()
