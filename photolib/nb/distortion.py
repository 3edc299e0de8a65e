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
    "PLUMB_FRACTIONS",
    "coverage_experiment",
    "plot_plumb_lines",
    "plumb_line_images",
    "plumb_line_summary",
    "projection_centres",
    "plot_projection_centres",
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
        self.live = LiveFigure((5.6, 3.0))
        ax = self.live.figure.add_subplot()
        self.live.figure.subplots_adjust(0.13, 0.15, 0.78, 0.9)
        ax.set(yscale="log", xlim=(0, 31), ylim=(1e-14, 1e2), xlabel="iteration",
               ylabel="largest step [mm]", title="convergence of the iteration")
        ax.axhline(1e-12, color="0.5", ls=":", lw=1)
        self._fixed = self.live.animate(ax.plot([], [], "o-", ms=3, label="fixed point")[0])
        self._newton = self.live.animate(ax.plot([], [], "s-", ms=3, label="Newton")[0])
        # beside the axes: inside, a diverging iteration's points pass under it
        ax.legend(loc="upper left", fontsize=8, bbox_to_anchor=(1.02, 1.0), borderaxespad=0)
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


# -- plumb-line calibration / Kalibrierung mit Lotlinien (Plumblines) --------------------------
#: positions of the plumb lines as fractions of the half format (none through the centre)
PLUMB_FRACTIONS = (-0.8, -0.4, 0.35, 0.75)


def plumb_line_images(d, *, extent=1.0, fractions=PLUMB_FRACTIONS, half=HALF, n_points=15,
                      noise_um=1.0, seed=0):
    """Simulated images of straight object lines: ideal lines, and measured ones through ``d``.

    Horizontal lines at ``y = f·extent·half[1]`` over ``|x| ≤ extent·half[0]`` and vertical
    lines at ``x = f·extent·half[0]`` over ``|y| ≤ extent·half[1]``, for each f of
    ``fractions``; the measured points are ``d.distort(ideal)`` plus Gaussian noise.

    Parameters
    ----------
    d : photolib.Distortion
        The lens.
    extent : float
        Fraction of the format the lines cover (1: the whole format).
    fractions : sequence of float
        Line positions as fractions of the half format.
    half : tuple of float
        Half width and height of the format, mm.
    n_points : int
        Points per line.
    noise_um : float
        σ of the measuring noise per coordinate, µm.
    seed : int
        Seed of ``numpy.random.default_rng``.

    Returns
    -------
    (list of ndarray, list of ndarray)
        Ideal and measured points per line, each (n_points, 2), mm.

    Examples
    --------
    >>> ideal, measured = plumb_line_images(pl.Distortion(A1=-2e-5), noise_um=0.0)
    >>> len(ideal), ideal[0].shape, bool(abs(measured[0] - ideal[0]).max() > 0.01)
    (8, (15, 2), True)
    """
    rng = np.random.default_rng(seed)
    hw, hh = half[0] * extent, half[1] * extent
    s = np.linspace(-1.0, 1.0, n_points)
    ideal = [np.column_stack([hw * s, np.full(n_points, f * hh)]) for f in fractions]
    ideal += [np.column_stack([np.full(n_points, f * hw), hh * s]) for f in fractions]
    measured = [d.distort(p) + rng.normal(0.0, noise_um / 1000.0, p.shape) for p in ideal]
    return ideal, measured


def _exaggerated(points, theta, dist, factor):
    """Points moved away from the line ``cos θ x + sin θ y = d`` by ``factor`` × their offset."""
    n = np.array([np.cos(theta), np.sin(theta)])
    offset = points @ n - dist
    return points + (factor - 1.0) * offset[:, None] * n


def plot_plumb_lines(measured, fit, exaggeration=20.0, half=HALF):
    """Static figure: imaged plumb lines (curved) and the same points corrected (straight).

    Left: the measured points with their offsets from a straight line through them
    (total least squares, grey) × ``exaggeration``; right: the points corrected with
    ``fit.distortion`` and their offsets from the adjusted lines ``fit.lines``, same factor.

    Parameters
    ----------
    measured : list of ndarray
        Measured points per line, (n_i, 2), mm, reduced to the principal point.
    fit : photolib.calibration.PlumbLineResult
    """
    import matplotlib.pyplot as plt

    from photolib.calibration import _initial_line

    fig, axes = plt.subplots(1, 2, figsize=(7.4, 2.7), layout="constrained")
    for ax, title in zip(axes, ("imaged: curved", "corrected: straight")):
        ax.plot(*format_corners(*half).T, color="0.6", lw=0.8)
        ax.set(aspect="equal", title=title)
        ax.set_axis_off()
    for pts, (theta, dist) in zip(measured, fit.lines):
        t0, d0 = _initial_line(pts)
        corrected = fit.distortion.correct(pts)
        for ax, p, (t, d), colour in ((axes[0], pts, (t0, d0), "#1f77b4"),
                                      (axes[1], corrected, (theta, dist), "#2ca02c")):
            shown = _exaggerated(p, t, d, exaggeration)
            ax.plot(*_exaggerated(p, t, d, 0.0)[[0, -1]].T, color="0.75", lw=0.8)
            ax.plot(*shown.T, ".-", color=colour, ms=3, lw=0.8)
    fig.suptitle(f"plumb lines (Plumblines / Lotlinien), offsets from straight × {exaggeration:g}",
                 fontsize=10)
    return finished(fig)


def _pm(value, sigma, unit):
    """``'(−2.031 ± 0.062)e-05 mm⁻²'``: value and σ to the σ's second significant digit."""
    exp = int(np.floor(np.log10(abs(value)))) if value else 0
    digits = max(0, exp - int(np.floor(np.log10(sigma))) + 1) if sigma > 0 else 3
    return f"({value / 10**exp:.{digits}f} ± {sigma / 10**exp:.{digits}f})e{exp:+03d} {unit}"


_UNITS = {"A1": "mm⁻²", "A2": "mm⁻⁴", "A3": "mm⁻⁶", "B1": "mm⁻¹", "B2": "mm⁻¹"}


def plumb_line_summary(fit, true=None) -> str:
    """Text of a plumb-line estimate: each parameter ± σ (and the true value), σ0, iterations.

    Parameters
    ----------
    fit : photolib.calibration.PlumbLineResult
    true : photolib.Distortion or None
        The simulated lens, for comparison.

    Returns
    -------
    str

    Examples
    --------
    >>> import photolib.calibration as cal
    >>> _, m = plumb_line_images(pl.Distortion(A1=-2e-5), seed=1)
    >>> print(plumb_line_summary(cal.plumb_line(m, c=35.0, terms=("A1",))).splitlines()[0])
    A1 = (-2.004 ± 0.013)e-05 mm⁻²
    """
    rows = []
    for name in fit.terms:
        row = f"{name} = {_pm(fit.distortion.params[name], fit.sigma[name], _UNITS[name])}"
        if true is not None:
            err = (fit.distortion.params[name] - true.params[name]) / fit.sigma[name]
            row += f"   (true {true.params[name]:.3g}, error {err:+.1f} σ)"
        rows.append(row)
    rows.append(f"σ0 = {fit.sigma0 * 1000:.2f} µm · redundancy {fit.redundancy} · "
                f"{fit.iterations} iterations, converged: {fit.converged}")
    return "\n".join(rows)


def coverage_experiment(d, extents=(0.35, 1.0), *, c=35.0, terms=("A1", "A2"), noise_um=1.0,
                        seed=3, half=HALF) -> list:
    """Plumb-line calibrations from lines that cover a part of the format or all of it.

    The same lens, line pattern, number of points and noise, scaled to ``extent`` of the
    format; each fit's σ of Δr′ and its actual error at the format corner show how far the
    estimate can be trusted where the points were not.

    Parameters
    ----------
    d : photolib.Distortion
        The simulated lens.
    extents : sequence of float
        Fractions of the format covered by the lines.
    c : float
        Camera constant, mm.
    terms : sequence of str
        Estimated parameters.
    noise_um, seed : float, int
        Measuring noise (µm) and seed of :func:`plumb_line_images`.
    half : tuple of float
        Half format, mm.

    Returns
    -------
    list of dict
        Per extent: ``extent``, ``fit``, ``sigma_corner_um`` (σ of Δr′ at the corner, µm),
        ``error_corner_um`` (estimated minus true Δr′ there, µm).

    Examples
    --------
    >>> part, full = coverage_experiment(pl.Distortion(A1=-2e-5, A2=4e-8))
    >>> bool(part["sigma_corner_um"] > 10 * full["sigma_corner_um"])
    True
    """
    import photolib.calibration as cal

    corner = float(np.hypot(*half))
    out = []
    for extent in extents:
        _, measured = plumb_line_images(d, extent=extent, half=half, noise_um=noise_um, seed=seed)
        fit = cal.plumb_line(measured, c=c, terms=terms, r0=d.params["r0"])
        err = float(fit.distortion.radial_profile(corner) - d.radial_profile(corner)) * 1000.0
        out.append({"extent": extent, "fit": fit, "error_corner_um": err,
                    "sigma_corner_um": float(fit.radial_sigma(corner)) * 1000.0})
    return out


# -- projection centres of a real lens / Projektionszentren (Liniensystem) ----------------------
def projection_centres(d, tau, *, c=35.0, exit_pupil=40.0, pupil_separation=10.0) -> dict:
    """One principal ray through a centred lens: entrance and exit angle, ideal and measured radius.

    A meridional section with the image plane perpendicular to the optical axis, so that the
    principal point H′ is the axis' piercing point. The ray from the object meets the entrance
    pupil O at the field angle τ. The mathematical projection centre O_M′ lies on the
    perpendicular through H′ at the camera constant c; a ray leaving it at τ meets the image
    plane at the ideal radius ``r̄′ = c·tan τ``. The real ray leaves the exit pupil O′
    (``exit_pupil`` e′ above the image plane) and meets it at the measured radius r′, which
    the course model puts where ``r′ − Δr′(r′) = r̄′`` (Δ at the *measured* point,
    :meth:`photolib.Distortion.distort`). Its exit angle follows from the triangle O′H′P′:

        ``tan τ′ = r′/e′``,  ``Δr′ = r′ − c·tan τ``  (so ``r′ = c·tan τ + Δr′``).

    Parameters
    ----------
    d : photolib.Distortion
        Radial model (A1, A2, A3, r0); B1, B2, C1, C2 would move the point out of the section.
    tau : float
        Field angle τ on the object side, rad, ``0 ≤ τ < π/2``.
    c : float
        Camera constant, mm (> 0).
    exit_pupil : float
        Distance e′ of the exit pupil O′ from the image plane, mm (> 0); an assumption of
        the drawing, the course model does not use it.
    pupil_separation : float
        Distance from O′ to the entrance pupil O, mm (≥ 0); only drawn.

    Returns
    -------
    dict
        ``tau``, ``tau_exit`` (rad); ``r_ideal`` (c·tan τ), ``r_measured``, ``delta_r``
        (mm); ``H``, ``O_M``, ``O_exit``, ``O_entrance``: heights above the image plane on
        the axis (mm); ``c``, ``exit_pupil``.

    Raises
    ------
    ValueError
        For τ outside [0, π/2), c or e′ ≤ 0, or a model with B1, B2, C1 or C2.

    Examples
    --------
    >>> import photolib as pl
    >>> g = projection_centres(pl.Distortion(A1=-5e-4), np.radians(25.0))
    >>> round(g["r_ideal"], 3), round(g["r_measured"], 3), round(g["delta_r"], 3)
    (16.321, 14.725, -1.596)
    >>> round(float(np.degrees(g["tau_exit"])), 2)     # τ′ = atan(r′/e′) ≠ τ = 25°
    20.21
    """
    from photolib._validate import as_scalar

    tau = as_scalar(tau, "tau")
    if not 0.0 <= tau < np.pi / 2:
        raise ValueError(f"tau must be in [0, π/2) rad, got {tau!r}")
    c = as_scalar(c, "c", positive=True)
    e = as_scalar(exit_pupil, "exit_pupil", positive=True)
    s = as_scalar(pupil_separation, "pupil_separation")
    if s < 0:
        raise ValueError(f"pupil_separation must be ≥ 0, got {s!r}")
    other = {k: v for k, v in d.params.items() if k in ("B1", "B2", "C1", "C2") and v}
    if other:
        raise ValueError(f"projection_centres draws a radial model only, got {other}")
    r_ideal = c * np.tan(tau)
    r_measured = float(np.hypot(*d.distort([r_ideal, 0.0])))
    return {"tau": tau, "tau_exit": float(np.arctan2(r_measured, e)), "r_ideal": float(r_ideal),
            "r_measured": r_measured, "delta_r": r_measured - float(r_ideal), "H": 0.0,
            "O_M": c, "O_exit": e, "O_entrance": e + s, "c": c, "exit_pupil": e}


def _angle_arc(ax, centre, start_deg, span_deg, radius, label, colour):
    """An arc of ``span_deg`` from ``start_deg`` about ``centre``, labelled at its middle."""
    from matplotlib.patches import Arc

    ax.add_patch(Arc(centre, 2 * radius, 2 * radius, theta1=min(start_deg, start_deg + span_deg),
                     theta2=max(start_deg, start_deg + span_deg), color=colour, lw=1))
    mid = np.radians(start_deg + span_deg / 2)
    ax.text(centre[0] + 1.35 * radius * np.cos(mid), centre[1] + 1.35 * radius * np.sin(mid),
            label, color=colour, ha="center", va="center", fontsize=9)


def plot_projection_centres(d, tau, *, c=35.0, exit_pupil=40.0, pupil_separation=10.0):
    """Static figure: entrance pupil O, exit pupil O′, mathematical centre O_M′, τ, τ′ and Δr′.

    The optical axis runs left to right (object side left), the image plane is the vertical
    line at the right; heights are radii in the image plane, mm, drawn to scale. The object
    ray (label ``"object ray"``) reaches O at τ; the real ray (``"exit ray"``) goes from O′
    to the measured point r′; the ideal ray (``"ideal ray"``) from O_M′ at τ to ``c·tan τ``.
    Between the pupils the ray's path inside the lens is not modelled (dotted). The geometry
    is :func:`projection_centres`, with the same parameters.

    Returns
    -------
    matplotlib.figure.Figure

    Examples
    --------
    >>> import photolib as pl
    >>> fig = plot_projection_centres(pl.Distortion(A1=-5e-4), np.radians(25.0))
    >>> [ln.get_label() for ln in fig.axes[0].lines if not ln.get_label().startswith("_")]
    ['object ray', 'exit ray', 'ideal ray']
    """
    import matplotlib.pyplot as plt

    g = projection_centres(d, tau, c=c, exit_pupil=exit_pupil, pupil_separation=pupil_separation)
    # plot coordinates: u = −(height above the image plane), v = radius in the image plane
    uO, uE, uM = -g["O_entrance"], -g["O_exit"], -g["O_M"]
    t, t2 = g["tau"], g["tau_exit"]
    fig, ax = plt.subplots(figsize=(7.4, 3.4))
    top = max(g["r_ideal"], g["r_measured"])
    ax.axhline(0.0, color="0.6", lw=0.8, ls="-.")
    ax.plot([0, 0], [-0.35 * top, 1.25 * top], color="k", lw=2)
    # the lens (schematic) and the aperture stop between the pupils
    lo, hi = min(uO, uE) - 2.0, max(uO, uE) + 2.0
    ax.add_patch(plt.Rectangle((lo, -0.55 * top), hi - lo, 1.1 * top, color="#dbe9f6", zorder=0))
    us = (uO + uE) / 2
    for sign in (1, -1):
        ax.plot([us, us], [sign * 0.18 * top, sign * 0.5 * top], color="0.25", lw=3)
    ax.text(us, -0.62 * top, "aperture stop / Blende", ha="center", va="top", fontsize=8)
    # rays
    reach = 0.5 * top / np.tan(max(t, 0.3))          # horizontal extent of the object ray
    ax.plot([uO - reach, uO], [-reach * np.tan(t), 0.0], color="#1f77b4", label="object ray")
    ax.plot([uO, uE], [0.0, 0.0], color="#1f77b4", ls=":", lw=1.5)
    ax.plot([uE, 0.0], [0.0, g["r_measured"]], color="#1f77b4", label="exit ray")
    ax.plot([uM, 0.0], [0.0, g["r_ideal"]], color="#d62728", ls="--", label="ideal ray")
    # points
    for u, name, dv in ((uO, "O", -1), (uE, "O′", -1), (uM, "O$_M$′", 1), (0.0, "H′", -1)):
        ax.plot(u, 0.0, "o", color="k", ms=4)
        ax.text(u + (0.8 if u == 0.0 else 0.0), dv * 0.08 * top, name, ha="center",
                va="bottom" if dv > 0 else "top", fontsize=9)
    _angle_arc(ax, (uO, 0.0), 180.0, np.degrees(t), 0.45 * top, "τ", "#1f77b4")
    _angle_arc(ax, (uE, 0.0), 0.0, np.degrees(t2), 0.9 * top, "τ′", "#1f77b4")
    _angle_arc(ax, (uM, 0.0), 0.0, np.degrees(t), 0.25 * top, "τ", "#d62728")
    # distances of O_M′ (c) and O′ (e′) from the image plane
    for u, v, name in ((uM, -0.22 * top, "c"), (uE, -0.4 * top, "e′")):
        ax.annotate("", xy=(u, v), xytext=(0.0, v),
                    arrowprops={"arrowstyle": "<->", "color": "0.4", "lw": 0.8})
        ax.text(u / 2, v, name, ha="center", va="bottom", fontsize=8, color="0.3")
    # Δr′ on the image plane, the two radii labelled to the right
    arrow = {"arrowstyle": "->", "color": "#2ca02c", "lw": 1.5, "shrinkA": 0, "shrinkB": 0}
    ax.annotate("", xy=(1.0, g["r_measured"]), xytext=(1.0, g["r_ideal"]), arrowprops=arrow)
    ax.text(2.0, (g["r_ideal"] + g["r_measured"]) / 2, f"Δr′ = {g['delta_r']:+.2f} mm",
            color="#2ca02c", va="center", fontsize=9)
    upper = g["r_ideal"] >= g["r_measured"]
    for r, name, colour, side in ((g["r_ideal"], "c·tan τ", "#d62728", 1 if upper else -1),
                                  (g["r_measured"], "r′", "#1f77b4", -1 if upper else 1)):
        ax.annotate(f"{name} = {r:.2f} mm", xy=(0.0, r), xytext=(2.0, r + side * 0.25 * top),
                    color=colour, fontsize=8, va="center",
                    arrowprops={"arrowstyle": "-", "color": colour, "lw": 0.6})
    ax.text(1.0, -0.5 * top, "image plane /\nBildebene", fontsize=8, va="center")
    ax.set(aspect="equal", xlabel="distance from the image plane [mm]", ylabel="radius r′ [mm]",
           xlim=(uO - reach - 2.0, 24.0), ylim=(-0.75 * top, 1.3 * top))
    ax.set_title(f"c = {c:g} mm, exit pupil e′ = {exit_pupil:g} mm, τ = {np.degrees(t):.1f}°, "
                 f"τ′ = {np.degrees(t2):.1f}°", fontsize=9)
    fig.tight_layout()
    return finished(fig)
