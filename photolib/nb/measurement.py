"""Chapter 11 pictures and widgets: image measurement / Bildmessung.

Synthetic images with known truth: :func:`target_image` (a bright circular target with a
smooth edge, Zielmarke), :func:`scene_image` (a disc and a square for edges),
:func:`texture` (a smooth analytic grey-value surface for least-squares matching). The
reports (``*_report``) are the widgets' callbacks as plain functions; the explorers only move
artists. All randomness is seeded.
"""

from __future__ import annotations

import functools
import math

import numpy as np

from photolib.fitting import fit_ellipse
from photolib.matching import least_squares_matching
from photolib.measurement import (
    fit_circle,
    gaussian_radius,
    log_filter,
    moment_threshold,
    weighted_centroid,
    zero_crossings,
)
from photolib.nb.live import Explorer, LiveFigure, finished, slider
from photolib.transforms._base import ConvergenceError

__all__ = [
    "ELLIPSE_TRUE",
    "LSM_TRUE",
    "SCENE_DISC",
    "EllipseExplorer",
    "LSMExplorer",
    "LoGExplorer",
    "ThresholdExplorer",
    "ellipse_points",
    "ellipse_report",
    "log_report",
    "lsm_report",
    "lsm_search_image",
    "lsm_template",
    "plot_log_profile",
    "scene_image",
    "target_image",
    "texture",
    "threshold_report",
]

#: the disc of :func:`scene_image`: centre (col, row) and radius, pixels
SCENE_DISC = ((24.3, 30.6), 10.0)
#: the ellipse of the ellipse explorer: centre (x, y), semi-axes (a, b), angle (rad)
ELLIPSE_TRUE = ((3.0, 2.0), (6.0, 3.5), math.radians(30.0))
#: the true LSM parameters: a0, a1, a2, b0, b1, b2, r0, r1 (template centre at (a0, b0))
LSM_TRUE = (32.4, 1.03, 0.05, 30.7, -0.04, 0.98, 6.0, 0.9)


def _smooth_step(t, blur):
    """0 → 1 across t = 0 with a Gaussian edge of σ = ``blur`` (erf profile, as a PSF gives)."""
    from math import erf

    return 0.5 * (1.0 + np.vectorize(erf)(t / (math.sqrt(2.0) * blur)))


def target_image(size: int = 32, centre=(15.4, 16.2), radius: float = 5.0, blur: float = 0.8,
                 background: float = 30.0, amplitude: float = 170.0, noise: float = 0.0,
                 seed: int = 11) -> np.ndarray:
    """A bright circular target on a dark background, edge blurred by a Gaussian PSF.

    >>> img = target_image()
    >>> img.shape, round(float(img[16, 15])), round(float(img[0, 0]))
    ((32, 32), 200, 30)
    """
    rows, cols = np.mgrid[:size, :size].astype(float)
    dist = np.hypot(cols - centre[0], rows - centre[1])
    img = background + amplitude * _smooth_step(radius - dist, blur)
    return img + np.random.default_rng(seed).normal(0.0, noise, img.shape)


def scene_image(noise: float = 2.0, seed: int = 12) -> np.ndarray:
    """64 × 80 test image: the disc :data:`SCENE_DISC` and a square, blurred edges, noise.

    >>> scene_image().shape
    (64, 80)
    """
    return _scene(float(noise), int(seed)).copy()


@functools.lru_cache(maxsize=32)
def _scene(noise, seed):
    rows, cols = np.mgrid[:64, :80].astype(float)
    (cx, cy), r = SCENE_DISC
    disc = _smooth_step(r - np.hypot(cols - cx, rows - cy), 0.7)
    square = (_smooth_step(9.0 - np.abs(cols - 58.0), 0.7) * _smooth_step(9.0 - np.abs(rows - 30.0), 0.7))
    img = 40.0 + 150.0 * disc + 100.0 * square
    return img + np.random.default_rng(seed).normal(0.0, noise, img.shape)


# -- LoG -------------------------------------------------------------------------------------------

def plot_log_profile(sigma: float = 2.0):
    """∇²G over r: the corrected 5.42 and the old print (scaled to the same value at r = 0)."""
    import matplotlib.pyplot as plt

    from photolib.measurement import laplacian_of_gaussian

    r = np.linspace(0.0, 4.0 * sigma, 200)
    corrected = laplacian_of_gaussian(r, sigma)
    old = -(1.0 - r / sigma**2) * np.exp(-(r**2) / (2.0 * sigma**2))
    fig, ax = plt.subplots(figsize=(5.6, 3.0))
    ax.plot(r, corrected, label="corrected 5.42 (derived)")
    ax.plot(r, old * corrected[0] / old[0], "--", label="old print, scaled")
    ax.axvline(math.sqrt(2.0) * sigma, color="0.5", lw=0.8)
    ax.axhline(0.0, color="0.3", lw=0.6)
    ax.set(xlabel="r [px]", ylabel="∇²G", title=f"LoG profile, σ = {sigma:g} px (zero at √2·σ)")
    ax.legend(fontsize=8)
    return finished(fig)


def log_report(sigma: float = 2.0, threshold: float = 2.0, noise: float = 2.0) -> dict:
    """LoG of :func:`scene_image` and its zero crossings; the disc's rim radius from them.

    Returns
    -------
    dict
        ``response`` (H, W), ``edges`` (N, 2) (col, row) of the zero-crossing pixels,
        ``kernel`` (kernel width), ``rim_radius`` (mean distance of the edges near the disc
        from its centre, px; true 10), ``html``.

    Examples
    --------
    >>> rep = log_report(2.0, 2.0)
    >>> rep["kernel"], abs(rep["rim_radius"] - 10.0) < 0.6
    (17, True)
    """
    img = scene_image(noise)
    L = log_filter(img, sigma) * sigma**2            # σ²-normalised: comparable over σ
    zc = zero_crossings(L, threshold)
    rows, cols = np.nonzero(zc)
    edges = np.column_stack([cols, rows]).astype(float)
    (cx, cy), r = SCENE_DISC
    d = np.hypot(edges[:, 0] - cx, edges[:, 1] - cy)
    near = np.abs(d - r) < 4.0
    rim = float(np.mean(d[near])) if near.any() else float("nan")
    k = 2 * gaussian_radius(sigma) + 1
    html = (f"<p>σ = {sigma:.2f} px: kernel {k} × {k} as two 1-D passes of {k}<br>"
            f"zero crossings (jump &gt; {threshold:g}): <b>{len(edges)}</b> pixels<br>"
            f"disc rim from them: r = <b>{rim:.2f} px</b> (true {r:g})</p>")
    return {"response": L, "edges": edges, "kernel": k, "rim_radius": rim, "html": html}


class LoGExplorer(Explorer):
    """σ and threshold of the LoG → filtered image and zero crossings (edges)."""

    title = "Laplacian of Gaussian explorer"

    def __init__(self, sigma=2.0, threshold=2.0):
        self.controls = {"sigma": slider("σ [px]", sigma, 0.6, 4.0, 0.1, fmt=".1f"),
                         "threshold": slider("jump threshold", threshold, 0.0, 20.0, 0.5)}
        self.live = LiveFigure((7.2, 2.9))
        fig = self.live.figure
        ax, bx = fig.add_subplot(1, 2, 1), fig.add_subplot(1, 2, 2)
        fig.subplots_adjust(0.02, 0.08, 0.98, 0.9, wspace=0.08)
        ax.imshow(scene_image(), cmap="gray", vmin=0, vmax=255)
        ax.set(title="image and zero crossings", xticks=[], yticks=[])
        (self._edges,) = ax.plot([], [], "s", color="#d62728", ms=1.5)
        self._img = bx.imshow(np.zeros((64, 80)), cmap="RdBu_r", vmin=-40, vmax=40,
                              interpolation="nearest")
        bx.set(title="σ²·∇²(G * g)", xticks=[], yticks=[])
        for artist in (self._edges, self._img):
            self.live.animate(artist)
        self.report = None
        self._finish()

    def draw(self, sigma, threshold) -> str:
        self.report = rep = log_report(sigma, threshold)
        self._img.set_data(rep["response"])
        self._edges.set_data(*rep["edges"].T)
        return rep["html"]


# -- moment-preserving threshold -------------------------------------------------------------------

def threshold_report(radius: float = 6.0, noise: float = 8.0) -> dict:
    """Tsai's threshold of :func:`target_image` with a disc of ``radius`` and Gaussian noise.

    Returns
    -------
    dict
        ``image``, ``result`` (:class:`photolib.MomentThreshold`), ``fraction`` (true
        dark fraction), ``printed_p1`` (the errata's printed 5.50, wrong), ``hist``
        (counts, edges), ``centroid`` (col, row) above the threshold, ``html``.

    Examples
    --------
    >>> rep = threshold_report(6.0, 0.0)
    >>> abs(rep["result"].p1 - rep["fraction"]) < 0.02, rep["printed_p1"] > 1
    (True, True)
    """
    img = target_image(radius=radius, noise=noise)
    t = moment_threshold(img)
    c0 = img.ravel() - img.mean()
    sd = math.sqrt(float(np.mean(c0**2)))
    s = float(np.mean(c0**3)) / sd**3
    printed = 0.5 * (1.0 + s * math.sqrt(4.0 + s * s))
    frac = 1.0 - math.pi * radius**2 / img.size
    counts, edges = np.histogram(img, bins=64, range=(-20.0, 260.0))
    cen = weighted_centroid(img, t.threshold)
    html = (f"<p>skewness s̄ = {s:+.3f}<br>p1 = ½[1 + s̄/√(4 + s̄²)] = <b>{t.p1:.3f}</b> "
            f"(dark fraction of the image ≈ {frac:.3f})<br>"
            f"printed 5.50 ½[1 + s̄·√(4 + s̄²)] = <span style='color:#b00'>{printed:.3f}</span>"
            f"<br>h1 = {t.h1:.1f}, h2 = {t.h2:.1f}, threshold = <b>{t.threshold:.1f}</b><br>"
            f"centroid above it: ({cen.colrow[0]:.2f}, {cen.colrow[1]:.2f}) (true 15.40, 16.20)</p>")
    return {"image": img, "result": t, "fraction": frac, "printed_p1": printed,
            "hist": (counts, edges), "centroid": cen.colrow, "html": html}


class ThresholdExplorer(Explorer):
    """Target size and noise → histogram, Tsai's threshold, p1 (right and as printed)."""

    title = "moment-preserving threshold explorer"

    def __init__(self, radius=6.0, noise=8.0):
        self.controls = {"radius": slider("target radius [px]", radius, 2.0, 12.0, 0.5),
                         "noise": slider("noise [grey]", noise, 0.0, 30.0, 1.0, fmt=".0f")}
        self.live = LiveFigure((7.2, 2.9))
        fig = self.live.figure
        ax, bx = fig.add_subplot(1, 2, 1), fig.add_subplot(1, 2, 2)
        fig.subplots_adjust(0.02, 0.16, 0.98, 0.9, wspace=0.2)
        self._img = ax.imshow(np.zeros((32, 32)), cmap="gray", vmin=0, vmax=255,
                              interpolation="nearest")
        (self._cross,) = ax.plot([], [], "+", color="#d62728", ms=12, mew=2)
        ax.set(title="target; pixels > threshold in red", xticks=[], yticks=[])
        self._mask = ax.imshow(np.zeros((32, 32, 4)), interpolation="nearest")
        (self._hist,) = bx.plot([], [], drawstyle="steps-mid", color="#1f77b4")
        self._line = bx.axvline(0.0, color="#d62728")
        (self._levels,) = bx.plot([], [], "v", color="#2ca02c", ms=8)
        bx.set(yscale="log", xlim=(-20, 260), ylim=(0.8, 1200), xlabel="grey value",
               title="histogram, threshold, h1/h2")
        for artist in (self._img, self._mask, self._cross, self._hist, self._line, self._levels):
            self.live.animate(artist)
        self.report = None
        self._finish()

    def draw(self, radius, noise) -> str:
        self.report = rep = threshold_report(radius, noise)
        t = rep["result"]
        self._img.set_data(rep["image"])
        overlay = np.zeros(rep["image"].shape + (4,))
        overlay[rep["image"] > t.threshold] = (0.84, 0.15, 0.16, 0.35)
        self._mask.set_data(overlay)
        self._cross.set_data([rep["centroid"][0]], [rep["centroid"][1]])
        counts, edges = rep["hist"]
        self._hist.set_data(0.5 * (edges[1:] + edges[:-1]), np.maximum(counts, 0.9))
        self._line.set_xdata([t.threshold, t.threshold])
        self._levels.set_data([t.h1, t.h2], [900.0, 900.0])
        return rep["html"]


# -- ellipse fit -------------------------------------------------------------------------------------

def ellipse_points(arc_deg: float = 360.0, noise: float = 0.05, n: int = 30, seed: int = 13):
    """``n`` points (N, 2) on an arc of :data:`ELLIPSE_TRUE` (start at the a-axis), noisy.

    The same standard-normal draws are scaled by ``noise`` for every slider position.

    >>> ellipse_points(360.0, 0.0, 4).round(6).tolist()[0]
    [8.196152, 5.0]
    """
    (cx, cy), (a, b), th = ELLIPSE_TRUE
    t = np.radians(arc_deg) * np.arange(n) / (n - 1 if arc_deg < 360.0 else n)
    R = np.array([[math.cos(th), -math.sin(th)], [math.sin(th), math.cos(th)]])
    p = np.array([cx, cy]) + (R @ np.vstack([a * np.cos(t), b * np.sin(t)])).T
    return p + noise * np.random.default_rng(seed).standard_normal((n, 2))


def _ellipse_curve(centre, axes, angle, k=120):
    t = np.linspace(0, 2 * np.pi, k)
    R = np.array([[math.cos(angle), -math.sin(angle)], [math.sin(angle), math.cos(angle)]])
    return np.asarray(centre) + (R @ np.vstack([axes[0] * np.cos(t), axes[1] * np.sin(t)])).T


def ellipse_report(arc_deg: float = 360.0, noise: float = 0.05) -> dict:
    """Ellipse and circle fit to :func:`ellipse_points`: centre errors (same unit, mm say).

    Examples
    --------
    >>> rep = ellipse_report(360.0, 0.0)
    >>> rep["centre_error"] < 1e-9, rep["fit"] is not None
    (True, True)
    """
    xy = ellipse_points(arc_deg, noise)
    (cx, cy), axes_true, _ = ELLIPSE_TRUE
    try:
        fit = fit_ellipse(xy)
        err = float(np.hypot(*(fit.centre - (cx, cy))))
        text = (f"ellipse fit: centre ({fit.centre[0]:.3f}, {fit.centre[1]:.3f}), "
                f"a = {fit.axes[0]:.3f}, b = {fit.axes[1]:.3f}, "
                f"θ = {math.degrees(fit.angle):.1f}°<br>centre error <b>{err:.3f}</b>")
    except ValueError as exc:
        fit, err = None, float("nan")
        text = f"<span style='color:#b00'>ellipse fit failed: {str(exc).split(';')[0]}</span>"
    circ = fit_circle(xy)
    cerr = float(np.hypot(*(circ.centre - (cx, cy))))
    html = (f"<p>{len(xy)} points on {arc_deg:.0f}° of arc, noise σ = {noise:.3f}<br>{text}<br>"
            f"circle fit (wrong model): centre error {cerr:.3f}, r = {circ.radius:.3f}<br>"
            f"true: centre ({cx:g}, {cy:g}), a = {axes_true[0]:g}, b = {axes_true[1]:g}, θ = 30°</p>")
    return {"xy": xy, "fit": fit, "centre_error": err, "circle": circ, "html": html}


class EllipseExplorer(Explorer):
    """Arc length and noise → fitted ellipse (and a circle for contrast), centre error."""

    title = "ellipse fit explorer"

    def __init__(self, arc_deg=360.0, noise=0.05):
        self.controls = {"arc_deg": slider("arc [°]", arc_deg, 30.0, 360.0, 10.0, fmt=".0f"),
                         "noise": slider("noise σ", noise, 0.0, 0.5, 0.01, fmt=".2f")}
        self.live = LiveFigure((5.4, 3.3))
        ax = self.live.figure.add_subplot()
        self.live.figure.subplots_adjust(0.1, 0.12, 0.76, 0.92)
        ax.plot(*_ellipse_curve(*ELLIPSE_TRUE).T, color="0.7", lw=3, label="true")
        (self._fit,) = ax.plot([], [], color="#1f77b4", label="ellipse fit")
        (self._circle,) = ax.plot([], [], ":", color="#ff7f0e", label="circle fit")
        (self._pts,) = ax.plot([], [], ".", color="k", ms=4)
        (self._centre,) = ax.plot([], [], "+", color="#d62728", ms=10, mew=2)
        ax.set(xlim=(-6, 12), ylim=(-5, 9), aspect="equal", title="ellipse / Ellipse")
        # beside the axes: inside, the fitted curves and points pass under it
        ax.legend(fontsize=7, loc="upper left", bbox_to_anchor=(1.02, 1.0), borderaxespad=0)
        for artist in (self._fit, self._circle, self._pts, self._centre):
            self.live.animate(artist)
        self.report = None
        self._finish()

    def draw(self, arc_deg, noise) -> str:
        self.report = rep = ellipse_report(arc_deg, noise)
        self._pts.set_data(*rep["xy"].T)
        fit = rep["fit"]
        if fit is None:
            self._fit.set_data([], [])
            self._centre.set_data([], [])
        else:
            self._fit.set_data(*_ellipse_curve(fit.centre, fit.axes, fit.angle).T)
            self._centre.set_data([fit.centre[0]], [fit.centre[1]])
        c = rep["circle"]
        self._circle.set_data(*_ellipse_curve(c.centre, (c.radius, c.radius), 0.0).T)
        return rep["html"]


# -- least-squares matching ------------------------------------------------------------------------

def texture(c, r):
    """Smooth analytic grey values at (col, row): the search image's truth for LSM.

    >>> round(float(texture(0.0, 0.0)), 6)
    145.0
    """
    c, r = np.asarray(c, float), np.asarray(r, float)
    return (120 + 40 * np.sin(c / 3.1) * np.cos(r / 4.3) + 25 * np.cos((c + 2 * r) / 5.7)
            + 15 * np.exp(-((c - 30) ** 2 + (r - 28) ** 2) / 60))


def lsm_search_image(shape=(64, 64)) -> np.ndarray:
    """The search image: :func:`texture` sampled at the pixel centres."""
    rr, cc = np.mgrid[: shape[0], : shape[1]].astype(float)
    return texture(cc, rr)


def lsm_template(params=LSM_TRUE, size: int = 21, noise: float = 0.0, seed: int = 14):
    """Template f(x, y) = r0 + r1·texture(x', y') + noise, (x, y) from the template centre."""
    a0, a1, a2, b0, b1, b2, r0, r1 = params
    y, x = np.mgrid[:size, :size].astype(float) - (size - 1) / 2
    f = r0 + r1 * texture(a0 + a1 * x + a2 * y, b0 + b1 * x + b2 * y)
    return f + noise * np.random.default_rng(seed).standard_normal(f.shape)


def lsm_report(offset: float = 2.0, noise: float = 2.0, direction_deg: float = 45.0) -> dict:
    """LSM from a start ``offset`` px away from the true position (direction in degrees).

    Returns
    -------
    dict
        ``result`` (:class:`photolib.matching.LSMResult` or None), ``history`` (K, 8),
        ``error`` (px distance of the final position from the truth), ``failure``, ``html``.

    Examples
    --------
    >>> rep = lsm_report(2.0, 0.0)
    >>> rep["failure"], rep["error"] < 0.05
    (None, True)
    """
    f = lsm_template(noise=noise)
    g = lsm_search_image()
    a = math.radians(direction_deg)
    start = (LSM_TRUE[0] + offset * math.cos(a), LSM_TRUE[3] + offset * math.sin(a))
    try:
        res = least_squares_matching(f, g, start)
    except (ConvergenceError, ValueError) as exc:
        msg = str(exc).split(":")[0]
        hist = getattr(exc, "history", np.array([[start[0], 1, 0, start[1], 0, 1, 0, 1]]))
        html = (f"<p>start offset {offset:.1f} px<br><span style='color:#b00'>{msg}</span> "
                f"after {len(hist) - 1} iterations</p>")
        return {"result": None, "history": hist, "error": float("nan"), "failure": msg,
                "html": html}
    err = float(np.hypot(res.params[0] - LSM_TRUE[0], res.params[3] - LSM_TRUE[3]))
    q = res.params
    html = (f"<p>start offset {offset:.1f} px, noise {noise:.1f} grey<br>"
            f"iterations: <b>{res.iterations}</b><br>"
            f"position ({q[0]:.3f}, {q[3]:.3f}) px, true ({LSM_TRUE[0]}, {LSM_TRUE[3]})<br>"
            f"error <b>{err:.3f} px</b>; σ<sub>a0</sub> = {res.std[0]:.3f}, "
            f"σ<sub>b0</sub> = {res.std[3]:.3f} px<br>"
            f"a1, a2, b1, b2 = {q[1]:.3f}, {q[2]:.3f}, {q[4]:.3f}, {q[5]:.3f}<br>"
            f"r0 = {q[6]:.2f}, r1 = {q[7]:.3f} (true {LSM_TRUE[6]}, {LSM_TRUE[7]})<br>"
            f"σ0 = {res.sigma0:.2f} grey</p>")
    if err > 1.0:
        html += "<p style='color:#b00'>converged, but to a false match (another texture detail)</p>"
    return {"result": res, "history": res.history, "error": err, "failure": None, "html": html}


def _patch_outline(q, size=21):
    h = (size - 1) / 2
    corners = np.array([[-h, -h], [h, -h], [h, h], [-h, h], [-h, -h]])
    return np.column_stack([q[0] + q[1] * corners[:, 0] + q[2] * corners[:, 1],
                            q[3] + q[4] * corners[:, 0] + q[5] * corners[:, 1]])


class LSMExplorer(Explorer):
    """Start offset and noise → the iterations of least-squares matching and the final patch."""

    title = "least-squares matching explorer"

    def __init__(self, offset=2.0, noise=2.0):
        self.controls = {"offset": slider("start offset [px]", offset, 0.0, 8.0, 0.25, fmt=".2f"),
                         "noise": slider("noise [grey]", noise, 0.0, 20.0, 0.5)}
        self.live = LiveFigure((4.6, 3.6))
        ax = self.live.figure.add_subplot()
        self.live.figure.subplots_adjust(0.1, 0.1, 0.98, 0.92)
        ax.imshow(lsm_search_image(), cmap="gray")
        ax.plot(*_patch_outline(LSM_TRUE).T, color="#2ca02c", lw=2, label="true patch")
        (self._path,) = ax.plot([], [], "o-", color="#ff7f0e", ms=3, label="iterates")
        (self._patch,) = ax.plot([], [], color="#d62728", lw=1.2, label="final patch")
        ax.set(xlim=(10, 55), ylim=(52, 8), title="search image / Suchbild")
        ax.legend(fontsize=7, loc="lower left")
        for artist in (self._path, self._patch):
            self.live.animate(artist)
        self.report = None
        self._finish()

    def draw(self, offset, noise) -> str:
        self.report = rep = lsm_report(offset, noise)
        hist = rep["history"]
        self._path.set_data(hist[:, 0], hist[:, 3])
        self._patch.set_data(*_patch_outline(hist[-1]).T)
        return rep["html"]


# -- real photographs: targets, LSM on the motorcycle pair, features, RANSAC, dense --------------

@functools.lru_cache(maxsize=1)
def real_targets():
    """The four yellow targets of :func:`photolib.data.yellowtargets`, measured (cached)."""
    from photolib.data import yellowtargets
    from photolib.measurement._real import measure_targets

    return tuple(measure_targets(yellowtargets()[0]))


def target_report(index: int) -> dict:
    """Numbers of target ``index`` of :func:`real_targets` (centroids, centre, precision)."""
    tg = real_targets()[int(index)]
    html = (f"<p>target {int(index)}: {tg.area} px above t = {tg.threshold:.1f}<br>"
            f"binary centroid: ({tg.binary[0]:.2f}, {tg.binary[1]:.2f})<br>"
            f"weighted centroid: ({tg.weighted[0]:.2f}, {tg.weighted[1]:.2f}) "
            f"± ({tg.weighted_std[0]:.3f}, {tg.weighted_std[1]:.3f}) px "
            f"(σ_g = {tg.sigma_g:.1f}, independent noise); "
            f"× {tg.noise_factor:.1f} for the correlated noise: "
            f"± ({tg.weighted_std[0] * tg.noise_factor:.3f}, "
            f"{tg.weighted_std[1] * tg.noise_factor:.3f}) px<br>"
            f"diagonal centre: ({tg.centre[0]:.2f}, {tg.centre[1]:.2f})<br>"
            f"side fits σ0: {', '.join(f'{s:.2f}' for s in tg.side_sigma)} px "
            f"({tg.side_points} edge points)</p>")
    return {"target": tg, "html": html}


class TargetPicker(Explorer):
    """Pick a target of the real photograph: zoom on it with its centroids, sides and centre."""

    title = "target picker (yellowtargets)"

    def __init__(self, index=0, zoom=1.0):
        from photolib.data import yellowtargets

        self.controls = {"index": slider("target", index, 0, len(real_targets()) - 1, 1,
                                         fmt=".0f"),
                         "zoom": slider("zoom", zoom, 1.0, 4.0, 0.25, fmt=".2f")}
        self.live = LiveFigure((4.6, 3.6))
        ax = self.live.figure.add_subplot()
        self.ax = ax
        self.live.figure.subplots_adjust(0.1, 0.24, 0.98, 0.92)
        ax.imshow(yellowtargets()[0])
        (self._bin,) = ax.plot([], [], "x", color="#1f77b4", ms=9, label="binary centroid")
        (self._wc,) = ax.plot([], [], "+", color="#d62728", ms=12, mew=2, label="weighted")
        (self._quad,) = ax.plot([], [], "-", color="#2ca02c", lw=1.2, label="side lines")
        (self._ctr,) = ax.plot([], [], "o", mfc="none", color="k", ms=7, label="diagonals")
        # below the image, off the data
        ax.legend(fontsize=7, loc="upper center", bbox_to_anchor=(0.5, -0.1), ncol=4)
        self.report = None
        self._finish()

    def draw(self, index, zoom) -> str:
        index = int(round(index))               # the slider's value is a float
        self.report = rep = target_report(index)
        tg = rep["target"]
        self._bin.set_data([tg.binary[0]], [tg.binary[1]])
        self._wc.set_data([tg.weighted[0]], [tg.weighted[1]])
        q = np.vstack([tg.corners, tg.corners[:1], tg.corners[2:3], tg.corners[1:2],
                       tg.corners[3:4]])
        self._quad.set_data(q[:, 0], q[:, 1])
        self._ctr.set_data([tg.centre[0]], [tg.centre[1]])
        half = 60.0 / zoom
        self.ax.set(xlim=(tg.weighted[0] - half, tg.weighted[0] + half),
                    ylim=(tg.weighted[1] + half, tg.weighted[1] - half))
        self.live.invalidate()  # nothing is animated: the markers and the limits are the background
        return rep["html"]


def grey(rgb) -> np.ndarray:
    """0.299 R + 0.587 G + 0.114 B as float (the block matcher's grey conversion)."""
    return np.asarray(rgb, float)[..., :3] @ np.array([0.299, 0.587, 0.114])


def lsm_real_patches(n: int = 30, half: int = 7, seed: int = 0, min_std: float = 8.0):
    """Textured patches of the left motorcycle image on smooth ground truth: (col, row) list.

    A patch qualifies when the ground truth is known on all its pixels and varies by less
    than 1 px across it (the affine model fits) and its grey values vary (σ ≥ ``min_std``).
    """
    from photolib.data import motorcycle

    m = motorcycle()
    L, gt = grey(m.left), m.disparity
    rng = np.random.default_rng(seed)
    out = []
    for _ in range(40 * n):
        c, r = int(rng.integers(80, L.shape[1] - 20)), int(rng.integers(20, L.shape[0] - 20))
        win = gt[r - half:r + half + 1, c - half:c + half + 1]
        if (np.isfinite(win).all() and np.ptp(win) < 1.0
                and L[r - half:r + half + 1, c - half:c + half + 1].std() >= min_std):
            out.append((c, r))
            if len(out) == n:
                break
    return out


@functools.lru_cache(maxsize=4)
def lsm_real_report(n: int = 30, half: int = 7, seed: int = 0) -> dict:
    """LSM of real motorcycle patches, started at the rounded ground truth, against it.

    Returns a dict: ``errors`` (k, 2) LSM position − truth (col: ``c − d_gt``, row: r), px,
    ``std`` (k, 2) LSM's own σ of a0, b0, ``sigma0`` (k,), the patches, and statistics.
    """
    from photolib.data import motorcycle

    m = motorcycle()
    L, R, gt = grey(m.left), grey(m.right), m.disparity
    errs, std, s0, used = [], [], [], []
    for c, r in lsm_real_patches(n, half, seed):
        f = L[r - half:r + half + 1, c - half:c + half + 1]
        try:
            res = least_squares_matching(f, R, (float(c - round(gt[r, c])), float(r)))
        except (ValueError, ConvergenceError):
            continue
        errs.append((res.params[0] - (c - gt[r, c]), res.params[3] - r))
        std.append(res.std[[0, 3]])
        s0.append(res.sigma0)
        used.append((c, r))
    e = np.array(errs)
    med = np.median(e[:, 0])
    return {"errors": e, "std": np.array(std), "sigma0": np.array(s0), "patches": used,
            "rms": np.sqrt(np.mean(e**2, axis=0)), "nmad": 1.4826 * np.median(np.abs(e[:, 0] - med)),
            "median_std": np.median(np.array(std), axis=0), "attempted": n}


@functools.lru_cache(maxsize=2)
def feature_matches(detector: str = "auto", scale: int = 2, ratio: float = 0.8):
    """Features of the two Eiffel views (OpenCV measures), matched with Lowe's ratio test.

    Returns ``(name, x1, x2, img1, img2)``: the detector used ("SIFT" if ``cv2.SIFT_create``
    exists, else "ORB"), the matched (col, row) in each image (down-sampled by ``scale``).
    """
    import cv2

    from photolib.data import eiffel

    e = eiffel()
    a = cv2.cvtColor(e[0], cv2.COLOR_RGB2GRAY)[::scale, ::scale]
    b = cv2.cvtColor(e[1], cv2.COLOR_RGB2GRAY)[::scale, ::scale]
    use_sift = detector == "SIFT" or (detector == "auto" and hasattr(cv2, "SIFT_create"))
    if use_sift:
        det, norm, name = cv2.SIFT_create(nfeatures=800), cv2.NORM_L2, "SIFT"
    else:
        det, norm, name = cv2.ORB_create(nfeatures=1500), cv2.NORM_HAMMING, "ORB"
    k1, d1 = det.detectAndCompute(a, None)
    k2, d2 = det.detectAndCompute(b, None)
    pairs = cv2.BFMatcher(norm).knnMatch(d1, d2, k=2)
    good = [p[0] for p in pairs if len(p) == 2 and p[0].distance < ratio * p[1].distance]
    x1 = np.array([k1[m.queryIdx].pt for m in good])
    x2 = np.array([k2[m.trainIdx].pt for m in good])
    return name, x1, x2, a, b


def draws_until_clean(inliers, sample_size: int, runs: int = 2000, seed: int = 0) -> np.ndarray:
    """For ``runs`` random sequences of samples: the number of draws until the first sample of
    ``sample_size`` observations that are all inliers (the count needed in practice)."""
    inliers = np.asarray(inliers, bool)
    rng = np.random.default_rng(seed)
    n = len(inliers)
    out = np.empty(runs, int)
    for k in range(runs):
        t = 0
        while True:
            t += 1
            if inliers[rng.choice(n, sample_size, replace=False)].all():
                break
        out[k] = t
    return out


def plot_matches(img1, img2, x1, x2, inliers, title=""):
    """The two images side by side with the inlier (green) and outlier (red) matches."""
    import matplotlib.pyplot as plt

    h = max(img1.shape[0], img2.shape[0])
    canvas = np.zeros((h, img1.shape[1] + img2.shape[1]))
    canvas[:img1.shape[0], :img1.shape[1]] = img1
    canvas[:img2.shape[0], img1.shape[1]:] = img2
    fig, ax = plt.subplots(figsize=(9, 3.6))
    ax.imshow(canvas, cmap="gray")
    off = img1.shape[1]
    for ok, col in ((False, "#d62728"), (True, "#2ca02c")):
        sel = np.asarray(inliers) == ok
        ax.plot(np.vstack([x1[sel, 0], x2[sel, 0] + off]), np.vstack([x1[sel, 1], x2[sel, 1]]),
                color=col, lw=0.5, alpha=0.7)
    ax.set(title=title, xticks=[], yticks=[])
    return finished(fig)


@functools.lru_cache(maxsize=1)
def dense_report(scale: int = 2, half: int = 3) -> dict:
    """Block matching (photolib) and OpenCV's SGBM on the motorcycle pair vs the ground truth.

    Both at 1/``scale`` resolution (the ground truth divided by ``scale``); returns the
    maps, the ground truth and :class:`photolib.dense.DisparityErrors` of each.
    """
    import cv2

    from photolib.data import motorcycle
    from photolib.dense import block_matching, disparity_errors

    m = motorcycle()
    L, R = m.left[::scale, ::scale], m.right[::scale, ::scale]
    gt = m.disparity[::scale, ::scale] / scale
    d_max = int(np.ceil(np.nanmax(gt))) + 4
    bm = block_matching(L, R, 0, d_max, half)
    k = 2 * half + 1
    n_disp = 16 * int(np.ceil((d_max + 1) / 16))
    sgbm = cv2.StereoSGBM_create(minDisparity=0, numDisparities=n_disp, blockSize=k,
                                 P1=8 * k * k, P2=32 * k * k, uniquenessRatio=5)
    gl, gr = (cv2.cvtColor(np.ascontiguousarray(im), cv2.COLOR_RGB2GRAY) for im in (L, R))
    sg = sgbm.compute(gl, gr).astype(float) / 16.0
    sg[sg < 0] = np.nan
    return {"bm": bm, "sgbm": sg, "truth": gt, "bm_errors": disparity_errors(bm, gt),
            "sgbm_errors": disparity_errors(sg, gt), "d_max": d_max}


def plot_dense(rep):
    """Ground truth, photolib's block matching and OpenCV's SGBM, same colour scale."""
    import matplotlib.pyplot as plt

    fig, axs = plt.subplots(1, 3, figsize=(10, 2.6))
    vmax = float(np.nanmax(rep["truth"]))
    for ax, key, t in zip(axs, ("truth", "bm", "sgbm"),
                          ("ground truth", "photolib block matching (SAD)", "OpenCV SGBM")):
        ax.imshow(rep[key], vmin=0, vmax=vmax, cmap="viridis")
        ax.set(title=t, xticks=[], yticks=[])
    return finished(fig)
