"""Chapter 05 pictures and widgets: distortion / Verzeichnung and its iterative inversion.

Course model (:class:`photolib.Distortion`): ``Δ = distorted − ideal`` at the *measured*
point, so correcting is direct and distorting (ideal → measured) is an iteration. The
widget parameters use scaled units so that the sliders move in round numbers:
A1 in 10⁻⁵ mm⁻², A2 in 10⁻⁸ mm⁻⁴, B1, B2 in 10⁻⁵ mm⁻¹, C1, C2 in 10⁻⁴.
"""

from __future__ import annotations

import numpy as np

import photolib as pl
from photolib.nb.draw import format_corners, grid_lines
from photolib.nb.live import Explorer, LiveFigure, finished, slider

__all__ = [
    "SCALE",
    "DistortionExplorer",
    "IterationExplorer",
    "distortion_from_sliders",
    "distortion_report",
    "contraction_factor",
    "iteration_report",
    "plot_convergence",
    "plot_distorted_grid",
    "plot_distortion_field",
    "plot_radial_profiles",
]

#: factor from slider units to mm-based units, per parameter
SCALE = {"A1": 1e-5, "A2": 1e-8, "A3": 1e-11, "r0": 1.0, "B1": 1e-5, "B2": 1e-5,
         "C1": 1e-4, "C2": 1e-4}
#: half format of the course camera (36 mm × 24 mm), mm
HALF = (18.0, 12.0)


def distortion_from_sliders(**values) -> pl.Distortion:
    """A :class:`photolib.Distortion` from slider values in the scaled units of :data:`SCALE`.

    >>> distortion_from_sliders(A1=-2.0).params["A1"]
    -2e-05
    """
    return pl.Distortion(**{k: v * SCALE[k] for k, v in values.items()})


def _distorted_lines(d, lines, exaggeration):
    """Measured positions of the ideal grid lines, displacements exaggerated."""
    flat = np.concatenate(lines)
    measured = d.distort(flat)
    shown = flat + exaggeration * (measured - flat)
    return np.split(shown, np.cumsum([len(line) for line in lines])[:-1])


def distortion_report(A1=0.0, A2=0.0, r0=0.0, B1=0.0, B2=0.0, C1=0.0, C2=0.0,
                      exaggeration=10.0, half=HALF, n=9) -> dict:
    """Where the straight lines of a grid are imaged, and the radial distortion curve.

    Parameters
    ----------
    A1, A2, r0, B1, B2, C1, C2 : float
        Slider units (:data:`SCALE`); r0 in mm.
    exaggeration : float
        Displacements are drawn this many times larger.
    half : tuple of float
        Half width and height of the format, mm.

    Returns
    -------
    dict
        ``distortion``; ``lines`` (list of (k, 2) arrays, or None if the model is not
        invertible over the format); ``r`` and ``dr`` (radial curve Δr'(r), µm);
        ``max_um`` (largest |Δ| at the measured grid points, µm); ``html``.

    Examples
    --------
    >>> rep = distortion_report(A1=-2.0)
    >>> round(rep["max_um"], 1)    # less than |A1|·r³ = 2e-5·21.633³ mm = 202.5 µm at the ideal corner:
    197.0
    >>> # Δ is evaluated at the measured corner, which barrel distortion moves inwards
    """
    d = distortion_from_sliders(A1=A1, A2=A2, r0=r0, B1=B1, B2=B2, C1=C1, C2=C2)
    ideal = grid_lines(*half, n=n)
    r = np.linspace(0.0, float(np.hypot(*half)), 60)
    dr = d.radial_profile(r) * 1000.0
    try:
        lines = _distorted_lines(d, ideal, exaggeration)
        measured = d.distort(np.concatenate(ideal))
        max_um = float(np.max(np.hypot(*d.delta(measured).T))) * 1000.0
        status = f"max |Δ| over the format: <b>{max_um:.1f} µm</b>"
    except pl.DistortionDivergenceError as exc:
        lines, max_um = None, float("nan")
        status = ("<span style='color:#b00'>not invertible over the format: "
                  f"{type(exc).__name__}</span>")
    params = ", ".join(f"{k} = {v:.3g}" for k, v in d.params.items() if v)
    html = (f"<p>{params or 'no distortion'}</p><p>{status}<br>"
            f"grid drawn with displacements × {exaggeration:g}</p>")
    return {"distortion": d, "lines": lines, "r": r, "dr": dr, "max_um": max_um, "html": html}


#: widget status texts of one inversion run
CONVERGED = "converged"
SLOW = "iteration limit reached, still converging"
DIVERGED = "diverged / not contracting"
BEYOND_FOLD = "converged beyond the fold (no measured position connected to the centre)"


def _history(d, point, method, max_iter):
    """``(steps, status, measured or None)`` of one inversion run; status from :data:`CONVERGED` …

    A run stopped by ``max_iter`` whose steps still shrink (``DistortionDivergenceError.converging``)
    is :data:`SLOW`, not a divergence; a root beyond the fold (``.beyond_fold``) is
    :data:`BEYOND_FOLD`.
    """
    try:
        m, report = d.distort(point, method=method, tol=1e-12, max_iter=max_iter,
                              return_report=True)
    except pl.DistortionDivergenceError as exc:
        status = SLOW if exc.converging else BEYOND_FOLD if exc.beyond_fold else DIVERGED
        return np.array(exc.report.history), status, None
    return np.array(report.history), CONVERGED, m


def contraction_factor(d, measured) -> float:
    """Contraction factor q of the fixed-point iteration at the measured point (dimensionless).

    ``x ← x_ideal + Δ(x)`` shrinks its steps by ``q = ρ(∂Δ/∂x)`` per iteration near the
    solution (ρ: largest |eigenvalue|); it converges where q < 1. For the radial model the
    eigenvalues are ``∂Δr′/∂r′ = 3A1r′² + 5A2r′⁴`` (radial) and ``Δr′/r′ = A1r′² + A2r′⁴``
    (tangential), so with A1 only, ``q = 3|A1|r′²`` at the *measured* radius r′.

    >>> d = distortion_from_sliders(A1=-50.0)
    >>> m = d.distort([16.0, 10.0])
    >>> round(contraction_factor(d, m), 3), round(3 * 5e-4 * float(np.hypot(*m)) ** 2, 3)
    (0.413, 0.413)
    """
    return float(np.max(np.abs(np.linalg.eigvals(d.jacobian_xy(measured)))))


def iteration_report(A1=-2.0, A2=0.0, radius=20.0, max_iter=30) -> dict:
    """Convergence of fixed-point and Newton iteration for one ideal point (Luhmann p. 163/164).

    Parameters
    ----------
    A1, A2 : float
        Slider units (:data:`SCALE`).
    radius : float
        Distance of the ideal point from the principal point, mm (on the format diagonal).
    max_iter : int
        Iteration limit of both runs.

    Returns
    -------
    dict
        ``point`` (ideal, mm); ``fixed`` and ``newton``: arrays of the largest step per
        iteration (mm); ``status`` per method, one of :data:`CONVERGED`, :data:`SLOW`
        (the limit was reached while the steps still shrank: slow convergence, not
        divergence), :data:`DIVERGED` and :data:`BEYOND_FOLD`; ``measured`` (mm, or None);
        ``q``, the contraction factor of the fixed point at the measured point (NaN when
        there is none); ``html``.

    Examples
    --------
    >>> rep = iteration_report(A1=-2.0, radius=20.0)
    >>> len(rep["newton"]) < len(rep["fixed"])
    True
    >>> strong = iteration_report(A1=-50.0, radius=20.0)   # q = 0.45: slow, not divergent
    >>> strong["status"]["fixed"], round(strong["q"], 2)
    ('iteration limit reached, still converging', 0.45)
    """
    d = distortion_from_sliders(A1=A1, A2=A2)
    u = np.array(HALF) / np.hypot(*HALF) * radius
    out = {"point": u}
    status, measured = {}, {}
    for key, method in (("fixed", "fixed-point"), ("newton", "newton")):
        out[key], status[key], measured[key] = _history(d, u, method, max_iter)
    m = measured["newton"] if status["newton"] == CONVERGED else (
        measured["fixed"] if status["fixed"] == CONVERGED else None)
    q = contraction_factor(d, m) if m is not None else float("nan")
    direct = float(np.hypot(*d.delta(u))) * 1000.0
    if m is None:
        where = "no measured position on the sheet connected to the centre"
    else:
        where = (f"measured point at r′ = {np.hypot(*m):.2f} mm; contraction factor of the "
                 f"fixed point there q = {q:.2f} ({'converges' if q < 1 else 'not contracting'})")
    html = (f"<p>ideal point ({u[0]:.2f}, {u[1]:.2f}) mm<br>"
            f"|Δ| evaluated at the ideal point: {direct:.1f} µm<br>{where}</p>"
            f"<p>fixed point: {len(out['fixed'])} iterations, {status['fixed']}<br>"
            f"Newton: {len(out['newton'])} iterations, {status['newton']}</p>")
    out.update(status=status, measured=m, q=q, html=html)
    return out


class DistortionExplorer(Explorer):
    """Sliders for A1, A2, r0, B1, B2, C1, C2 deforming a grid; the radial curve beside it."""

    title = "distortion explorer"

    def __init__(self, A1=-2.0, A2=0.0, r0=0.0, B1=0.0, B2=0.0, C1=0.0, C2=0.0,
                 exaggeration=10.0):
        c = self.controls = {
            "A1": slider("A1 [1e-5/mm²]", A1, -10, 10, 0.1),
            "A2": slider("A2 [1e-8/mm⁴]", A2, -10, 10, 0.1),
            "r0": slider("r0 [mm]", r0, 0, 20, 0.5),
            "B1": slider("B1 [1e-5/mm]", B1, -10, 10, 0.1),
            "B2": slider("B2 [1e-5/mm]", B2, -10, 10, 0.1),
            "C1": slider("C1 [1e-4]", C1, -10, 10, 0.1),
            "C2": slider("C2 [1e-4]", C2, -10, 10, 0.1),
            "exaggeration": slider("exaggeration ×", exaggeration, 1, 50, 1, fmt=".0f"),
        }
        self.controls = c
        self.live = LiveFigure((7.0, 3.0))
        ax, ax2 = self.live.figure.subplots(1, 2, gridspec_kw={"width_ratios": (1.3, 1)})
        self.live.figure.subplots_adjust(0.09, 0.15, 0.98, 0.9, wspace=0.3)
        ideal = grid_lines(*HALF)
        for line in ideal:
            ax.plot(*line.T, color="0.8", lw=0.8)
        ax.plot(*format_corners(*HALF).T, color="0.5", lw=1)
        self._lines = [self.live.animate(ax.plot([], [], color="#1f77b4", lw=1)[0]) for _ in ideal]
        ax.set(xlim=(-26, 26), ylim=(-17, 17), aspect="equal", xlabel="x' [mm]", ylabel="y' [mm]",
               title="measured image of a straight grid")
        ax2.set(xlim=(0, np.hypot(*HALF)), ylim=(-400, 400), xlabel="r' [mm]",
                ylabel="Δr' [µm]", title="radial distortion")
        ax2.axhline(0, color="0.5", lw=0.8)
        (self._curve,) = ax2.plot([], [], color="#d62728")
        self.live.animate(self._curve)
        self.report = None
        self._finish()

    def draw(self, **v) -> str:
        self.report = distortion_report(**v)
        lines = self.report["lines"]
        for artist, line in zip(self._lines, lines or [np.empty((0, 2))] * len(self._lines)):
            artist.set_data(*line.T)
        self._curve.set_data(self.report["r"], np.clip(self.report["dr"], -1e4, 1e4))
        return self.report["html"]


class IterationExplorer(Explorer):
    """Convergence curves of fixed-point and Newton iteration as the distortion grows."""

    title = "iterative correction explorer"

    def __init__(self, A1=-2.0, A2=0.0, radius=20.0):
        self.controls = {"A1": slider("A1 [1e-5/mm²]", A1, -100, 100, 1),
                         "A2": slider("A2 [1e-8/mm⁴]", A2, -20, 20, 0.5),
                         "radius": slider("r' of point [mm]", radius, 1, 21.5, 0.5)}
        self.live = LiveFigure((4.6, 3.0))
        ax = self.live.figure.add_subplot()
        self.live.figure.subplots_adjust(0.16, 0.15, 0.97, 0.9)
        ax.set(yscale="log", xlim=(0, 31), ylim=(1e-14, 1e2), xlabel="iteration",
               ylabel="largest step [mm]", title="convergence of the iteration")
        ax.axhline(1e-12, color="0.5", ls=":", lw=1)
        self._fixed = self.live.animate(ax.plot([], [], "o-", ms=3, label="fixed point")[0])
        self._newton = self.live.animate(ax.plot([], [], "s-", ms=3, label="Newton")[0])
        ax.legend(loc="upper right", fontsize=8)
        self.report = None
        self._finish()

    def draw(self, A1, A2, radius) -> str:
        self.report = rep = iteration_report(A1, A2, radius)
        for artist, h in ((self._fixed, rep["fixed"]), (self._newton, rep["newton"])):
            h = np.where(h > 0, h, 1e-16)
            artist.set_data(np.arange(1, len(h) + 1), np.clip(h, 1e-16, 1e3))
        return rep["html"]


def plot_distortion_field(d, half=HALF, n=11, title="Δ at measured points"):
    """Static figure: arrows of Δ (measured − ideal) over the format.

    Returns
    -------
    matplotlib.figure.Figure
    """
    import matplotlib.pyplot as plt

    gx, gy = np.meshgrid(np.linspace(-half[0], half[0], n), np.linspace(-half[1], half[1], n))
    xy = np.column_stack([gx.ravel(), gy.ravel()])
    D = d.delta(xy) * 1000.0
    fig, ax = plt.subplots(figsize=(5.0, 3.6))
    q = ax.quiver(xy[:, 0], xy[:, 1], D[:, 0], D[:, 1], np.hypot(*D.T), angles="xy")
    fig.colorbar(q, ax=ax, label="|Δ| [µm]")
    ax.plot(*format_corners(*half).T, color="0.5", lw=1)
    ax.set(aspect="equal", xlabel="x' [mm]", ylabel="y' [mm]", title=title)
    return finished(fig)


def plot_distorted_grid(models, half=HALF, exaggeration=10.0):
    """Static figure: a straight grid imaged through each model (displacements exaggerated).

    Parameters
    ----------
    models : sequence of (str, Distortion)
    """
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(1, len(models), figsize=(3.4 * len(models), 2.8))
    for ax, (name, d) in zip(np.atleast_1d(axes), models):
        ideal = grid_lines(*half)
        for line, shown in zip(ideal, _distorted_lines(d, ideal, exaggeration)):
            ax.plot(*line.T, color="0.85", lw=0.8)
            ax.plot(*shown.T, color="#1f77b4", lw=1)
        ax.set(aspect="equal", title=name, xticks=[], yticks=[])
    fig.suptitle(f"straight lines, imaged (displacements × {exaggeration:g})", fontsize=10)
    return finished(fig)


def plot_radial_profiles(models, rmax=None):
    """Static figure: Δr'(r) in µm for each (label, Distortion)."""
    import matplotlib.pyplot as plt

    r = np.linspace(0.0, rmax or float(np.hypot(*HALF)), 100)
    fig, ax = plt.subplots(figsize=(5.0, 3.0))
    for name, d in models:
        ax.plot(r, d.radial_profile(r) * 1000.0, label=name)
    ax.axhline(0, color="0.5", lw=0.8)
    ax.set(xlabel="r' [mm]", ylabel="Δr' [µm]", title="radial-symmetric distortion")
    ax.legend(fontsize=8)
    return finished(fig)


def plot_convergence(histories, tol=1e-12):
    """Static figure: largest step per iteration, log scale, for each (label, steps)."""
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(5.0, 3.0))
    for name, h in histories:
        h = np.clip(np.asarray(h, dtype=float), 1e-16, None)
        ax.semilogy(np.arange(1, len(h) + 1), h, "o-", ms=3, label=name)
    ax.axhline(tol, color="0.5", ls=":", lw=1)
    ax.set(xlabel="iteration", ylabel="largest step [mm]", title="convergence")
    ax.legend(fontsize=8)
    return finished(fig)
