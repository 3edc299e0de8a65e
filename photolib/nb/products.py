"""Chapter 12 pictures and widgets: orthophoto, true orthophoto, relief displacement, mosaic.

The chapter's scene: hilly ground (``terrain``) with three box buildings (``BUILDINGS``),
seen by a vertical aerial camera (c = 50 mm, 400 × 300 pixels of 60 µm, 300 m above the
datum). :func:`render` makes its image by casting a ray through every pixel (the ground by
iterated monoplotting, the buildings by a slab test), so every product of the chapter is
computed from an image whose truth is known.
"""

from __future__ import annotations

import numpy as np

import photolib as pl
from photolib.nb.draw import lines_xyz
from photolib.nb.live import Explorer, LiveFigure, finished, slider
from photolib.orthophoto import DTM, FrameCamera
from photolib.rectify import output_grid

__all__ = [
    "BUILDINGS", "C_MM", "ORTHO", "OrthoErrorExplorer", "ReliefExplorer", "TrueOrthoExplorer",
    "building_scene", "camera", "dsm", "dtm", "ortho_error_report", "plot_height_models",
    "plot_mosaic", "plot_ortho_map", "plot_products", "plot_relief_geometry", "relief_report", "render", "terrain",
    "texture", "true_ortho_report", "Z_REF", "zoom_span",
]

C_MM = 50.0
PIXEL_MM = 0.06
IMAGE_SIZE = (400, 300)                 # width, height in pixels
#: boxes (Xmin, Xmax, Ymin, Ymax, roof height Z) in m
BUILDINGS = ((30.0, 42.0, 58.0, 70.0, 32.0), (72.0, 86.0, 18.0, 30.0, 38.0),
             (52.0, 60.0, 38.0, 46.0, 22.0))
#: the orthophoto grid: (rows, cols), origin (X, Y of the top-left pixel centre), pixel size
ORTHO = ((180, 240), (0.25, 89.75), 0.5)


def terrain(X, Y, amplitude: float = 1.0):
    """Ground height (m) of the chapter's hills; ``amplitude`` scales the relief.

    >>> float(np.round(terrain(0.0, 0.0), 6))
    5.2
    """
    X, Y = np.asarray(X, float), np.asarray(Y, float)
    return 10.0 + amplitude * (9.0 * np.sin(X / 21.0) * np.cos(Y / 17.0) + 0.08 * (X - 60.0))


def camera(X0=(60.0, 45.0, 300.0), angles_deg=(1.5, -2.0, 5.0), distortion=True) -> FrameCamera:
    """The chapter's camera (distortion A1 = −2·10⁻⁵ mm⁻² unless ``distortion=False``).

    >>> camera().nadir.tolist()
    [60.0, 45.0]
    """
    d = pl.Distortion(A1=-2e-5) if distortion else None
    return FrameCamera(X0, pl.rotation_opk(*np.radians(angles_deg)), C_MM, *IMAGE_SIZE,
                       PIXEL_MM, distortion=d)


def dtm(amplitude: float = 1.0, spacing: float = 1.0) -> DTM:
    """The terrain as a DTM over X in [−5, 125], Y in [−5, 95] m."""
    n = int(round(130 / spacing)) + 1, int(round(100 / spacing)) + 1
    return DTM.from_function(lambda X, Y: terrain(X, Y, amplitude), (n[1], n[0]), (-5.0, 95.0),
                             spacing)


def _roofs(XY, buildings=BUILDINGS):
    Z = np.full(XY.shape[:-1], -np.inf)
    for x0, x1, y0, y1, z in buildings:
        inside = (XY[..., 0] > x0) & (XY[..., 0] < x1) & (XY[..., 1] > y0) & (XY[..., 1] < y1)
        Z = np.where(inside, z, Z)
    return Z


def dsm(spacing: float = 0.5, buildings=BUILDINGS) -> DTM:
    """Surface model: terrain and roofs, nearest-cell interpolation (vertical walls)."""
    # cell centres on the ortho pixel centres (ORTHO): X = −4.75 + k·0.5
    n = int(round(129.5 / spacing)) + 1, int(round(99.5 / spacing)) + 1
    grid = output_grid((n[1], n[0]), (-4.75, 94.75), spacing)
    Z = np.maximum(terrain(grid[..., 0], grid[..., 1]), _roofs(grid, buildings))
    return DTM(Z, (-4.75, 94.75), spacing, order=0)


def texture(P) -> np.ndarray:
    """Grey value of the scene at object points P (N, 3): fields, roads, roofs, walls."""
    P = np.asarray(P, float)
    X, Y, Z = P[..., 0], P[..., 1], P[..., 2]
    field = 110 + 45 * np.sin(X / 9.0) * np.cos(Y / 7.0)
    road = (np.abs(((X + 5) % 25) - 12.5) > 11.5) | (np.abs(((Y + 5) % 25) - 12.5) > 11.5)
    ground = np.where(road, 40.0, field)
    roof = _roofs(P[..., :2])
    on_roof = np.isfinite(roof) & (Z > roof - 1e-6)
    on_wall = np.isfinite(roof) & ~on_roof & (Z > terrain(X, Y) + 1e-3)
    grey = np.where(on_roof, 235.0 - 25.0 * (np.abs(X % 4 - 2) < 0.3), ground)
    return np.where(on_wall, 75.0, grey)


def render(cam: FrameCamera | None = None, buildings=BUILDINGS) -> np.ndarray:
    """Grey image (H, W) of the scene: ray casting through every pixel centre."""
    cam = camera() if cam is None else cam
    col, row = np.meshgrid(np.arange(cam.width, dtype=float), np.arange(cam.height, dtype=float))
    xy = pl.image_from_pixel(np.column_stack([col.ravel(), row.ravel()]), cam.width,
                             cam.height, cam.pixel_size) - [cam.x0, cam.y0]
    if cam.distortion is not None:
        xy = cam.distortion.correct(xy)
    rays = np.column_stack([xy, np.full(len(xy), -cam.c)]) @ cam.R.T
    t = np.full(len(rays), (10.0 - cam.X0[2]) / rays[:, 2])
    for _ in range(8):                      # monoplotting onto the hills, iterated
        P = cam.X0 + t[:, None] * rays
        t = (terrain(P[:, 0], P[:, 1]) - cam.X0[2]) / rays[:, 2]
    best = t
    with np.errstate(divide="ignore", invalid="ignore"):
        inv = 1.0 / rays
        for x0, x1, y0, y1, z in buildings:
            lo = (np.array([x0, y0, -50.0]) - cam.X0) * inv
            hi = (np.array([x1, y1, z]) - cam.X0) * inv
            t0 = np.nanmax(np.minimum(lo, hi), axis=1)
            t1 = np.nanmin(np.maximum(lo, hi), axis=1)
            hit = (t1 >= t0) & (t0 > 0) & (t0 < best)
            best = np.where(hit, t0, best)
    P = cam.X0 + best[:, None] * rays
    return texture(P).reshape(cam.height, cam.width)


def building_scene():
    """``(camera, image, dtm, dsm)`` of the chapter (the image rendered once)."""
    cam = camera()
    return cam, render(cam), dtm(), dsm()


# -- relief displacement --------------------------------------------------------------------------

def relief_report(h: float = 30.0, H: float = 300.0, R: float = 120.0, c: float = C_MM) -> dict:
    """Relief displacement of a tower of height h at plan distance R (m), flying height H.

    Returns r_top, r_foot, Δr (mm), the formula value ``r·Δh/H``, the ground error of a plane
    rectification ``Δr·H/c`` (m) and the html text.

    >>> rep = relief_report(30.0, 300.0, 120.0)
    >>> round(rep["dr"], 6), round(rep["formula"], 6), round(rep["ground_m"], 6)
    (2.222222, 2.222222, 13.333333)
    """
    X0 = np.array([0.0, 0.0, H])
    xy = pl.project(np.array([[R, 0.0, 0.0], [R, 0.0, h]]), X0, np.eye(3), c)
    r_foot, r_top = float(np.hypot(*xy[0])), float(np.hypot(*xy[1]))
    dr = r_top - r_foot
    formula = pl.relief_displacement(r_top, h, H)
    ground = dr * H / c
    html = (f"<p>r<sub>foot</sub> = {r_foot:.3f} mm, r<sub>top</sub> = {r_top:.3f} mm<br>"
            f"Δr = r<sub>top</sub> − r<sub>foot</sub> = <b>{dr:.3f} mm</b><br>"
            f"r<sub>top</sub>·Δh/H = {formula:.3f} mm<br>"
            f"r<sub>foot</sub>·Δh/H = {r_foot * h / H:.3f} mm (too small: the foot's r "
            "needs H − Δh)<br>"
            f"on the ground (plane rectification): Δr·H/c = <b>{ground:.2f} m</b></p>")
    return {"r_top": r_top, "r_foot": r_foot, "dr": dr, "formula": formula, "ground_m": ground,
            "html": html}


def _relief_lines(h, H, R, c, exaggerate):
    """Side view: the two rays from the (positive) image plane through X0 to foot and top.

    The image plane is drawn ``exaggerate`` times enlarged below the projection centre
    (positive image, at distance c·exaggerate), so r_foot and r_top can be told apart.
    """
    f = exaggerate * c / 1000.0                           # drawn image distance, m
    img_z = H - f
    foot_x, top_x = R * f / H, R * f / (H - h)
    rays = np.array([[[0.0, H], [R, 0.0]], [[0.0, H], [R, h]]])
    return rays, np.array([[R, 0.0], [R, h]]), np.array([foot_x, top_x]), img_z


def _image_axis(ax, c=C_MM):
    ax.set(xlim=(0, 60), ylim=(-1, 1), yticks=[], xlabel="r in the image [mm]",
           title="image: r_foot (blue), r_top (red)")
    ax.axhline(0, color="0.4", lw=1)


#: spans of the zoomed image axis, mm: r − r_foot from −span/4 to span
_ZOOM_SPANS = (0.5, 1.0, 2.0, 2.5, 5.0, 10.0, 20.0, 25.0, 50.0, 100.0, 200.0, 250.0)


def zoom_span(dr: float) -> float:
    """The span (mm) of the zoomed image axis for a displacement ``dr``: the smallest of
    ``_ZOOM_SPANS`` that holds 1.25·dr, so that Δr fills at most 80 % of it.

    >>> zoom_span(2.222), zoom_span(0.0), zoom_span(170.0)
    (5.0, 0.5, 250.0)
    """
    need = 1.25 * abs(float(dr))
    return next((s for s in _ZOOM_SPANS if s >= need), _ZOOM_SPANS[-1] * 2)


def _zoom_axis(ax, span):
    """The image radius around the foot, magnified: the relief displacement Δr fills it."""
    ax.set(xlim=(-0.25 * span, span), ylim=(-1, 2.4), yticks=[], xlabel="r − r_foot [mm]",
           title="zoom: Δr = r_top − r_foot")
    ax.axhline(0, color="0.4", lw=1)


def plot_relief_geometry(h=30.0, H=300.0, R=120.0, c=C_MM, exaggerate=1500.0):
    """Side view of the relief displacement, the two image points on the image radius, and
    the same radius magnified around the foot (a few mm on the whole radius are a few pixels
    of the figure; the zoom shows them)."""
    import matplotlib.pyplot as plt

    rep = relief_report(h, H, R, c)
    rays, tower, xs, img_z = _relief_lines(h, H, R, c, exaggerate)
    fig, (ax, bx, zx) = plt.subplots(3, 1, figsize=(6.0, 5.0), height_ratios=(4, 1, 1))
    ax.plot([-20, R + 60], [0, 0], color="#8c564b", lw=2, label="reference plane")
    ax.plot(*tower.T, color="0.2", lw=4, label=f"tower, Δh = {h:g} m")
    for (a, b), colour, name in zip(rays, ("#1f77b4", "#d62728"), ("foot", "top")):
        ax.plot([a[0], b[0]], [a[1], b[1]], color=colour, lw=1, label=f"ray to the {name}")
    ax.plot([0, xs.max() * 1.4], [img_z, img_z], color="0.4", lw=1, label="image plane (enlarged)")
    ax.plot(0, H, "k^", ms=7, label="projection centre")
    ax.set(xlabel="X [m]", ylabel="Z [m]", title="relief displacement / radiale Versetzung")
    # beside the axes: inside, it would cover the rays
    ax.legend(fontsize=7, loc="upper left", bbox_to_anchor=(1.01, 1.0), borderaxespad=0)
    _image_axis(bx, c)
    bx.plot([rep["r_foot"]], [0], "o", color="#1f77b4")
    bx.plot([rep["r_top"]], [0], "o", color="#d62728")
    _zoom_axis(zx, zoom_span(rep["dr"]))
    zx.plot([0.0], [0], "o", color="#1f77b4")
    zx.plot([rep["dr"]], [0], "o", color="#d62728")
    zx.annotate("", (rep["dr"], 0.7), (0.0, 0.7), arrowprops={"arrowstyle": "<->", "lw": 1})
    zx.text(0.5 * rep["dr"], 1.0, f"Δr = {rep['dr']:.2f} mm", ha="center", va="bottom",
            fontsize=8)
    fig.tight_layout()
    return finished(fig)


class ReliefExplorer(Explorer):
    """Tower height, flying height and distance → relief displacement, drawn and in numbers."""

    title = "relief displacement explorer"
    exaggerate = 1500.0

    def __init__(self, h=30.0, H=300.0, R=120.0):
        self.controls = {"h": slider("tower Δh [m]", h, 0, 100, 1, fmt=".0f"),
                         "H": slider("flying H [m]", H, 150, 600, 10, fmt=".0f"),
                         "R": slider("distance R [m]", R, 0, 250, 5, fmt=".0f")}
        self.live = LiveFigure((5.6, 4.6))
        fig = self.live.figure
        gs = fig.add_gridspec(3, 1, height_ratios=(4, 1, 1))
        ax, bx = fig.add_subplot(gs[0]), fig.add_subplot(gs[1])
        zx = self._zoom = fig.add_subplot(gs[2])
        fig.subplots_adjust(0.13, 0.1, 0.98, 0.94, hspace=0.95)
        ax.plot([-20, 320], [0, 0], color="#8c564b", lw=2)
        ax.set(xlim=(-20, 320), ylim=(-20, 640), xlabel="X [m]", ylabel="Z [m]",
               title=f"side view (image plane ×{self.exaggerate:g})")
        _image_axis(bx)
        bx.set(xlim=(0, 250 * C_MM / 60.0))
        self._span = None
        (self._tower,) = ax.plot([], [], color="0.2", lw=4)
        (self._ray_foot,) = ax.plot([], [], color="#1f77b4", lw=1)
        (self._ray_top,) = ax.plot([], [], color="#d62728", lw=1)
        (self._plane,) = ax.plot([], [], color="0.4", lw=1)
        (self._centre,) = ax.plot([], [], "k^", ms=7)
        (self._foot,) = bx.plot([], [], "o", color="#1f77b4")
        (self._top,) = bx.plot([], [], "o", color="#d62728")
        # the zoom: r − r_foot, the foot at 0, Δr between the two points
        (self._zoom_foot,) = zx.plot([0.0], [0.0], "o", color="#1f77b4")
        (self._zoom_top,) = zx.plot([], [], "o", color="#d62728")
        (self._zoom_bar,) = zx.plot([], [], color="0.2", lw=1, marker="|", ms=6)
        self._zoom_text = zx.text(0.0, 1.0, "", ha="center", va="bottom", fontsize=8)
        for a in (self._tower, self._ray_foot, self._ray_top, self._plane, self._centre,
                  self._foot, self._top, self._zoom_top, self._zoom_bar, self._zoom_text):
            self.live.animate(a)
        self.report = None
        self._finish()

    def _set_span(self, dr) -> None:
        """Rescale the zoom only when Δr outgrows it or shrinks below a tenth of it: a new
        scale means a full redraw (new ticks), a blitted update is several times cheaper."""
        span = zoom_span(dr)
        if self._span is not None and span <= self._span and 1.25 * dr >= 0.1 * self._span:
            return
        self._span = span
        _zoom_axis(self._zoom, span)
        self.live.invalidate()

    def draw(self, h, H, R) -> str:
        h = min(h, H - 10.0)
        self.report = rep = relief_report(h, H, R)
        rays, tower, xs, img_z = _relief_lines(h, H, R, C_MM, self.exaggerate)
        self._tower.set_data(*tower.T)
        self._ray_foot.set_data(*rays[0].T)
        self._ray_top.set_data(*rays[1].T)
        self._plane.set_data([0, max(xs.max() * 1.4, 20.0)], [img_z, img_z])
        self._centre.set_data([0], [H])
        self._foot.set_data([rep["r_foot"]], [0])
        self._top.set_data([rep["r_top"]], [0])
        self._set_span(rep["dr"])
        self._zoom_top.set_data([rep["dr"]], [0])
        self._zoom_bar.set_data([0.0, rep["dr"]], [0.7, 0.7])
        self._zoom_text.set_position((0.5 * rep["dr"], 1.0))
        self._zoom_text.set_text(f"Δr = {rep['dr']:.2f} mm")
        return rep["html"]


# -- plane versus differential rectification ------------------------------------------------------

#: height of the reference plane of the plane rectification (the terrain's mean level), m
Z_REF = 10.0
_CHECK = np.stack(np.meshgrid(np.linspace(10, 110, 9), np.linspace(10, 80, 8)), -1).reshape(-1, 2)
_CONTROL = np.array([[5.0, 5.0], [115.0, 5.0], [115.0, 85.0], [5.0, 85.0]])


def ortho_error_report(phi_deg: float = 0.0, amplitude: float = 1.0) -> dict:
    """Plan errors of plane rectification and of differential rectification.

    The camera is tilted by φ; the hills are scaled by ``amplitude``. Plane rectification:
    a :class:`photolib.ProjectiveTransform` image → ground from four control points
    (Passpunkte) at the corners on the reference plane Z = ``Z_REF``; it is exact on that
    plane, whatever the tilt, and misplaces a point of height Δh above it radially from
    the ground nadir N by ``(P − N)·Δh/(H − Δh)`` (``relief``), H = Z0 − Z_REF. Differential rectification:
    the ortho pixel's ground point from the DTM (1 m, bilinear), projected.

    Returns
    -------
    dict
        ``points`` (N, 2) check points, ``plane_err`` (N, 2) m, ``diff_err`` (N, 2) m,
        ``relief`` (N, 2) the predicted error ``(P − N)·Δh/(H − Δh)``, ``html``.

    >>> rep = ortho_error_report(0.0, 0.0)
    >>> bool(np.abs(rep["plane_err"]).max() < 1e-6)
    True
    """
    cam = camera(angles_deg=(0.0, phi_deg, 0.0), distortion=False)
    def Z(XY):
        return terrain(XY[:, 0], XY[:, 1], amplitude)
    ctrl = np.column_stack([_CONTROL, np.full(len(_CONTROL), Z_REF)])
    to_ground = pl.ProjectiveTransform.from_estimate(cam.image(ctrl), _CONTROL)
    truth = np.column_stack([_CHECK, Z(_CHECK)])
    xy = cam.image(truth)
    plane_err = to_ground(xy) - _CHECK
    model = dtm(amplitude)
    # differential: the pixel at the check point takes the image point of (X, Y, Z_DTM)
    xy_dtm = cam.image(np.column_stack([_CHECK, model.height(_CHECK)]))
    # the ground point really seen there: monoplotting onto the true surface, iterated
    P = _monoplot_terrain(cam, xy_dtm, amplitude)
    diff_err = P[:, :2] - _CHECK
    H = cam.X0[2] - Z_REF
    dh = truth[:, 2] - Z_REF
    relief = (_CHECK - cam.nadir) * (dh / (H - dh))[:, None]
    pm = float(np.abs(np.hypot(*plane_err.T)).max())
    dm = float(np.abs(np.hypot(*diff_err.T)).max())
    html = (f"<p>camera tilt φ = {phi_deg:.1f}°, relief ×{amplitude:.2f} "
            f"(height range {np.ptp(truth[:, 2]):.1f} m)<br>"
            f"plane rectification (projective, 4 control points): max error "
            f"<b>{pm:.2f} m</b><br>differential rectification (DTM 1 m): max error "
            f"<b>{dm * 1000:.1f} mm</b></p>")
    return {"points": _CHECK, "plane_err": plane_err, "diff_err": diff_err, "relief": relief,
            "html": html}


def _monoplot_terrain(cam, xy, amplitude, iterations=15):
    """Ground points seen at image points ``xy``: monoplotting, iterated on the height."""
    rays = np.column_stack([xy - [cam.x0, cam.y0], np.full(len(xy), -cam.c)]) @ cam.R.T
    t = (10.0 - cam.X0[2]) / rays[:, 2]
    for _ in range(iterations):
        P = cam.X0 + t[:, None] * rays
        t = (terrain(P[:, 0], P[:, 1], amplitude) - cam.X0[2]) / rays[:, 2]
    return cam.X0 + t[:, None] * rays


class OrthoErrorExplorer(Explorer):
    """Camera tilt and terrain relief → errors of plane versus differential rectification."""

    title = "orthophoto explorer"
    scale = 5.0

    def __init__(self, phi=0.0, amplitude=1.0):
        self.controls = {"phi": slider("tilt φ [°]", phi, -15, 15, 0.5),
                         "amplitude": slider("relief ×", amplitude, 0, 3, 0.1, fmt=".1f")}
        self.live = LiveFigure((5.4, 3.4))
        ax = self.live.figure.add_subplot()
        self.live.figure.subplots_adjust(0.12, 0.14, 0.98, 0.9)
        ax.plot(*np.vstack([_CONTROL, _CONTROL[:1]]).T, "^--", color="#8c564b", ms=6, lw=0.8)
        ax.plot(*_CHECK.T, ".", color="0.5", ms=3)
        ax.set(xlim=(-5, 125), ylim=(-5, 95), aspect="equal", xlabel="X [m]", ylabel="Y [m]",
               title=f"plan errors ×{self.scale:g}: plane (red), differential (blue)")
        (self._plane,) = ax.plot([], [], color="#d62728", lw=1.5)
        (self._diff,) = ax.plot([], [], color="#1f77b4", lw=2.5)
        for a in (self._plane, self._diff):
            self.live.animate(a)
        self.report = None
        self._finish()

    def draw(self, phi, amplitude) -> str:
        self.report = rep = ortho_error_report(phi, amplitude)
        P = rep["points"]
        for line, err in ((self._plane, rep["plane_err"]), (self._diff, rep["diff_err"])):
            seg = np.stack([P, P + self.scale * err], axis=1)
            line.set_data(*lines_xyz(seg)[:2])
        return rep["html"]


# -- true orthophoto ------------------------------------------------------------------------------

_TO_GRID = ((50, 60), (0.5, 49.5), 1.0)


def true_ortho_report(height: float = 20.0, offset: float = 20.0, H: float = 100.0) -> dict:
    """Occlusion behind one building (14 m × 14 m) on flat ground, vertical camera.

    The building stands at X in [30, 44], Y in [18, 32]; the nadir point lies ``offset`` m
    to the left of its left wall, the camera ``H`` m above the ground.

    Returns ``classes`` (rows, cols: 0 occluded, 1 visible ground, 2 roof), ``area`` (m² of
    occluded ground), ``length`` (occluded length behind the far wall along the row through
    the nadir, m) with its formula value ``d·h/(H − h)``, ``html``.

    >>> rep = true_ortho_report(20.0, 20.0, 100.0)
    >>> rep["length"], round(rep["formula"], 3)
    (8.0, 8.5)
    """
    box = (30.0, 44.0, 18.0, 32.0, float(height))
    shape, origin, d = _TO_GRID
    grid = output_grid(shape, origin, d)
    roof = np.isfinite(_roofs(grid, (box,))) & (height > 0)
    model = DTM(np.where(roof, height, 0.0), origin, d, order=0)
    nadir = (box[0] - offset, 25.0)
    cam = FrameCamera((nadir[0], nadir[1], H), np.eye(3), C_MM, 2000, 2000, 0.05)
    vis = pl.visibility(cam, model, shape, origin, d)
    classes = np.where(roof, 2, np.where(vis, 1, 0))
    row = int(round(origin[1] - nadir[1]))
    behind = (~vis[row]) & (grid[row, :, 0] > box[1])
    length = float(behind.sum() * d)
    dist = box[1] - nadir[0]
    formula = dist * height / (H - height) if height > 0 else 0.0
    area = float((classes == 0).sum() * d * d)
    html = (f"<p>building Δh = {height:.0f} m, far wall d = {dist:.0f} m from the nadir, "
            f"H = {H:.0f} m<br>occluded ground (sichttote Fläche): <b>{area:.0f} m²</b><br>"
            f"behind the far wall: {length:.0f} m in the grid, d·Δh/(H − Δh) = "
            f"<b>{formula:.2f} m</b></p>")
    return {"classes": classes, "area": area, "length": length, "formula": formula,
            "nadir": nadir, "html": html}


class TrueOrthoExplorer(Explorer):
    """Building height and nadir distance → the occluded ground a true orthophoto must mark."""

    title = "true orthophoto explorer"

    def __init__(self, height=20.0, offset=20.0):
        self.controls = {"height": slider("building Δh [m]", height, 0, 60, 1, fmt=".0f"),
                         "offset": slider("nadir offset [m]", offset, 0, 30, 1, fmt=".0f")}
        self.live = LiveFigure((4.2, 3.6))
        ax = self.live.figure.add_subplot()
        self.live.figure.subplots_adjust(0.14, 0.12, 0.98, 0.9)
        shape, origin, d = _TO_GRID
        ext = (origin[0] - d / 2, origin[0] + (shape[1] - 0.5) * d,
               origin[1] - (shape[0] - 0.5) * d, origin[1] + d / 2)
        from matplotlib.colors import ListedColormap
        self._im = ax.imshow(np.ones(shape), extent=ext, vmin=0, vmax=2, interpolation="nearest",
                             cmap=ListedColormap(["#d62728", "#dddddd", "#555555"]))
        (self._nadir,) = ax.plot([], [], "k+", ms=10, mew=2)
        ax.set(xlabel="X [m]", ylabel="Y [m]", title="occluded (red), roof (dark)")
        ax.grid(False)
        for a in (self._im, self._nadir):
            self.live.animate(a)
        self.report = None
        self._finish()

    def draw(self, height, offset) -> str:
        self.report = rep = true_ortho_report(height, offset)
        self._im.set_data(rep["classes"])
        self._nadir.set_data([rep["nadir"][0]], [rep["nadir"][1]])
        return rep["html"]


# -- static figures -------------------------------------------------------------------------------

def plot_products(panels: dict, extent=None, cmap="gray"):
    """Side-by-side grey images (title → array); NaN shown red (no value / occluded)."""
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(1, len(panels), figsize=(3.2 * len(panels), 2.8))
    axes = np.atleast_1d(axes)
    for ax, (title, img) in zip(axes, panels.items()):
        cm = plt.get_cmap(cmap).with_extremes(bad="#d62728")
        ax.imshow(np.ma.masked_invalid(img), cmap=cm, vmin=0, vmax=255, extent=extent,
                  interpolation="nearest")
        ax.set_title(title, fontsize=9)
        ax.grid(False)
        ax.set_xticks([])
        ax.set_yticks([])
    fig.tight_layout()
    return finished(fig)


def plot_mosaic(mosaic, source, nadirs, extent):
    """The mosaic with its seamline (where the source image changes) and the nadir points."""
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(4.6, 3.5))
    cm = plt.get_cmap("gray").with_extremes(bad="#d62728")
    ax.imshow(np.ma.masked_invalid(mosaic), cmap=cm, vmin=0, vmax=255, extent=extent,
              interpolation="nearest")
    rows, cols = source.shape
    X = np.linspace(extent[0], extent[1], cols)
    Y = np.linspace(extent[3], extent[2], rows)
    ax.contour(X, Y, source.astype(float), levels=[0.5], colors="#ff7f0e", linewidths=1.5)
    nad = np.asarray(nadirs)
    ax.plot(*nad.T, "+", color="#1f77b4", ms=12, mew=2)
    ax.set(xlabel="X [m]", ylabel="Y [m]", title="mosaic, seamline (orange), nadir points (+)")
    ax.grid(False)
    return finished(fig)


def plot_height_models(models: dict, vmax: float = 40.0):
    """Height models side by side (title → :class:`photolib.DTM`), one colour scale."""
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(1, len(models), figsize=(3.8 * len(models), 2.8))
    axes = np.atleast_1d(axes)
    for ax, (title, model) in zip(axes, models.items()):
        Xmin, Xmax, Ymin, Ymax = model.extent
        im = ax.imshow(model.heights, extent=(Xmin, Xmax, Ymin, Ymax), cmap="terrain",
                       vmin=0, vmax=vmax, interpolation="nearest")
        ax.set(title=title, xlabel="X [m]")
        ax.grid(False)
    fig.colorbar(im, ax=list(axes), label="Z [m]", shrink=0.85)
    return finished(fig)


def plot_ortho_map(ortho, model, shape, origin, pixel_size, interval: float = 2.5):
    """Orthophoto map (Orthophotokarte): the orthophoto with contour lines from the DTM."""
    import matplotlib.pyplot as plt

    XY = output_grid(shape, origin, pixel_size)
    extent = (origin[0] - pixel_size / 2, origin[0] + (shape[1] - 0.5) * pixel_size,
              origin[1] - (shape[0] - 0.5) * pixel_size, origin[1] + pixel_size / 2)
    fig, ax = plt.subplots(figsize=(4.6, 3.5))
    cm = plt.get_cmap("gray").with_extremes(bad="#d62728")
    ax.imshow(np.ma.masked_invalid(ortho), cmap=cm, vmin=0, vmax=255, extent=extent)
    Z = model.height(XY)
    levels = np.arange(np.floor(Z.min() / interval) * interval, Z.max() + interval, interval)
    cs = ax.contour(XY[..., 0], XY[..., 1], Z, levels=levels, colors="#ff7f0e", linewidths=0.8)
    ax.clabel(cs, fontsize=6)
    ax.grid(False)
    ax.set(title=f"orthophoto map, contours {interval:g} m", xlabel="X [m]", ylabel="Y [m]")
    return finished(fig)
