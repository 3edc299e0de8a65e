"""Chapter 07 on a real photograph: the church's aisle wall, its measured window corners,
a zoom/pick widget and the figures of its rectification.

The photograph is ``church.png`` of mvtb-data (:func:`photolib.data.church`). The left
corners of the glass of the wall's five large windows were measured once
(``photolib/data/church_windows.json``): approximate positions picked by hand, refined by
OpenCV's ``cv2.cornerSubPix`` (OpenCV measures, photolib does the photogrammetry).
:func:`measure` repeats that refinement, so the committed numbers can be checked.

The façade system (Fassadensystem) is not in metres: the church's dimensions are not
published. X counts window spacings (window k's left glass edge at X = k), Y is 0 at the
bottom of the glass and up; the glass height in spacings comes from the photograph itself
(chapter 07, "How high are the windows?").
"""

from __future__ import annotations

import functools
import json
from importlib import resources

import ipywidgets as widgets
import numpy as np

from photolib.nb.live import Explorer, LiveFigure, finished, slider

__all__ = ["CORNERS", "WindowZoom", "church_photo", "facade_points", "render_fiducial", "measure", "measurements",
           "plot_measured", "plot_rectified", "zoom_report"]

#: the measured corners, in the order of the JSON file: window k top-left is 2k, bottom-left 2k + 1
CORNERS = tuple(f"window {k} {corner}" for k in range(5) for corner in ("top-left", "bottom-left"))


@functools.cache
def _json() -> dict:
    return json.loads(resources.files("photolib.data").joinpath("church_windows.json")
                      .read_text(encoding="utf-8"))


def measurements():
    """``(approx, refined)``: the picked and the refined corner positions, (10, 2) (col, row) px.

    >>> approx, refined = measurements()
    >>> approx.shape, float(np.abs(refined - approx).max()) < 3
    ((10, 2), True)
    """
    data = _json()
    return (np.array(data["approx_px"], dtype=float).reshape(-1, 2),
            np.array(data["refined_px"], dtype=float).reshape(-1, 2))


def measure(image, approx=None) -> np.ndarray:
    """Refine corner positions with ``cv2.cornerSubPix`` as the JSON file records it.

    Parameters
    ----------
    image : ndarray, (H, W, 3) uint8 RGB or (H, W) grey
    approx : array_like, shape (N, 2), optional
        Start positions (col, row) px; default the committed picked positions.

    Returns
    -------
    ndarray, shape (N, 2)
        Refined (col, row) px, not rounded.
    """
    import cv2

    start = measurements()[0] if approx is None else np.asarray(approx, dtype=float)
    grey = cv2.cvtColor(image, cv2.COLOR_RGB2GRAY) if image.ndim == 3 else image
    crit = (cv2.TERM_CRITERIA_EPS + cv2.TERM_CRITERIA_MAX_ITER, 100, 1e-4)
    p = start.reshape(-1, 1, 2).astype(np.float32).copy()
    return cv2.cornerSubPix(grey, p, (3, 3), (-1, -1), crit).reshape(-1, 2).astype(float)


def facade_points(height: float) -> np.ndarray:
    """Façade coordinates (X, Y) of the ten corners: window k top-left (k, height), bottom-left (k, 0).

    >>> facade_points(0.5)[:4].tolist()
    [[0.0, 0.5], [0.0, 0.0], [1.0, 0.5], [1.0, 0.0]]
    """
    h = float(height)
    if not (np.isfinite(h) and h > 0):
        raise ValueError(f"the glass height must be a positive number of spacings, got {height!r}")
    return np.array([[k, y] for k in range(5) for y in (h, 0.0)], dtype=float)


@functools.cache
def church_photo() -> np.ndarray:
    """The photograph, ``photolib.data.church().images[0]`` (851 × 1280 × 3 uint8), read once."""
    from photolib import data

    return data.church().images[0]


# -- the zoom / pick widget -----------------------------------------------------------------------

def zoom_report(image, corner: int = 0, half: int = 12) -> dict:
    """The crop of ``image`` around one measured corner, and its numbers.

    Returns a dict with ``crop`` (rows, cols[, 3]), ``extent`` (matplotlib, pixel
    coordinates, centres at integers), ``approx`` and ``refined`` (2,) and ``html``.
    """
    approx, refined = measurements()
    k = int(corner)
    if not 0 <= k < len(CORNERS):
        raise ValueError(f"corner must be 0…{len(CORNERS) - 1}, got {corner!r}")
    h = int(half)
    if h < 3:
        raise ValueError(f"half must be ≥ 3 px, got {half!r}")
    c, r = np.round(approx[k]).astype(int)
    rows, cols = image.shape[:2]
    r0, r1, c0, c1 = max(r - h, 0), min(r + h + 1, rows), max(c - h, 0), min(c + h + 1, cols)
    crop = image[r0:r1, c0:c1]
    extent = (c0 - 0.5, c1 - 0.5, r1 - 0.5, r0 - 0.5)
    shift = refined[k] - approx[k]
    html = (f"<b>{CORNERS[k]}</b><br>picked: ({approx[k, 0]:.0f}, {approx[k, 1]:.0f}) px<br>"
            f"cornerSubPix: ({refined[k, 0]:.2f}, {refined[k, 1]:.2f}) px<br>"
            f"moved by ({shift[0]:+.2f}, {shift[1]:+.2f}) px<br>"
            f"zoom window: {c1 - c0} × {r1 - r0} px")
    return {"crop": crop, "extent": extent, "approx": approx[k], "refined": refined[k],
            "html": html}


class WindowZoom(Explorer):
    """Pick a measured corner and zoom in: the picked (×) and refined (+) positions on the pixels."""

    title = "measured window corners: zoom and pick"

    def __init__(self, image=None, corner: int = 4, half: int = 12):
        self.image = church_photo() if image is None else np.asarray(image)
        self.controls = {
            "corner": widgets.Dropdown(options=[(name, i) for i, name in enumerate(CORNERS)],
                                       value=int(corner), description="corner"),
            "half": slider("zoom: half width [px]", half, 4, 40, 1, fmt=".0f"),
        }
        self.live = LiveFigure((3.4, 3.4))
        ax = self.live.figure.add_subplot()
        self.live.figure.subplots_adjust(0.2, 0.13, 0.96, 0.88)
        rep = zoom_report(self.image, corner, half)
        self._ax = ax
        self._crop = ax.imshow(rep["crop"], extent=rep["extent"], interpolation="nearest")
        (self._approx,) = ax.plot([], [], "x", color="#ff7f0e", ms=10, mew=2)
        (self._refined,) = ax.plot([], [], "+", color="#d62728", ms=14, mew=2)
        ax.set(xlabel="col [px]", ylabel="row [px]", title="× picked, + refined")
        ax.grid(False)
        self.report = None
        self._finish()

    def draw(self, corner, half) -> str:
        self.report = rep = zoom_report(self.image, corner, int(half))
        self._crop.set_data(rep["crop"])
        self._crop.set_extent(rep["extent"])
        self._ax.set_xlim(rep["extent"][0], rep["extent"][1])
        self._ax.set_ylim(rep["extent"][2], rep["extent"][3])
        self._approx.set_data([rep["approx"][0]], [rep["approx"][1]])
        self._refined.set_data([rep["refined"][0]], [rep["refined"][1]])
        self.live.invalidate()  # the image and the limits are part of the background
        return rep["html"]


# -- static figures --------------------------------------------------------------------------

def plot_measured(image, points, window=None):
    """Static figure: the photograph with the measured corners (numbered) and, optionally, the
    rectified area's outline ``window`` (N, 2) (col, row)."""
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(6.4, 4.3))
    ax.imshow(image)
    P = np.asarray(points, dtype=float)
    ax.plot(*P.T, "+", color="#d62728", ms=10, mew=1.5)
    for i, (c, r) in enumerate(P):
        ax.text(c - 14, r + (14 if i % 2 else -6), str(i), color="#d62728", fontsize=8)
    if window is not None:
        W = np.asarray(window, dtype=float)
        ax.plot(*np.vstack([W, W[:1]]).T, "--", color="#1f77b4", lw=1)
    ax.set(title="church.png (mvtb-data) · measured glass corners", xlabel="col [px]",
           ylabel="row [px]")
    ax.grid(False)
    fig.tight_layout()
    return finished(fig)


def plot_rectified(images, extent, points):
    """Static figure: rectified images (title, array) one above the other in façade units, with the
    control points' façade positions."""
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(len(images), 1, figsize=(6.4, 1.9 * len(images)), sharex=True)
    P = np.asarray(points, dtype=float)
    for ax, (name, img) in zip(np.atleast_1d(axes), images):
        ax.imshow(np.clip(img, 0, 255).astype(np.uint8), extent=extent)
        ax.plot(*P.T, "+", color="#d62728", ms=7)
        ax.set(title=name, ylabel="Y [spacings]")
        ax.grid(False)
    np.atleast_1d(axes)[-1].set_xlabel("X [window spacings]")
    fig.tight_layout()
    return finished(fig)


# -- a scanned fiducial mark ------------------------------------------------------------------

def render_fiducial(centre, shape=(21, 21), radius_px: float = 2.5, noise: float = 4.0,
                    seed: int = 0, oversample: int = 8) -> np.ndarray:
    """A scanned fiducial mark (Rahmenmarke): a bright dot of radius ``radius_px`` on dark film.

    The dot is integrated over each pixel (``oversample``² sub-samples), so its grey-value
    centroid is at ``centre`` = (col, row) px up to the sampling; then Gaussian grey-value
    noise σ = ``noise`` (seeded) is added. Grey values 20 (film) to 220 (dot), float.
    """
    rows, cols = (int(v) for v in shape)
    c0, r0 = (float(v) for v in centre)
    if not (0 <= c0 <= cols - 1 and 0 <= r0 <= rows - 1):
        raise ValueError(f"centre {centre!r} lies outside the patch of shape {shape!r}")
    k = int(oversample)
    fine_r = (np.arange(rows * k) + 0.5) / k - 0.5        # sub-sample centres, px
    fine_c = (np.arange(cols * k) + 0.5) / k - 0.5
    inside = (fine_c[None, :] - c0) ** 2 + (fine_r[:, None] - r0) ** 2 <= radius_px ** 2
    inside = inside.reshape(rows, k, cols, k)
    cover = inside.mean(axis=(1, 3))
    rng = np.random.default_rng(seed)
    return 20.0 + 200.0 * cover + rng.normal(0.0, noise, (rows, cols))
