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
