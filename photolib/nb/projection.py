"""Chapter 06 pictures and widgets: collinearity, projection and monoplotting.

A camera (projection centre X0, rotation R = R_ω·R_φ·R_κ, camera constant c, 36 mm × 24 mm
format) looks at a house; :func:`projection_report` projects it with
:func:`photolib.project`, :func:`footprint_report` intersects the image rays of a tilted
aerial image with the ground with :func:`photolib.monoplot`.
"""

from __future__ import annotations

import numpy as np

import photolib as pl
from photolib.nb.draw import (
    AXIS_COLOURS,
    format_corners,
    frame_segments,
    frustum_segments,
    grid_lines,
    house_edges,
    lines_xyz,
    setup_axes3d,
)
from photolib.nb.live import Explorer, LiveFigure, finished, slider
from photolib.nb.text import matrix_html

__all__ = [
    "ConvergenceExplorer",
    "convergence_scene",
    "dtm_iteration",
    "plot_collinearity_geometry",
    "plot_convergence",
    "plot_dtm_iteration",
    "resection_history",
    "HALF",
    "FootprintExplorer",
    "ProjectionExplorer",
    "footprint_limit",
    "footprint_report",
    "horizon_angle",
    "plot_projection",
    "projection_report",
    "scene_points",
]

#: half format, mm
HALF = (18.0, 12.0)
_LIMITS = ((-40.0, 40.0), (-60.0, 20.0), (0.0, 50.0))


def scene_points():
    """The object of chapter 06: house edges (E, 2, 3) and a ground grid (G, 3), metres.

    >>> edges, ground = scene_points()
    >>> edges.shape, ground.shape
    ((17, 2, 3), (25, 3))
    """
    g = np.linspace(-20.0, 20.0, 5)
    gx, gy = np.meshgrid(g, g)
    ground = np.column_stack([gx.ravel(), gy.ravel(), np.zeros(gx.size)])
    return house_edges(10.0), ground


def projection_report(X0=0.0, Y0=-40.0, Z0=18.0, omega=70.0, phi=0.0, kappa=0.0, c=50.0) -> dict:
    """Project the scene with the collinearity equations.

    Parameters
    ----------
    X0, Y0, Z0 : float
        Projection centre, m.
    omega, phi, kappa : float
        Angles in degrees.
    c : float
        Camera constant / Kamerakonstante, mm.

    Returns
    -------
    dict
        ``R``; ``edges_xy`` (E, 2, 2) and ``ground_xy`` (G, 2) image coordinates in mm, NaN
        where a point is not in front of the camera; ``inside`` (number of ground and
        house corner points inside the format); ``html``.

    Examples
    --------
    >>> rep = projection_report(0, 0, 50, 0, 0, 0, 50)   # nadir image 50 m above the ground
    >>> rep["ground_xy"][-1].tolist()                     # ground point (20, 20, 0) m
    [20.0, 20.0]
    """
    R = pl.rotation_opk(*(pl.deg2rad(a) for a in (omega, phi, kappa)))
    X0v = np.array([X0, Y0, Z0], dtype=float)
    edges, ground = scene_points()
    pts = np.concatenate([edges.reshape(-1, 3), ground])
    xy, valid = pl.project(pts, X0v, R, c, return_valid=True)
    edges_xy = xy[: edges.shape[0] * 2].reshape(-1, 2, 2)
    ground_xy = xy[edges.shape[0] * 2:]
    with np.errstate(invalid="ignore"):
        inside = int(np.sum(valid & (np.abs(xy[:, 0]) <= HALF[0]) & (np.abs(xy[:, 1]) <= HALF[1])))
    behind = int(np.sum(~valid))
    html = (matrix_html(R, "R = R<sub>ω</sub>·R<sub>φ</sub>·R<sub>κ</sub>")
            + f"<p>X0 = ({X0:.0f}, {Y0:.0f}, {Z0:.0f}) m, c = {c:.0f} mm<br>"
            f"points in the format: {inside} of {len(pts)}<br>"
            f"points behind the camera (N ≥ 0): {behind}</p>")
    return {"R": R, "X0": X0v, "edges_xy": edges_xy, "ground_xy": ground_xy,
            "inside": inside, "behind": behind, "html": html}


def horizon_angle(c=35.0, half=HALF[1]) -> float:
    """Roll angle ω (degrees) at which the image edge ``y' = half`` reaches the horizon.

    With roll only, the ray of an image point is ``R_ω·(x', y', −c)``; its Z component
    ``y' sin ω − c cos ω`` is negative (the ray goes down) while ``tan ω < c/y'``. So the
    corner rays of the upper edge miss the ground from ``ω = atan(c/y')`` on; for pitch φ use
    the half width ``x'`` instead (``φ = −atan(c/x')``).

    >>> round(horizon_angle(35.0, 12.0), 2), round(horizon_angle(35.0, 18.0), 2)
    (71.08, 62.78)
    """
    return float(np.degrees(np.arctan2(c, half)))


def footprint_report(omega=0.0, phi=0.0, kappa=0.0, Z0=1000.0, c=35.0) -> dict:
    """Ground footprint of a tilted aerial image by monoplotting onto Z = 0.

    Parameters
    ----------
    omega, phi, kappa : float
        Roll / Querneigung, pitch / Längsneigung, yaw / Kantung, degrees.
    Z0 : float
        Flying height above the ground, m.
    c : float
        Camera constant, mm.

    Returns
    -------
    dict
        ``corners`` (5, 3) closed footprint polygon in m or None when a corner ray misses
        the ground; ``lines``: the image grid on the ground; ``area_km2``; ``scale_number``
        (Bildmaßstabszahl of the nadir image over the ground Z = 0: (Z0 − Z)/c = Z0/c);
        ``ray_angle_deg``: the largest angle of a corner ray from the plumb line (≥ 90°: that ray does not go down, horizon in the
        image); ``extent_m``: the largest |X| or |Y| of the footprint (inf without one);
        ``html``.

    Examples
    --------
    >>> rep = footprint_report(0, 0, 0, Z0=700.0, c=35.0)
    >>> rep["corners"][2].round(6).tolist()        # image corner (18, 12) mm
    [360.0, 240.0, 0.0]
    >>> footprint_report(71.0)["corners"] is None, footprint_report(71.1)["corners"] is None
    (False, True)
    """
    R = pl.rotation_opk(*(pl.deg2rad(a) for a in (omega, phi, kappa)))
    X0 = np.array([0.0, 0.0, Z0])
    scale_number = Z0 / (c / 1000.0)
    image_corners = format_corners(*HALF)[:4]
    rays = np.column_stack([image_corners, np.full(4, -c)]) @ R.T
    ray_angle = float(np.max(np.degrees(np.arccos(-rays[:, 2] / np.linalg.norm(rays, axis=1)))))
    try:
        corners = pl.monoplot(format_corners(*HALF), X0, R, c, Z=0.0)
        lines = [pl.monoplot(line, X0, R, c, Z=0.0) for line in grid_lines(*HALF, n=7, samples=2)]
        x, y = corners[:4, 0], corners[:4, 1]
        area = 0.5 * abs(np.dot(x, np.roll(y, -1)) - np.dot(y, np.roll(x, -1))) / 1e6
        extent = float(np.max(np.abs(corners[:, :2])))
        status = (f"footprint area: <b>{area:,.3f} km²</b>, reaching {extent / 1000:,.2f} km "
                  "from the nadir point")
    except ValueError:
        corners, lines, area, extent = None, None, float("nan"), float("inf")
        status = ("<span style='color:#b00'>a corner ray does not meet the ground "
                  "(horizon in the image)</span>")
    html = (f"<p>nadir image scale 1 : {scale_number:,.0f} "
            f"(Bildmaßstabszahl m<sub>b</sub> = (Z0 − Z)/c, ground Z = 0)"
            f"<br>most oblique (flattest) corner ray: {ray_angle:.1f}° from the plumb line (90° = horizon)"
            f"<br>{status}</p>")
    return {"R": R, "corners": corners, "lines": lines, "area_km2": area,
            "scale_number": scale_number, "ray_angle_deg": ray_angle, "extent_m": extent,
            "html": html}


def footprint_limit(extent, Z0, clip=20.0) -> tuple[float, bool]:
    """Half width of the footprint axes: a round number above ``extent`` (m), at most
    ``clip·Z0``; returns ``(limit, clipped)``.

    >>> footprint_limit(360.0, 700.0), footprint_limit(5.3e4, 1000.0)
    ((500.0, False), (20000.0, True))
    """
    top = clip * Z0
    if not np.isfinite(extent) or 1.1 * extent > top:
        return float(top), True
    need = max(1.1 * extent, 0.5 * Z0)
    mag = 10.0 ** np.floor(np.log10(need))
    for f in (1.0, 2.0, 2.5, 5.0, 10.0):
        if f * mag >= need:
            return float(min(f * mag, top)), False
    return float(top), False  # pragma: no cover


def _draw_scene(ax):
    edges, ground = scene_points()
    ax.plot(*lines_xyz(edges), color="0.3", lw=1)
    ax.plot(*ground.T, ".", color="#8c564b", ms=3)


def _camera_segments(X0, R, c):
    return frustum_segments(X0, R, c, *HALF, scale=12.0 / c)


class ProjectionExplorer(Explorer):
    """Move and turn the camera over the house; the image shows the projection."""

    title = "projection explorer"

    def __init__(self, X0=0.0, Y0=-40.0, Z0=18.0, omega=70.0, phi=0.0, kappa=0.0, c=50.0):
        self.controls = {"X0": slider("X0 [m]", X0, -40, 40, 1),
                         "Y0": slider("Y0 [m]", Y0, -60, 0, 1),
                         "Z0": slider("Z0 [m]", Z0, 2, 50, 1),
                         "omega": slider("ω [°]", omega, -30, 120, 1),
                         "phi": slider("φ [°]", phi, -60, 60, 1),
                         "kappa": slider("κ [°]", kappa, -180, 180, 1),
                         "c": slider("c [mm]", c, 10, 100, 1)}
        self.live = LiveFigure((7.2, 3.2))
        fig = self.live.figure
        ax3 = fig.add_subplot(1, 2, 1, projection="3d")
        ax2 = fig.add_subplot(1, 2, 2)
        fig.subplots_adjust(0.0, 0.14, 0.98, 0.92, wspace=0.32)
        setup_axes3d(ax3, _LIMITS, elev=25, azim=-50)
        ax3.set_zlabel("Z", labelpad=-4)  # keeps clear of the image panel's y' label
        _draw_scene(ax3)
        (self._frustum,) = ax3.plot([], [], [], color="#9467bd", lw=1)
        self._axes = [ax3.plot([], [], [], color=col, lw=2)[0] for col in AXIS_COLOURS]
        ax2.plot(*format_corners(*HALF).T, color="0.5", lw=1)
        ax2.plot(0, 0, "+", color="0.5")
        (self._edges,) = ax2.plot([], [], color="0.2", lw=1)
        (self._ground,) = ax2.plot([], [], ".", color="#8c564b", ms=4)
        ax2.set(xlim=(-24, 24), ylim=(-16, 16), aspect="equal", xlabel="x' [mm]",
                ylabel="y' [mm]", title="image / Bild")
        for a in [self._frustum, *self._axes, self._edges, self._ground]:
            self.live.animate(a)
        self.report = None
        self._finish()

    def draw(self, X0, Y0, Z0, omega, phi, kappa, c) -> str:
        self.report = rep = projection_report(X0, Y0, Z0, omega, phi, kappa, c)
        self._frustum.set_data_3d(*lines_xyz(_camera_segments(rep["X0"], rep["R"], c)))
        for line, seg in zip(self._axes, frame_segments(rep["R"], rep["X0"], 8.0)):
            line.set_data_3d(*seg.T)
        ex, ey = lines_xyz(rep["edges_xy"])
        self._edges.set_data(ex, ey)
        self._ground.set_data(*rep["ground_xy"].T)
        return rep["html"]


class FootprintExplorer(Explorer):
    """Flight attitude / Fluglage: roll, pitch and yaw of an aerial camera and its footprint.

    ω and φ go to ±80°, past the horizon angles of the 36 mm × 24 mm format with c = 35 mm
    (:func:`horizon_angle`: 71.1° in roll, 62.8° in pitch). The axes follow the footprint
    (:func:`footprint_limit`) up to ±20·Z0; a longer footprint is clipped and the text says so.
    """

    title = "flight attitude and footprint explorer"

    def __init__(self, omega=0.0, phi=0.0, kappa=0.0, Z0=1000.0):
        self.controls = {"omega": slider("ω roll [°]", omega, -80, 80, 0.5),
                         "phi": slider("φ pitch [°]", phi, -80, 80, 0.5),
                         "kappa": slider("κ yaw [°]", kappa, -180, 180, 1),
                         "Z0": slider("Z0 [m]", Z0, 200, 1500, 50, fmt=".0f")}
        self.live = LiveFigure((4.0, 3.6))
        ax = self._ax = self.live.figure.add_subplot()
        self.live.figure.subplots_adjust(0.2, 0.13, 0.97, 0.92)
        ax.set(aspect="equal", xlabel="X [m]", ylabel="Y [m]",
               title="footprint on the ground Z = 0")
        self._limit = None
        ax.plot(0, 0, "k^")
        (self._poly,) = ax.plot([], [], color="#d62728", lw=2)
        (self._grid,) = ax.plot([], [], color="#1f77b4", lw=0.7)
        self.live.animate(self._poly)
        self.live.animate(self._grid)
        self.report = None
        self._finish()

    def _set_limit(self, limit) -> None:
        """Rescale the axes only when the footprint outgrows them or shrinks below a quarter.

        A new scale means a full redraw (the cached background holds the old ticks), which
        costs several times a blitted update; the hysteresis keeps a slider that moves back
        and forth on one scale.
        """
        if self._limit is not None and limit <= self._limit <= 4.0 * limit:
            return
        self._limit = limit
        self._ax.set(xlim=(-limit, limit), ylim=(-limit, limit))
        self.live.invalidate()

    def draw(self, omega, phi, kappa, Z0) -> str:
        self.report = rep = footprint_report(omega, phi, kappa, Z0)
        limit, clipped = footprint_limit(rep["extent_m"], Z0)
        self._set_limit(limit)
        html = rep["html"]
        if rep["corners"] is None:
            self._poly.set_data([], [])
            self._grid.set_data([], [])
        else:
            self._poly.set_data(rep["corners"][:, 0], rep["corners"][:, 1])
            gx, gy, _ = lines_xyz(np.array([line for line in rep["lines"]]))
            self._grid.set_data(gx, gy)
            if clipped:
                html += (f"<p>axes clipped at ±{self._limit / 1000:g} km (20·Z0): the far corners lie "
                         f"{rep['extent_m'] / 1000:,.0f} km out</p>")
        return html


def plot_projection(X0, R, c, x0=0.0, y0=0.0, distortion=None, title="image / Bild"):
    """Static figure: the scene with the camera (left) and its image (right).

    Returns
    -------
    matplotlib.figure.Figure
    """
    import matplotlib.pyplot as plt

    X0 = np.asarray(X0, dtype=float)
    fig = plt.figure(figsize=(7.2, 3.2))
    ax3 = fig.add_subplot(1, 2, 1, projection="3d")
    setup_axes3d(ax3, _LIMITS, elev=25, azim=-50)
    ax3.set_zlabel("Z", labelpad=-4)  # keeps clear of the image panel's y' label
    _draw_scene(ax3)
    ax3.plot(*lines_xyz(_camera_segments(X0, R, c)), color="#9467bd", lw=1)
    for col, seg in zip(AXIS_COLOURS, frame_segments(R, X0, 8.0)):
        ax3.plot(*seg.T, color=col, lw=2)
    edges, ground = scene_points()
    pts = np.concatenate([edges.reshape(-1, 3), ground])
    xy, _ = pl.project(pts, X0, R, c, x0, y0, distortion, return_valid=True)
    ax = fig.add_subplot(1, 2, 2)
    ax.plot(*format_corners(*HALF).T, color="0.5", lw=1)
    ax.plot(x0, y0, "+", color="0.5")
    ax.plot(*lines_xyz(xy[: edges.shape[0] * 2].reshape(-1, 2, 2)), color="0.2", lw=1)
    ax.plot(*xy[edges.shape[0] * 2:].T, ".", color="#8c564b", ms=4)
    ax.set(xlim=(-24, 24), ylim=(-16, 16), aspect="equal", xlabel="x' [mm]", ylabel="y' [mm]",
           title=title)
    fig.subplots_adjust(0.0, 0.14, 0.98, 0.92, wspace=0.32)
    return finished(fig)


# -- derivation, inverse on a height and on a DTM, linearisation (chapter 06 rewrite) ----------

def plot_collinearity_geometry():
    """Side view of the collinearity condition: projection centre O, the image plane at
    distance c behind it (negative image, z' = −c) and in front (positive), image point P',
    object point P on one straight line; X − X0 = m·R·x*.

    Returns
    -------
    matplotlib.figure.Figure
    """
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(6.4, 3.8))
    C, P, c = np.array([0.0, 5.0]), np.array([4.5, 0.3]), 1.3
    d = P - C
    Pn = C - d * c / abs(d[1])                     # on the negative image plane, z' = −c
    Pp = C + d * c / abs(d[1])                     # on the positive (mirrored) plane
    ax.plot([-3.5, 6.2], [0.0, 0.0], color="#8c564b", lw=1)
    ax.text(6.1, -0.45, "object space / Objektraum", ha="right", fontsize=8, color="#8c564b")
    ax.plot([-2.2, 1.0], [C[1] + c] * 2, color="0.3", lw=1.6)
    ax.plot([-1.0, 2.2], [C[1] - c] * 2, color="0.65", lw=1, ls="--")
    ax.text(1.1, C[1] + c - 0.05, "image plane, z' = −c", fontsize=7, color="0.3", va="center")
    ax.text(-3.5, C[1] - c - 0.05, "positive image (mirrored)", fontsize=7, color="0.5",
            va="center")
    ax.plot(*np.column_stack([Pn, P]), color="#1f77b4", lw=1.2)
    ax.plot([C[0], C[0]], [0.0, C[1] + c], color="0.55", lw=0.8, ls=":")
    ax.plot([C[0], C[0]], [C[1], C[1] + c], color="#9467bd", lw=2.2)
    ax.text(0.08, C[1] + 0.45, "c", color="#9467bd", fontsize=10)
    for pt in (C, Pn, Pp, P, np.array([C[0], C[1] + c])):
        ax.plot(*pt, "o", color="k", ms=4)
    ax.text(Pn[0] - 0.2, Pn[1] + 0.3, "P' = (x', y')", fontsize=8, ha="center")
    ax.text(0.05, C[1] + c + 0.3, "H' = (x'0, y'0)", fontsize=8)
    ax.text(0.3, C[1] - 0.15, "O = X0, projection centre", fontsize=8)
    ax.text(P[0] - 0.2, P[1] + 0.3, "P = X", fontsize=8, ha="right")
    ax.text(-3.5, 6.9, "x* = (x' − x'0, y' − y'0, −c)  (camera frame)", color="#2ca02c",
            fontsize=8)
    ax.annotate("", xy=Pn, xytext=C, arrowprops={"arrowstyle": "->", "color": "#2ca02c",
                                                 "lw": 1.5})
    ax.text(2.7, 2.6, "X − X0 = m·R·x*\nm > 0: in front", color="#d62728", fontsize=8)
    ax.annotate("", xy=P, xytext=C, arrowprops={"arrowstyle": "->", "color": "#d62728",
                                                "lw": 1.0, "shrinkA": 0, "shrinkB": 3})
    ax.set(xlim=(-3.6, 6.3), ylim=(-0.7, 7.3), aspect="equal")
    ax.axis("off")
    ax.set_title("collinearity / Kollinearität: P', O and P on one straight line", fontsize=9)
    return finished(fig)


def dtm_iteration(xy, X0, R, c, surface, Z_start=None, steps=6):
    """Points of the monoplotting iteration on a surface (:func:`photolib.monoplot_dtm`).

    Returns
    -------
    dict
        ``heights`` (k + 1,) plane heights Z_0 … Z_k, ``points`` (k + 1, 3) the ray's points
        on these planes, ``X`` the converged point.

    Examples
    --------
    >>> it = dtm_iteration([30.0, 0.0], [0.0, 0.0, 1000.0], np.eye(3), 100.0,
    ...                    lambda XY: 0.2 * XY[:, 0], Z_start=0.0, steps=3)
    >>> np.round(it["heights"], 3).tolist()            # each step shrinks the error by 0.06
    [0.0, 60.0, 56.4, 56.616]
    """
    X0 = np.asarray(X0, float)
    _, hist = pl.monoplot_dtm(xy, X0, R, c, surface, Z_start=Z_start, tol=1e-9,
                              return_iterations=True)
    heights = hist[: steps + 1, 0]
    points = np.vstack([pl.monoplot(xy, X0, R, c, Z=z) for z in heights])
    X = pl.monoplot_dtm(xy, X0, R, c, surface, Z_start=Z_start, tol=1e-9)
    return {"heights": heights, "points": points, "X": X}


def plot_dtm_iteration(xy, X0, R, c, surface, Z_start=None, steps=6):
    """Profile along the ray's plan direction: left the camera, the ray and the terrain; right
    a zoom on the iteration, the planes Z_k (grey), the points on them (red) and the step to
    the terrain height under each (dotted), converging to the surface point (star)."""
    import matplotlib.pyplot as plt

    it = dtm_iteration(xy, X0, R, c, surface, Z_start, steps)
    X0 = np.asarray(X0, float)
    d = it["X"][:2] - X0[:2]
    dist = float(np.linalg.norm(d))
    u = d / dist
    along = (it["points"][:, :2] - X0[:2]) @ u
    fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(8.0, 3.3), gridspec_kw={"width_ratios": [1, 1.3]})
    far = 1.1 * max(float(along.max()), dist)
    s = np.linspace(-0.1 * far, far, 300)
    terrain = surface(X0[:2] + s[:, None] * u)
    ray_z = X0[2] + s / dist * (it["X"][2] - X0[2])
    for ax in (ax1, ax2):
        ax.fill_between(s, terrain, terrain.min() - 1e4, color="#c7b299", alpha=0.6, lw=0)
        ax.plot(s, terrain, color="#8c564b", lw=1.2, label="terrain Z = h(X, Y)")
        front = s >= 0
        ax.plot(s[front], ray_z[front], color="#1f77b4", lw=1, label="image ray")
        ax.plot(dist, it["X"][2], "*", color="k", ms=10, label="surface point", zorder=5)
    ax1.plot(0.0, X0[2], "k^", label="projection centre")
    ax1.set(xlabel="plan distance along the ray [m]", ylabel="Z [m]",
            ylim=(min(terrain.min(), it["heights"].min()) - 50, X0[2] + 80))
    ax1.legend(fontsize=6, loc="upper right")
    ax1.set_title("camera, ray and terrain", fontsize=9)
    span_s = max(float(np.ptp(along)), 1.0)
    span_z = max(float(np.ptp(it["heights"])), 1.0)
    w = 0.06 * span_s
    for k, (z, a) in enumerate(zip(it["heights"], along)):
        ax2.plot([a - w, a + w], [z, z], color="0.45", lw=0.8)
        ax2.plot(a, z, "o", color="#d62728", ms=4, zorder=4)
        if k < 4:
            ax2.annotate(f"Z{k}", (a + 1.2 * w, z), fontsize=7, va="center")
        if k + 1 < len(along):
            ax2.plot([a, a], [z, it["heights"][k + 1]], color="#d62728", lw=0.8, ls=":")
    ax2.set(xlim=(along.min() - 0.3 * span_s, along.max() + 0.3 * span_s),
            ylim=(it["heights"].min() - 0.25 * span_z, it["heights"].max() + 0.25 * span_z),
            xlabel="plan distance along the ray [m]")
    ax2.set_title("zoom: plane Z_k → point → height under it → Z_(k+1)", fontsize=9)
    fig.tight_layout()
    return finished(fig)


def resection_history(X, xy, c, start, max_iter=12):
    """Gauss–Newton iterates of the space resection from ``start`` (X0, Y0, Z0, ω, φ, κ):
    the largest angle update (rad) of each iteration, NaN once it diverged (points behind the
    camera, non-finite updates).

    Examples
    --------
    >>> X = np.array([[0, 0, 0], [10, 0, 1], [0, 10, 2], [10, 10, 0], [5, 5, 4], [2, 8, 1.0]])
    >>> xy = pl.project(X, [4.0, 6.0, 30.0], pl.rotation_opk(0.05, -0.1, 0.2), 24.0)
    >>> h = resection_history(X, xy, 24.0, [5.0, 5.0, 25.0, 0.0, 0.0, 0.0], 8)
    >>> bool(h[-1] < 1e-12)
    True
    """
    q = np.asarray(start, float).copy()
    out = np.full(max_iter, np.nan)
    for k in range(max_iter):
        R = pl.rotation_opk(*q[3:])
        try:
            v = pl.project(X, q[:3], R, c) - xy
            A = pl.collinearity_jacobian(X, q[:3], R, c, angles=tuple(q[3:]))[:, :, :6]
        except ValueError:
            break
        dq = np.linalg.lstsq(A.reshape(-1, 6), -v.reshape(-1), rcond=None)[0]
        if not np.all(np.isfinite(dq)):
            break
        q = q + dq
        out[k] = np.max(np.abs(dq[3:]))
    return out


def plot_convergence(X, xy, c, truth, errors_deg=(2.0, 10.0, 25.0, 40.0, 60.0), max_iter=12):
    """Convergence of the linearised collinearity equations from start values whose angles
    are off by ``errors_deg`` (all three) and whose centre is off by 20 % of the distance."""
    import matplotlib.pyplot as plt

    truth = np.asarray(truth, float)
    fig, ax = plt.subplots(figsize=(5.6, 3.2))
    colours = plt.cm.viridis(np.linspace(0.0, 0.9, len(errors_deg)))
    for e, col in zip(errors_deg, colours):
        start = truth + np.r_[0.2 * truth[2] * np.array([0.3, -0.3, 0.5]), np.radians([e, -e, e])]
        h = resection_history(X, xy, c, start, max_iter)
        ok = np.isfinite(h) & (h > 0)
        converged = bool(ok.any() and np.nanmin(h) < 1e-10)
        ax.semilogy(np.arange(1, max_iter + 1)[ok], h[ok], "o-", color=col, ms=3,
                    label=f"angles off by {e:g}°" + ("" if converged else " (no convergence)"))
    ax.axhline(1e-10, color="0.6", lw=0.8, ls=":")
    ax.set(xlabel="iteration", ylabel="largest angle update [rad]", ylim=(1e-16, 10.0))
    ax.legend(fontsize=7)
    ax.set_title("Gauss–Newton from start values of different quality", fontsize=9)
    fig.tight_layout()
    return finished(fig)


def convergence_scene(seed=6, n=8, c=50.0):
    """The close-range resection of chapter 06's convergence study: ``(X, xy, c, truth)``,
    n object points (m) on a 80 m × 80 m site, their exact image points (mm) and the true
    ``(X0, Y0, Z0, ω, φ, κ)`` (m, rad).

    >>> X, xy, c, truth = convergence_scene()
    >>> X.shape, xy.shape, c
    ((8, 3), (8, 2), 50.0)
    """
    rng = np.random.default_rng(seed)
    X = np.column_stack([rng.uniform(-40, 40, n), rng.uniform(-40, 40, n), rng.uniform(0, 10, n)])
    truth = np.r_[5.0, -3.0, 120.0, np.radians([3.0, -2.0, 30.0])]
    return X, pl.project(X, truth[:3], pl.rotation_opk(*truth[3:]), c), c, truth


class ConvergenceExplorer(Explorer):
    """Approximate values / Näherungswerte: start the space resection's Gauss–Newton iteration
    with the angles off by ``angle_error`` degrees (all three, alternating signs) and the
    projection centre off by ``centre_error`` % of the distance; the figure shows the largest
    angle update of each iteration (:func:`resection_history`)."""

    title = "approximate values and convergence"
    max_iter = 15

    def __init__(self, angle_error=10.0, centre_error=20.0):
        self.controls = {"angle_error": slider("angle error [°]", angle_error, 0, 80, 1),
                         "centre_error": slider("centre error [%]", centre_error, 0, 60, 1)}
        self.X, self.xy, self.c, self.truth = convergence_scene()
        self.live = LiveFigure((4.4, 3.0))
        ax = self.live.figure.add_subplot()
        self.live.figure.subplots_adjust(0.18, 0.16, 0.97, 0.9)
        ax.set(yscale="log", xlim=(0.5, self.max_iter + 0.5), ylim=(1e-17, 10.0),
               xlabel="iteration", ylabel="largest angle update [rad]",
               title="Gauss–Newton from the start values")
        ax.axhline(1e-10, color="0.6", lw=0.8, ls=":")
        (self._line,) = ax.plot([], [], "o-", color="#1f77b4", ms=3)
        self.live.animate(self._line)
        self.report = None
        self._finish()

    def start(self, angle_error, centre_error) -> np.ndarray:
        """The start values for these errors (degrees, per cent of the distance)."""
        off = 0.01 * centre_error * self.truth[2] * np.array([0.3, -0.3, 0.5]) / 0.6557
        return self.truth + np.r_[off, np.radians([angle_error, -angle_error, angle_error])]

    def draw(self, angle_error, centre_error) -> str:
        h = resection_history(self.X, self.xy, self.c, self.start(angle_error, centre_error),
                              self.max_iter)
        ok = np.isfinite(h)
        it = np.arange(1, self.max_iter + 1)
        self._line.set_data(it[ok], np.maximum(h[ok], 1e-17))
        done = np.flatnonzero(ok & (h < 1e-10))
        if done.size:
            text = f"converged in {done[0] + 1} iterations"
        elif not ok.any():
            text = "<span style='color:#b00'>diverged at once (points behind the camera)</span>"
        elif not ok.all():
            text = (f"<span style='color:#b00'>diverged in iteration {int(ok.sum()) + 1} "
                    "(points behind the camera)</span>")
        else:
            text = (f"<span style='color:#b00'>not converged in {self.max_iter} "
                    "iterations</span>")
        self.report = {"history": h, "text": text}
        return (f"<p>start: angles off by {angle_error:.0f}°, centre off by "
                f"{centre_error:.0f} % of the distance<br>{text}</p>")
