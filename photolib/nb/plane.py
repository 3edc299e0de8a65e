"""Chapter 07 pictures and widgets: plane transformations and plane rectification (Entzerrung).

The numbers behind every widget are plain functions (:func:`projective_report`,
:func:`rectification_report`) that the widgets call and the tests call directly. The demo
image is synthetic and deterministic: a façade of 8 m × 6 m with twelve windows and a door,
seen obliquely (a known projective map), so the true rectification is known.
"""

from __future__ import annotations

import ipywidgets as widgets
import numpy as np

from photolib.nb.live import Explorer, LiveFigure, finished, label_width, slider
from photolib.nb.text import matrix_html
from photolib.rectify import rectify_image
from photolib.transforms import (
    AffineTransform,
    BilinearTransform,
    HelmertTransform,
    ProjectiveTransform,
)

__all__ = [
    "FACADE",
    "MODELS",
    "ProjectiveExplorer",
    "RectificationExplorer",
    "classify",
    "control_points",
    "facade_image",
    "facade_texture",
    "plot_control_points",
    "plot_rectifications",
    "plot_residuals",
    "plot_transformed_grids",
    "projective_report",
    "rectification_report",
    "square_grid",
]

#: façade extent in the object plane (X from 0 to 8 m, Y from 0 to 6 m)
FACADE = (8.0, 6.0)
#: size (rows, cols) of the synthetic oblique photograph
IMAGE_SHAPE = (120, 160)
#: true object → pixel homography of the synthetic photograph (façade seen from the left)
_TRUE = ProjectiveTransform.from_estimate(
    [[0.0, 0.0], [8.0, 0.0], [8.0, 6.0], [0.0, 6.0]],
    [[8.0, 112.0], [152.0, 98.0], [150.0, 18.0], [6.0, 4.0]])
#: the transformation families compared, by name
#: (col, row) ↔ (col, −row): pixel rows point down, the object's Y up
_FLIP = AffineTransform(b2=-1.0)
MODELS = {"Helmert": HelmertTransform, "affine": AffineTransform,
          "bilinear": BilinearTransform, "projective": ProjectiveTransform}


def square_grid(n: int = 9, samples: int = 21, half: float = 1.0):
    """Lines of a square grid over [−half, half]², densely sampled (curvature shows).

    Returns
    -------
    list of ndarray, each shape (samples, 2)

    >>> len(square_grid(5)), square_grid(5)[0].shape
    (10, (21, 2))
    """
    t = np.linspace(-half, half, samples)
    lines = [np.column_stack([np.full(samples, u), t]) for u in np.linspace(-half, half, n)]
    return lines + [np.column_stack([t, np.full(samples, v)]) for v in np.linspace(-half, half, n)]


def _joined(lines) -> np.ndarray:
    """Polylines (each (k, 2)) as one NaN-separated (K, 2) array: one artist, not one each.

    >>> _joined([np.zeros((2, 2)), np.ones((1, 2))]).tolist()
    [[0.0, 0.0], [0.0, 0.0], [nan, nan], [1.0, 1.0], [nan, nan]]
    """
    gap = np.full((1, 2), np.nan)
    return np.concatenate([part for line in lines for part in (np.asarray(line, float), gap)])


def classify(a1, a2, b1, b2, c1, c2, tol: float = 1e-12) -> str:
    """Smallest family of ``X = (a0 + a1x + a2y)/(1 + c1x + c2y)``, … that holds the map.

    >>> classify(1, 0, 0, 1, 0, 0), classify(2, 0, 0, 1, 0, 0), classify(1, 0, 0, 1, 0.1, 0)
    ('Helmert', 'affine', 'projective')
    """
    if abs(c1) > tol or abs(c2) > tol:
        return "projective"
    if abs(a1 - b2) <= tol and abs(a2 + b1) <= tol:
        return "Helmert"
    return "affine"


def projective_report(a0=0.0, a1=1.0, a2=0.0, b0=0.0, b1=0.0, b2=1.0, c1=0.0, c2=0.0,
                      n: int = 9) -> dict:
    """A square grid deformed by the projective transformation (Luhmann 2.18).

    Parameters
    ----------
    a0, a1, a2, b0, b1, b2, c1, c2 : float
        ``X = (a0 + a1x + a2y)/(1 + c1x + c2y)``, ``Y = (b0 + b1x + b2y)/(1 + c1x + c2y)``
        on the square [−1, 1]² (unitless).

    Returns
    -------
    dict
        ``transform``; ``kind`` ('Helmert', 'affine' or 'projective'); ``lines`` (list of
        (k, 2) arrays, points where the denominator is ≤ 0.05 set to NaN); ``horizon``:
        two points of the vanishing line 1 + c1x + c2y = 0 in the source plane or None;
        ``html``.

    Examples
    --------
    >>> rep = projective_report(c1=0.3)
    >>> rep["kind"], rep["horizon"][0].round(4).tolist()
    ('projective', [-3.3333, -10.0])
    >>> projective_report(a1=0.8, a2=-0.6, b1=0.6, b2=0.8)["kind"]
    'Helmert'
    """
    t = ProjectiveTransform(a0=a0, a1=a1, a2=a2, b0=b0, b1=b1, b2=b2, c1=c1, c2=c2)
    kind = classify(a1, a2, b1, b2, c1, c2)
    lines = []
    for line in square_grid(n):
        den = 1.0 + c1 * line[:, 0] + c2 * line[:, 1]
        out = t._forward(line) if np.all(den > 0.05) else _guarded(t, line, den)
        lines.append(out)
    horizon = None
    if abs(c1) > 1e-12 or abs(c2) > 1e-12:
        d = np.array([-c2, c1]) / np.hypot(c1, c2)          # direction of the line
        p = -np.array([c1, c2]) / (c1 * c1 + c2 * c2)       # its point nearest the origin
        horizon = np.array([p - 10 * d, p + 10 * d])
    names = {"Helmert": "Helmert / Ähnlichkeitstransformation (4 parameters)",
             "affine": "affine / Affintransformation (6 parameters)",
             "projective": "projective / Projektivtransformation (8 parameters)"}
    rule = {"Helmert": "c1 = c2 = 0, a1 = b2, a2 = −b1",
            "affine": "c1 = c2 = 0: parallels stay parallel",
            "projective": "c1, c2 ≠ 0: parallels meet on the vanishing line "
                          "1 + c1·x + c2·y = 0"}[kind]
    html = (f"<p><b>{names[kind]}</b><br>{rule}</p>"
            + matrix_html(t.matrix, "H = [[a1, a2, a0], [b1, b2, b0], [c1, c2, 1]]", 3))
    return {"transform": t, "kind": kind, "lines": lines, "horizon": horizon, "html": html}


def _guarded(t, line, den):
    out = t._forward(np.where(den[:, None] > 0.05, line, 0.0))
    out[den <= 0.05] = np.nan
    return out


class ProjectiveExplorer(Explorer):
    """Sliders for the 8 projective parameters deforming a square grid.

    The text names the smallest family (Helmert, affine, projective) that holds the map:
    c1 and c2 are the two parameters that make it projective.
    """

    title = "projective transformation explorer"

    def __init__(self, a0=0.0, a1=1.0, a2=0.0, b0=0.0, b1=0.0, b2=1.0, c1=0.15, c2=0.0):
        self.controls = {
            "a0": slider("a0 (shift X)", a0, -1, 1, 0.05, fmt=".2f"),
            "a1": slider("a1", a1, -2, 2, 0.05, fmt=".2f"),
            "a2": slider("a2", a2, -2, 2, 0.05, fmt=".2f"),
            "b0": slider("b0 (shift Y)", b0, -1, 1, 0.05, fmt=".2f"),
            "b1": slider("b1", b1, -2, 2, 0.05, fmt=".2f"),
            "b2": slider("b2", b2, -2, 2, 0.05, fmt=".2f"),
            "c1": slider("c1 (projective)", c1, -0.45, 0.45, 0.01, fmt=".2f"),
            "c2": slider("c2 (projective)", c2, -0.45, 0.45, 0.01, fmt=".2f"),
        }
        self.live = LiveFigure((4.2, 3.6))
        ax = self.live.figure.add_subplot()
        self.live.figure.subplots_adjust(0.12, 0.12, 0.97, 0.92)
        grid = square_grid()
        ax.plot(*_joined(grid).T, color="0.85", lw=0.8)
        self._lines = [self.live.animate(ax.plot([], [], color="#1f77b4", lw=1)[0])
                       for _ in grid]
        (self._horizon,) = ax.plot([], [], "--", color="#d62728", lw=1)
        self.live.animate(self._horizon)
        ax.set(xlim=(-2.5, 2.5), ylim=(-2.5, 2.5), aspect="equal", xlabel="x → X",
               ylabel="y → Y", title="grey (x, y) · blue (X, Y) · red: vanishing line")
        self.report = None
        self._finish()

    def draw(self, **v) -> str:
        self.report = rep = projective_report(**v)
        for artist, line in zip(self._lines, rep["lines"]):
            artist.set_data(*line.T)
        if rep["horizon"] is None:
            self._horizon.set_data([], [])
        else:
            # the vanishing line of the source plane, mapped: drawn in the source frame
            self._horizon.set_data(*rep["horizon"].T)
        return rep["html"]


# -- the synthetic façade and its rectification -------------------------------------------------

def facade_texture(XY) -> np.ndarray:
    """Grey value (0-255) of the façade at object points (…, 2) in m; 0 outside the façade.

    A plaster wall with a left-to-right brightness ramp, 4 × 3 windows and a door.

    >>> facade_texture([[0.5, 0.5], [1.5, 1.5], [9.0, 1.0]]).tolist()
    [155.0, 50.0, 0.0]
    """
    P = np.asarray(XY, dtype=float)
    X, Y = P[..., 0], P[..., 1]
    g = 150.0 + 10.0 * X
    col = np.floor((X - 1.0) / 1.8)
    row = np.floor((Y - 1.2) / 1.6)
    u, v = X - 1.0 - 1.8 * col, Y - 1.2 - 1.6 * row
    window = (col >= 0) & (col <= 3) & (row >= 0) & (row <= 2) & (u < 0.9) & (v < 0.9)
    g = np.where(window, 50.0, g)
    g = np.where((X > 3.6) & (X < 4.4) & (Y < 1.0), 90.0, g)  # the door
    inside = (X >= 0) & (X <= FACADE[0]) & (Y >= 0) & (Y <= FACADE[1])
    return np.where(inside, g, 0.0)


def facade_image(shape=IMAGE_SHAPE) -> np.ndarray:
    """The synthetic oblique photograph of the façade, grey values 0-255, shape ``shape``.

    Every pixel is traced back to the façade with the inverse of the true homography
    (2 × 2 supersampling, so the edges are anti-aliased).

    >>> img = facade_image()
    >>> img.shape, float(img.min()) >= 0.0, float(img.max()) <= 255.0
    ((120, 160), True, True)
    """
    rows, cols = shape
    sub = (np.arange(2) + 0.5) / 2 - 0.5
    c = (np.arange(cols)[:, None] + sub).ravel()
    r = (np.arange(rows)[:, None] + sub).ravel()
    cc, rr = np.meshgrid(c, r)
    obj = _TRUE.inverse(np.column_stack([cc.ravel(), rr.ravel()]))
    g = facade_texture(obj).reshape(rows, 2, cols, 2)
    return g.mean(axis=(1, 3))


def control_points(noise_px: float = 0.3, seed: int = 7):
    """Control points (Passpunkte) of the façade: object (m) and measured pixel coordinates.

    The façade corners, the outer window corners and the door: 8 points; the pixel
    coordinates are the true projection plus seeded Gaussian measurement noise.

    Returns
    -------
    obj : ndarray, shape (8, 2)
        (X, Y) in m.
    pix : ndarray, shape (8, 2)
        (col, row) in pixels.

    >>> obj, pix = control_points()
    >>> obj.shape, pix.shape
    ((8, 2), (8, 2))
    """
    obj = np.array([[0.0, 0.0], [8.0, 0.0], [8.0, 6.0], [0.0, 6.0],
                    [1.0, 5.3], [7.3, 1.2], [3.6, 1.0], [4.4, 0.0]])
    rng = np.random.default_rng(seed)
    pix = _TRUE(obj) + rng.normal(0.0, noise_px, obj.shape)
    return obj, np.round(pix, 2)


def rectification_report(dcol=0.0, drow=0.0, model="projective", point: int = 4,
                         out_shape=(48, 64), image=None, order: int = 1) -> dict:
    """Plane rectification of the façade with one control point moved.

    Parameters
    ----------
    dcol, drow : float
        Displacement of control point ``point`` in the photograph, pixels (a blunder).
    model : str
        Key of :data:`MODELS`: the transformation used for the rectified image.
    out_shape : tuple of int
        Rows, cols of the rectified image covering the façade.
    image : ndarray, optional
        The photograph (default :func:`facade_image`, cached).

    Returns
    -------
    dict
        ``pix`` (control points as measured, with the moved one); ``fits``: model name →
        transform (col, −row) → object estimated from the control points (``sigma0`` in m);
        rows point down, so the fits use −row: the Helmert transformation (a similarity)
        cannot mirror;
        ``rectified`` (out_shape); ``extent`` of the rectified image in m; ``residuals``
        (8, 2) in m of ``model``; ``html``.

    Examples
    --------
    >>> rep = rectification_report()
    >>> [round(rep["fits"][m].sigma0 * 100, 1) for m in ("Helmert", "affine", "projective")]
    [38.1, 35.6, 1.4]
    """
    if model not in MODELS:
        raise ValueError(f"model must be one of {list(MODELS)}, got {model!r}")
    obj, pix = control_points()
    pix = pix.copy()
    pix[point] += (dcol, drow)
    up = _FLIP(pix)  # (col, −row): a right-handed frame like the object's, see below
    fits = {name: cls.from_estimate(up, obj) for name, cls in MODELS.items()}
    d = FACADE[0] / (out_shape[1] - 1)
    to_pixel = _FLIP @ MODELS[model].from_estimate(obj, up)
    img = _cached_image() if image is None else image
    rect = rectify_image(img, to_pixel, out_shape, origin=(0.0, FACADE[1]), pixel_size=d,
                         order=order)
    extent = (-d / 2, FACADE[0] + d / 2, FACADE[1] - (out_shape[0] - 0.5) * d, FACADE[1] + d / 2)
    rows = "".join(
        f"<tr><td>{name}</td><td style='text-align:right'>{f.n_params}</td>"
        f"<td style='text-align:right'>{f.redundancy}</td>"
        f"<td style='text-align:right'>{f.sigma0 * 100:.1f}</td>"
        f"<td style='text-align:right'>{np.max(np.hypot(*f.residuals.T)) * 100:.1f}</td></tr>"
        for name, f in fits.items())
    html = (f"<p>control point {point} moved by ({dcol:+.1f}, {drow:+.1f}) px</p>"
            "<table style='font-family:monospace'><tr><th>model</th><th>u</th><th>r</th>"
            "<th>σ0 [cm]</th><th>max |v| [cm]</th></tr>" + rows + "</table>"
            f"<p>rectified with the <b>{model}</b> transformation "
            "(indirect method, bilinear resampling)</p>")
    return {"obj": obj, "pix": pix, "fits": fits, "rectified": rect, "extent": extent,
            "residuals": fits[model].residuals, "html": html}


_IMAGE_CACHE: dict = {}


def _cached_image():
    if "facade" not in _IMAGE_CACHE:
        _IMAGE_CACHE["facade"] = facade_image()
    return _IMAGE_CACHE["facade"]


class RectificationExplorer(Explorer):
    """Move one control point of the façade photograph; rectified image and residuals follow.

    Left: the photograph with the control points (the movable one in red). Right: the
    façade rectified with the chosen model, residual vectors × 5 at the control points.
    The text compares σ0 of Helmert, affine, bilinear and projective.
    """

    title = "plane rectification explorer"
    exaggeration = 5.0

    def __init__(self, dcol=0.0, drow=0.0, model="projective", point=4):
        self.point = int(point)
        self.controls = {
            "dcol": slider("Δcol [px]", dcol, -10, 10, 0.5),
            "drow": slider("Δrow [px]", drow, -10, 10, 0.5),
            # wide enough for the longest name ("projective" was cut at 80 px)
            "model": widgets.ToggleButtons(
                options=list(MODELS), value=model,
                style={"button_width": f"{max(label_width(m, 80) for m in MODELS) + 10}px"}),
        }
        self.live = LiveFigure((7.0, 2.9))
        ax, ax2 = self.live.figure.subplots(1, 2)
        self.live.figure.subplots_adjust(0.06, 0.17, 0.98, 0.9, wspace=0.2)
        image = _cached_image()
        ax.imshow(image, cmap="gray", vmin=0, vmax=255)
        obj, pix = control_points()
        ax.plot(*pix.T, "+", color="#2ca02c", ms=8)
        (self._moved,) = ax.plot([], [], "o", mfc="none", color="#d62728", ms=9)
        self.live.animate(self._moved)
        ax.set(title="photograph (pixels)", xticks=[0, 80, 159], yticks=[0, 60, 119])
        rep = rectification_report(dcol, drow, model, self.point)
        self._rect = ax2.imshow(rep["rectified"], cmap="gray", vmin=0, vmax=255,
                                extent=rep["extent"])
        self.live.animate(self._rect)
        (self._vectors,) = ax2.plot([], [], color="#d62728", lw=1.5)
        self.live.animate(self._vectors)
        ax2.plot(*obj.T, ".", color="#2ca02c", ms=4)
        ax2.set(xlim=(-0.5, 8.5), ylim=(-0.5, 6.5), aspect="equal", xlabel="X [m]",
                ylabel="Y [m]", title=f"rectified · residuals × {self.exaggeration:g}")
        self.report = None
        self._finish()

    def draw(self, dcol, drow, model) -> str:
        self.report = rep = rectification_report(dcol, drow, model, self.point)
        self._moved.set_data([rep["pix"][self.point, 0]], [rep["pix"][self.point, 1]])
        self._rect.set_data(rep["rectified"])
        start = rep["obj"]
        end = start + self.exaggeration * rep["residuals"]
        segs = np.stack([start, end, np.full_like(start, np.nan)], axis=1).reshape(-1, 2)
        self._vectors.set_data(*segs.T)
        return rep["html"]


# -- static figures ---------------------------------------------------------------------------

def plot_transformed_grids(models, n: int = 9):
    """Static figure: the square grid [−1, 1]² (grey) mapped by each (name, transform).

    Returns
    -------
    matplotlib.figure.Figure
    """
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(1, len(models), figsize=(2.6 * len(models), 2.8))
    for ax, (name, t) in zip(np.atleast_1d(axes), models):
        grid = square_grid(n)
        ax.plot(*_joined(grid).T, color="0.85", lw=0.8)
        ax.plot(*_joined([t(line) for line in grid]).T, color="#1f77b4", lw=1)
        ax.set(aspect="equal", title=name, xticks=[], yticks=[])
    fig.tight_layout()
    return finished(fig)


def plot_residuals(points, fits, exaggeration: float = 1.0, unit: str = "m", scale: float = 1.0):
    """Static figure: residual vectors of each estimated (name, transform) at its points.

    Parameters
    ----------
    points : array_like, shape (N, 2)
        Where to draw the vectors (destination coordinates).
    fits : sequence of (str, PlaneTransform)
        Estimated transforms (with ``residuals`` and ``sigma0``).
    exaggeration : float
        Vectors drawn this many times longer.
    unit : str
        Name of the unit of σ0 in the titles; ``scale`` converts to it.
    """
    import matplotlib.pyplot as plt

    P = np.asarray(points, dtype=float)
    fig, axes = plt.subplots(1, len(fits), figsize=(2.8 * len(fits), 2.6), sharey=True)
    for ax, (name, f) in zip(np.atleast_1d(axes), fits):
        v = f.residuals * exaggeration
        ax.plot(*P.T, ".", color="0.3")
        ax.quiver(P[:, 0], P[:, 1], v[:, 0], v[:, 1], angles="xy", scale_units="xy", scale=1,
                  color="#d62728", width=0.012)
        ax.set(aspect="equal", title=f"{name}\nσ0 = {f.sigma0 * scale:.3g} {unit}")
        ax.margins(0.15)
    fig.suptitle(f"residuals × {exaggeration:g}", fontsize=10)
    fig.tight_layout()
    return finished(fig)


def plot_control_points(image, pix, labels=True):
    """Static figure: the photograph with its control points numbered."""
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(4.0, 3.0))
    ax.imshow(image, cmap="gray", vmin=0, vmax=255)
    ax.plot(*np.asarray(pix).T, "+", color="#2ca02c", ms=9, mew=1.5)
    if labels:
        for i, (c, r) in enumerate(pix):
            ax.text(c + 2, r - 2, str(i), color="#2ca02c", fontsize=8)
    ax.set(title="photograph with control points (col, row)")
    ax.grid(False)
    return finished(fig)


def plot_rectifications(images, extent):
    """Static figure: rectified images side by side, each (title, array), in object metres."""
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(1, len(images), figsize=(2.8 * len(images), 2.5), sharey=True)
    for ax, (name, img) in zip(np.atleast_1d(axes), images):
        ax.imshow(img, cmap="gray", vmin=0, vmax=255, extent=extent)
        ax.set(title=name, xlabel="X [m]")
        ax.grid(False)
    np.atleast_1d(axes)[0].set_ylabel("Y [m]")
    fig.tight_layout()
    return finished(fig)
