"""Chapter 08 pictures and widgets: space resection (räumlicher Rückwärtsschnitt) and the DLT.

A camera (c = 20 mm, 36 mm × 24 mm format) looks down from 30 m onto a control field
(Passpunktfeld) of 20 points spread over 20 m × 20 m with heights between 0 and ``depth``.
:func:`resection_report` orients the image by :func:`photolib.space_resection` from noisy
image points; :func:`dlt_report` estimates and decomposes the DLT with
:func:`photolib.dlt_estimate` / :func:`photolib.dlt_decompose` and shows what a flat
(coplanar) field does to it.
"""

from __future__ import annotations

import functools

import numpy as np

import photolib as pl
from photolib.nb.draw import format_corners, frustum_segments, lines_xyz, setup_axes3d
from photolib.nb.live import Explorer, LiveFigure, finished, slider
from photolib.transforms._base import ConvergenceError

__all__ = [
    "C_MM",
    "DEPTHS",
    "HALF",
    "TRUE_ANGLES_DEG",
    "TRUE_X0",
    "DLTExplorer",
    "ResectionExplorer",
    "control_points",
    "dlt_depth_curve",
    "dlt_report",
    "observations",
    "plot_convergence",
    "plot_dlt_depth",
    "plot_residuals",
    "plot_scene",
    "resection_history",
    "resection_report",
    "true_camera",
]

#: half format, mm
HALF = (18.0, 12.0)
#: camera constant of the chapter's camera, mm
C_MM = 20.0
#: true projection centre, m, and angles ω, φ, κ in degrees
TRUE_X0 = (3.0, -4.0, 30.0)
TRUE_ANGLES_DEG = (4.0, -3.0, 20.0)
#: approximate values of the explorers' resection: truth + (1, −1, 2) m and (2°, −2°, 5°)
START_OFFSET = (1.0, -1.0, 2.0, 2.0, -2.0, 5.0)
_LIMITS = ((-12.0, 12.0), (-12.0, 12.0), (0.0, 34.0))
_N_MAX = 20
#: the depths (m) of the explorer's error curve
DEPTHS = np.linspace(0.0, 10.0, 21)


def true_camera():
    """``(X0, R)`` of the chapter's camera.

    >>> X0, R = true_camera()
    >>> X0.tolist(), bool(np.allclose(R.T @ R, np.eye(3)))
    ([3.0, -4.0, 30.0], True)
    """
    return np.array(TRUE_X0), pl.rotation_opk(*np.radians(TRUE_ANGLES_DEG))


def control_points(n: int = _N_MAX, depth: float = 5.0, seed: int = 8) -> np.ndarray:
    """``n`` control points (N, 3) in m: X, Y in [−10, 10], Z = depth·u with u in [0, 1].

    The same ``seed`` gives the same plan positions for every ``depth``, so ``depth = 0``
    is the same field made flat (coplanar).

    >>> P = control_points(6, depth=0.0)
    >>> P.shape, float(np.ptp(P[:, 2]))
    ((6, 3), 0.0)
    """
    rng = np.random.default_rng(seed)
    XY = rng.uniform(-10.0, 10.0, (_N_MAX, 2))
    u = rng.uniform(0.0, 1.0, _N_MAX)
    return np.column_stack([XY, depth * u])[: int(n)]


def observations(X, noise_um: float = 0.0, seed: int = 1, c: float = C_MM) -> np.ndarray:
    """Image points (N, 2) in mm of ``X`` in the true camera, plus Gaussian noise (µm).

    The noise is ``noise_um·1e-3·z`` with a fixed standard-normal ``z`` per point, so
    moving a slider scales the same errors.

    >>> observations(control_points(3), 0.0).round(3).tolist()[0]
    [-2.532, 10.804]
    """
    X = np.asarray(X, dtype=float)
    X0, R = true_camera()
    z = np.random.default_rng(seed).standard_normal((_N_MAX, 2))[: len(X)]
    return pl.project(X, X0, R, c) + noise_um * 1e-3 * z


def _start() -> np.ndarray:
    return np.r_[TRUE_X0, np.radians(TRUE_ANGLES_DEG)] + np.r_[START_OFFSET[:3],
                                                                 np.radians(START_OFFSET[3:])]


def resection_report(noise_um: float = 5.0, n_points: int = 12, depth: float = 5.0) -> dict:
    """Space resection of the chapter's image from ``n_points`` noisy control points.

    Parameters
    ----------
    noise_um : float
        Standard deviation of the image-point noise, µm.
    n_points : int
        Number of control points, 3 … 20.
    depth : float
        Height range of the control field, m.

    Returns
    -------
    dict
        ``result`` (:class:`photolib.resection.ResectionResult` or None), ``xy`` (N, 2) mm,
        ``residuals`` (N, 2) mm, ``sigma0_um``, ``std`` (σX0, σY0, σZ0 in mm; σω, σφ, σκ
        in mdeg), ``error_mm`` (distance of X0 from the truth), ``html``.

    Examples
    --------
    >>> rep = resection_report(0.0, 8)
    >>> rep["error_mm"] < 1e-6, rep["result"].redundancy
    (True, 10)
    """
    n = int(round(n_points))
    X = control_points(n, depth)
    xy = observations(X, noise_um)
    try:
        res = pl.space_resection(X, xy, C_MM, initial=_start())
    except (ConvergenceError, ValueError) as exc:
        html = f"<p style='color:#b00'>space resection failed: {str(exc).split(':')[0]}</p>"
        return {"result": None, "xy": xy, "residuals": np.zeros_like(xy), "sigma0_um": np.nan,
                "std": np.full(6, np.nan), "error_mm": np.nan, "html": html}
    std = res.std * np.r_[1e3, 1e3, 1e3, np.degrees(1.0) * 1e3 * np.ones(3)]
    error = float(np.linalg.norm(res.X0 - np.array(TRUE_X0)) * 1e3)
    s0 = res.sigma0 * 1e3
    if res.redundancy == 0:
        s0_text = "undetermined (no redundancy: 3 points, 6 unknowns, r = 0)"
    else:
        s0_text = f"<b>{s0:.2f} µm</b> (noise put in: {noise_um:.0f} µm)"
    rows = "".join(f"<tr><td>σ<sub>{name}</sub></td><td style='text-align:right'>"
                   f"{value:.2f}</td><td>{unit}</td></tr>"
                   for name, value, unit in zip(("X0", "Y0", "Z0", "ω", "φ", "κ"), std,
                                                ("mm", "mm", "mm", "m°", "m°", "m°")))
    html = (f"<p>n = {n} points: 2n = {2 * n} observations, 6 unknowns, "
            f"redundancy r = {res.redundancy}<br>iterations: {res.iterations}<br>"
            f"σ0 = {s0_text}<br>|X0 − X0<sub>true</sub>| = {error:.1f} mm</p>"
            f"<table style='font-family:monospace'>{rows}</table>")
    return {"result": res, "xy": xy, "residuals": res.residuals, "sigma0_um": s0, "std": std,
            "error_mm": error, "html": html}


def _decomposition_error(d, c=C_MM):
    X0, _ = true_camera()
    return {"c": abs(d.c_x - c), "x0": float(np.hypot(d.x0, d.y0)),
            "X0": float(np.linalg.norm(d.X0 - X0))}


def dlt_report(depth: float = 5.0, noise_um: float = 5.0, n_points: int = _N_MAX) -> dict:
    """DLT of the chapter's image from a control field of height range ``depth`` (m).

    Returns
    -------
    dict
        ``X`` (N, 3); ``flatness`` (smallest / largest singular value of the centred points,
        0 for a plane); ``estimate`` and ``decomposition`` (None when the DLT fails);
        ``errors`` (|Δc| mm, |Δ(x'0, y'0)| mm, |ΔX0| m); ``error`` (the ValueError text);
        ``html``.

    Examples
    --------
    >>> dlt_report(0.0)["error"].startswith("the object points are coplanar")
    True
    >>> round(dlt_report(5.0, 0.0)["decomposition"].c_x, 9)
    20.0
    """
    n = int(round(n_points))
    X = control_points(n, depth)
    xy = observations(X, noise_um)
    sv = np.linalg.svd(X - X.mean(axis=0), compute_uv=False)
    flatness = float(sv[2] / sv[0])
    head = (f"<p>n = {n} points: 2n = {2 * n} observations, 11 unknowns, redundancy "
            f"r = {2 * n - 11}, image noise {noise_um:.0f} µm<br>flatness s<sub>3</sub>/s<sub>1</sub> of the points: "
            f"{flatness:.3f}</p>")
    try:
        est = pl.dlt_estimate(X, xy)
        d = pl.dlt_decompose(est)
    except ValueError as exc:
        msg = str(exc)
        html = head + f"<p style='color:#b00'>ValueError: {msg.split(';')[0]}</p>"
        return {"X": X, "flatness": flatness, "estimate": None, "decomposition": None,
                "errors": {"c": np.nan, "x0": np.nan, "X0": np.nan}, "error": msg, "html": html}
    err = _decomposition_error(d)
    html = head + (f"<p>σ0 = {est.sigma0 * 1e3:.2f} µm<br>"
                   f"c<sub>x</sub> = {d.c_x:.3f}, c<sub>y</sub> = {d.c_y:.3f} mm (true {C_MM:g})<br>"
                   f"x'0 = {d.x0:+.3f}, y'0 = {d.y0:+.3f} mm (true 0)<br>"
                   f"X0 = ({d.X0[0]:.2f}, {d.X0[1]:.2f}, {d.X0[2]:.2f}) m "
                   f"(true {TRUE_X0[0]:.0f}, {TRUE_X0[1]:.0f}, {TRUE_X0[2]:.0f})<br>"
                   f"|Δc| = <b>{err['c']:.3f} mm</b>, |ΔX0| = <b>{err['X0']:.3f} m</b></p>")
    return {"X": X, "flatness": flatness, "estimate": est, "decomposition": d, "errors": err,
            "error": None, "html": html}


@functools.lru_cache(maxsize=64)
def _depth_curve(depths: tuple, noise_um: float) -> dict:
    out = {"depth": np.array(depths), "c": [], "x0": [], "X0": []}
    for depth in depths:
        errors = dlt_report(depth, noise_um)["errors"]
        for key in ("c", "x0", "X0"):
            out[key].append(errors[key])
    for key in ("c", "x0", "X0"):
        out[key] = np.array(out[key])
    return out


def dlt_depth_curve(depths, noise_um: float = 5.0) -> dict:
    """Decomposition errors of the DLT over a range of field depths (NaN where it fails).

    >>> curve = dlt_depth_curve([0.0, 5.0], 5.0)
    >>> bool(np.isnan(curve["c"][0])), bool(curve["c"][1] < 1.0)
    (True, True)
    """
    key = tuple(float(v) for v in np.asarray(depths, float).ravel())
    return {k: np.array(v, copy=True) for k, v in _depth_curve(key, float(noise_um)).items()}


def resection_history(X, xy, c, initial, max_iter: int = 12):
    """The parameters after each iteration of :func:`photolib.space_resection`.

    Each row k is the result of a run with ``max_iter = k`` (row 0 is the start), so the
    rows are the library's own iterates.

    Returns
    -------
    history : ndarray, shape (K + 1, 6)
        ``(X0, Y0, Z0, ω, φ, κ)``, angles in radians.
    failure : str or None
        The first clause of the ConvergenceError of the full run (``max_iter`` iterations)
        when it fails; the history then ends at the last iterate that could be evaluated.

    Examples
    --------
    >>> X = control_points(10)
    >>> hist, failure = resection_history(X, observations(X), C_MM, _start(), 6)
    >>> failure, bool(np.allclose(hist[-1, :3], TRUE_X0))
    (None, True)
    """
    initial = np.asarray(initial, dtype=float)
    rows, converged = [initial], False
    for k in range(1, max_iter + 1):
        try:
            res = pl.space_resection(X, xy, c, initial=initial, max_iter=k, check=False)
        except ConvergenceError:
            break
        rows.append(res.params)
        if res.converged:
            converged = True
            break
    failure = None
    if not converged:
        try:
            pl.space_resection(X, xy, c, initial=initial, max_iter=max_iter)
        except ConvergenceError as exc:
            failure = str(exc).split(":")[0]
    return np.array(rows), failure


# -- static figures -------------------------------------------------------------------------------

def plot_scene(X, cameras, title="control points and cameras"):
    """3-D view: control points and cameras ``[(X0, R, colour, label), ...]``.

    Returns
    -------
    matplotlib.figure.Figure
    """
    import matplotlib.pyplot as plt

    fig = plt.figure(figsize=(4.6, 4.0))
    ax = fig.add_subplot(projection="3d")
    setup_axes3d(ax, _LIMITS, elev=18, azim=-60)
    X = np.asarray(X, float)
    ax.plot(*X.T, "^", color="#8c564b", ms=5, label="control points")
    for X0, R, colour, label in cameras:
        ax.plot(*lines_xyz(frustum_segments(X0, R, C_MM, *HALF, scale=8.0 / C_MM)),
                color=colour, lw=1.2, label=label)
    ax.legend(loc="upper left", fontsize=8)
    ax.set_title(title)
    return finished(fig)


def plot_residuals(xy, residuals, scale: float = 200.0, title="residuals / Verbesserungen"):
    """Image points and their residual vectors v (mm), drawn ``scale`` times enlarged."""
    import matplotlib.pyplot as plt

    xy, v = np.asarray(xy, float), np.asarray(residuals, float)
    fig, ax = plt.subplots(figsize=(4.8, 3.4))
    ax.plot(*format_corners(*HALF).T, color="0.5", lw=1)
    ax.plot(*xy.T, "o", color="#8c564b", ms=3)
    seg = np.stack([xy, xy + scale * v], axis=1)
    ax.plot(*lines_xyz(seg)[:2], color="#d62728", lw=1.5)
    ax.set(xlim=(-20, 20), ylim=(-14, 14), aspect="equal", xlabel="x' [mm]",
           ylabel="y' [mm]", title=f"{title} (×{scale:g})")
    return finished(fig)


def plot_convergence(histories: dict, reference, title="convergence / Konvergenz"):
    """Distance ‖q − q̂‖ of each iterate from the adjusted solution q̂ = ``reference``.

    ``q = (X0, Y0, Z0, ω, φ, κ)`` in m and radians; one line per start in ``histories``
    (label → :func:`resection_history` result), a cross where an iteration diverged.
    """
    import matplotlib.pyplot as plt

    reference = np.asarray(reference, float)
    fig, ax = plt.subplots(figsize=(5.6, 3.2))
    for label, (hist, failure) in histories.items():
        err = np.maximum(np.linalg.norm(hist - reference, axis=1), 1e-14)
        line, = ax.semilogy(np.arange(len(err)), err, "o-", ms=3, label=label)
        if failure:
            ax.semilogy(len(err) - 1, err[-1], "x", color=line.get_color(), ms=10, mew=2)
    ax.set(xlabel="iteration", ylabel="‖q − q̂‖ [m, rad]", title=title, ylim=(1e-14, 1e4))
    ax.legend(fontsize=8)
    return finished(fig)


def plot_dlt_depth(curve, title="DLT decomposition error and field depth"):
    """The errors of :func:`dlt_depth_curve` on a log scale over the depth."""
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(5.6, 3.2))
    ax.semilogy(curve["depth"], curve["c"], "o-", ms=3, label="|Δc| [mm]")
    ax.semilogy(curve["depth"], curve["x0"], "s-", ms=3, label="|Δ(x'0, y'0)| [mm]")
    ax.semilogy(curve["depth"], curve["X0"], "^-", ms=3, label="|ΔX0| [m]")
    ax.set(xlabel="height range of the control points [m]", ylabel="error", title=title)
    ax.legend(fontsize=8)
    return finished(fig)


# -- widgets --------------------------------------------------------------------------------------

class ResectionExplorer(Explorer):
    """Image noise and number of control points → σ0, standard deviations, residuals."""

    title = "space resection explorer"
    scale = 200.0

    def __init__(self, noise_um=5.0, n_points=12.0):
        self.controls = {"noise_um": slider("noise [µm]", noise_um, 0, 50, 1, fmt=".0f"),
                         "n_points": slider("points n", n_points, 3, _N_MAX, 1, fmt=".0f")}
        self.live = LiveFigure((7.2, 3.0))
        fig = self.live.figure
        ax = fig.add_subplot(1, 2, 1)
        bx = fig.add_subplot(1, 2, 2)
        fig.subplots_adjust(0.09, 0.16, 0.98, 0.9, wspace=0.35)
        ax.plot(*format_corners(*HALF).T, color="0.5", lw=1)
        ax.set(xlim=(-20, 20), ylim=(-14, 14), aspect="equal", xlabel="x' [mm]", ylabel="y' [mm]",
               title=f"residuals ×{self.scale:g}")
        (self._points,) = ax.plot([], [], "o", color="#8c564b", ms=3)
        (self._vectors,) = ax.plot([], [], color="#d62728", lw=1.5)
        labels = ("X0", "Y0", "Z0", "ω", "φ", "κ")
        self._bars = bx.bar(range(6), np.full(6, 1e-3), bottom=1e-3,
                            color=["#1f77b4"] * 3 + ["#ff7f0e"] * 3)
        bx.set(yscale="log", ylim=(1e-3, 1e4), xticks=range(6), title="σ: mm (X0), m° (angles)")
        bx.set_xticklabels(labels)
        for artist in [self._points, self._vectors, *self._bars]:
            self.live.animate(artist)
        self.report = None
        self._finish()

    def draw(self, noise_um, n_points) -> str:
        self.report = rep = resection_report(noise_um, n_points)
        self._points.set_data(*rep["xy"].T)
        seg = np.stack([rep["xy"], rep["xy"] + self.scale * rep["residuals"]], axis=1)
        self._vectors.set_data(*lines_xyz(seg)[:2])
        for bar, value in zip(self._bars, rep["std"]):
            bar.set_height(max(value, 1e-3) if np.isfinite(value) else 1e-6)
        return rep["html"]


class DLTExplorer(Explorer):
    """Height range of the control field (flat → coplanar) → DLT conditioning and errors."""

    title = "DLT geometry explorer"

    def __init__(self, depth=5.0, noise_um=5.0):
        self.controls = {"depth": slider("depth range [m]", depth, 0, 10, 0.25, fmt=".2f"),
                         "noise_um": slider("noise [µm]", noise_um, 0, 20, 1, fmt=".0f")}
        self.live = LiveFigure((7.2, 3.2))
        fig = self.live.figure
        ax3 = fig.add_subplot(1, 2, 1, projection="3d")
        ax = fig.add_subplot(1, 2, 2)
        fig.subplots_adjust(0.0, 0.15, 0.98, 0.9, wspace=0.25)
        setup_axes3d(ax3, _LIMITS, elev=12, azim=-60)
        X0, R = true_camera()
        ax3.plot(*lines_xyz(frustum_segments(X0, R, C_MM, *HALF, scale=8.0 / C_MM)),
                 color="0.6", lw=1)
        (self._points,) = ax3.plot([], [], [], "^", color="#8c564b", ms=4)
        (self._camera,) = ax3.plot([], [], [], color="#9467bd", lw=1.5)
        ax.set(yscale="log", xlim=(0, 10), ylim=(1e-6, 1e3), xlabel="depth range [m]",
               ylabel="|Δc| [mm], |ΔX0| [m]", title="decomposition error")
        (self._curve_c,) = ax.plot([], [], "-", color="#1f77b4", label="|Δc|")
        (self._curve_X0,) = ax.plot([], [], "-", color="#2ca02c", label="|ΔX0|")
        (self._marker,) = ax.plot([], [], "o", color="#d62728", ms=6)
        ax.legend(fontsize=7, loc="upper right")
        for artist in (self._points, self._camera, self._curve_c, self._curve_X0, self._marker):
            self.live.animate(artist)
        self._curves: dict = {}
        self.report = None
        self._finish()

    def curve(self, noise_um) -> dict:
        """The error curve over depth for this noise (cached per noise value)."""
        key = round(float(noise_um), 6)
        if key not in self._curves:
            self._curves[key] = dlt_depth_curve(DEPTHS, noise_um)
        return self._curves[key]

    def draw(self, depth, noise_um) -> str:
        self.report = rep = dlt_report(depth, noise_um)
        curve = self.curve(noise_um)
        self._curve_c.set_data(curve["depth"], np.maximum(curve["c"], 1e-6))
        self._curve_X0.set_data(curve["depth"], np.maximum(curve["X0"], 1e-6))
        self._points.set_data_3d(*rep["X"].T)
        d = rep["decomposition"]
        if d is None or rep["errors"]["X0"] > 20.0:  # no camera, or far outside the view
            self._camera.set_data_3d([], [], [])
        else:
            seg = frustum_segments(d.X0, d.R, C_MM, *HALF, scale=8.0 / C_MM)
            self._camera.set_data_3d(*lines_xyz(seg))
        if d is None:
            self._marker.set_data([depth], [1e3])
        else:
            self._marker.set_data([depth], [max(rep["errors"]["c"], 1e-6)])
        return rep["html"]
