"""Chapter 04 pictures and widgets: coordinate frames turned by ω, φ, κ.

The callbacks are plain functions (:func:`rotation_report`, :func:`order_report`) that the
widgets call and the tests call directly.
"""

from __future__ import annotations

import numpy as np

import photolib as pl
from photolib.nb.draw import AXIS_COLOURS, frame_segments, frustum_segments, lines_xyz, setup_axes3d
from photolib.nb.live import Explorer, LiveFigure, finished, slider
from photolib.nb.text import matrix_html

__all__ = [
    "OrderExplorer",
    "RotationExplorer",
    "draw_frame",
    "order_report",
    "plot_frames",
    "plot_rotation_2d",
    "rotation_report",
]

_LIMITS = ((-1.2, 1.2), (-1.2, 1.2), (-1.2, 1.2))


def rotation_report(omega_deg: float, phi_deg: float, kappa_deg: float) -> dict:
    """R of ω, φ, κ (degrees), its orthogonality and the angles recovered from it.

    Parameters
    ----------
    omega_deg, phi_deg, kappa_deg : float
        Angles in degrees (the widget's unit); converted with :func:`photolib.deg2rad`.

    Returns
    -------
    dict
        ``R`` (3, 3); ``orthogonality`` = max |RᵀR − I|; ``det``; ``gimbal`` (bool);
        ``recovered`` = (ω, φ, κ) in degrees from :func:`photolib.opk_from_rotation`
        (at gimbal lock with κ set to 0, and ``coupled`` names the angle sum or
        difference that R still fixes); ``html``.

    Examples
    --------
    >>> rep = rotation_report(10, 90, 20)
    >>> rep["gimbal"], rep["coupled"]
    (True, ('ω + κ', 30.0))
    """
    R = pl.rotation_opk(*(pl.deg2rad(a) for a in (omega_deg, phi_deg, kappa_deg)))
    ortho = float(np.max(np.abs(R.T @ R - np.eye(3))))
    det = float(np.linalg.det(R))
    try:
        angles = pl.opk_from_rotation(R)
        gimbal, coupled = False, None
    except pl.GimbalLockError:
        angles = pl.opk_from_rotation(R, split="kappa-zero")
        gimbal = True
        w = float(pl.rad2deg(angles[0]))
        coupled = ("ω + κ", round(w, 6)) if angles[1] > 0 else ("ω − κ", round(w, 6))
    recovered = tuple(round(float(pl.rad2deg(a)), 6) + 0.0 for a in angles)
    lines = [matrix_html(R, "R = R<sub>ω</sub>·R<sub>φ</sub>·R<sub>κ</sub>"),
             f"<p>max |RᵀR − I| = {ortho:.1e}<br>det R = {det:.6f}</p>"]
    if gimbal:
        name, value = coupled
        lines.append("<p style='color:#b00'><b>Gimbal lock / kardanische Blockade</b>: "
                     f"φ = ±90°, only {name} = {value:.1f}° is determined.<br>"
                     f"With κ := 0: ω = {recovered[0]:.1f}°</p>")
    else:
        lines.append("<p>recovered (ω, φ, κ) = ({:.1f}°, {:.1f}°, {:.1f}°)</p>".format(*recovered))
    return {"R": R, "orthogonality": ortho, "det": det, "gimbal": gimbal,
            "coupled": coupled, "recovered": recovered, "html": "".join(lines)}


def order_report(omega_deg: float, phi_deg: float, kappa_deg: float) -> dict:
    """The same three angles in the orders ω-φ-κ and φ-ω-κ, and how far apart they are.

    Returns
    -------
    dict
        ``R_opk``, ``R_pok`` (3, 3); ``angle_deg``: rotation angle of ``R_opkᵀ·R_pok``; ``html``.

    Examples
    --------
    >>> order_report(30, 0, 40)["angle_deg"]   # one angle zero: the orders agree
    0.0
    >>> order_report(30, 20, 0)["angle_deg"] > 5
    True
    """
    a = [pl.deg2rad(v) for v in (omega_deg, phi_deg, kappa_deg)]
    R1, R2 = pl.rotation_opk(*a), pl.rotation_pok(*a)
    from photolib.testing import rotation_angle_between

    angle = round(float(np.degrees(rotation_angle_between(R1, R2))), 6) + 0.0
    html = (matrix_html(R1, "ω-φ-κ: R<sub>ω</sub>R<sub>φ</sub>R<sub>κ</sub>")
            + matrix_html(R2, "φ-ω-κ: R<sub>φ</sub>R<sub>ω</sub>R<sub>κ</sub>")
            + f"<p>the two differ by a rotation of <b>{angle:.2f}°</b></p>")
    return {"R_opk": R1, "R_pok": R2, "angle_deg": angle, "html": html}


def draw_frame(ax, R, origin=(0, 0, 0), length=1.0, labels=("x", "y", "z"), style="-",
               animated=None):
    """Draw a frame (axes = columns of R) into a 3-D axes; returns the artists."""
    seg = frame_segments(R, origin, length)
    arts = []
    for i in range(3):
        (line,) = ax.plot(*seg[i].T, style, color=AXIS_COLOURS[i], lw=2)
        text = ax.text(*seg[i][1], labels[i], color=AXIS_COLOURS[i], fontsize=10)
        arts += [line, text]
        if animated is not None:
            animated.animate(line)
            animated.animate(text)
    return arts


def _set_frame(arts, R, origin=(0, 0, 0), length=1.0):
    seg = frame_segments(R, origin, length)
    for i in range(3):
        arts[2 * i].set_data_3d(*seg[i].T)
        arts[2 * i + 1].set_position_3d(seg[i][1])


def _camera_view(ax, live):
    """Object frame (grey), camera frame and a small viewing pyramid (moving)."""
    setup_axes3d(ax, _LIMITS)
    draw_frame(ax, np.eye(3), length=1.1, labels=("X", "Y", "Z"), style=":")
    frame = draw_frame(ax, np.eye(3), labels=("x'", "y'", "z'"), animated=live)
    (pyramid,) = ax.plot([], [], [], color="0.4", lw=1)
    live.animate(pyramid)
    return frame, pyramid


def _move_camera(frame, pyramid, R):
    _set_frame(frame, R)
    pyramid.set_data_3d(*lines_xyz(frustum_segments(np.zeros(3), R, 1.0, 0.45, 0.3, 0.9)))


class RotationExplorer(Explorer):
    """Sliders for ω, φ, κ (degrees) turning the camera frame; shows R and the recovered angles.

    At φ = ±90° the text reports gimbal lock and the angle sum/difference that survives.
    """

    title = "ω-φ-κ rotation explorer"

    def __init__(self, omega=20.0, phi=10.0, kappa=30.0):
        self.controls = {"omega": slider("ω (roll) [°]", omega, -180, 180, 1),
                         "phi": slider("φ (pitch) [°]", phi, -90, 90, 1),
                         "kappa": slider("κ (yaw) [°]", kappa, -180, 180, 1)}
        self.live = LiveFigure((4.2, 3.6))
        ax = self.live.figure.add_subplot(projection="3d")
        # room below and right of the axes for the X, Y and Z labels (tests/test_nb.py checks)
        self.live.figure.subplots_adjust(0.0, 0.07, 0.95, 1.0)
        self._frame, self._pyramid = _camera_view(ax, self.live)
        self.report = None
        self._finish()

    def draw(self, omega, phi, kappa) -> str:
        self.report = rotation_report(omega, phi, kappa)
        _move_camera(self._frame, self._pyramid, self.report["R"])
        return self.report["html"]


class OrderExplorer(Explorer):
    """The same ω, φ, κ applied in the orders ω-φ-κ and φ-ω-κ, side by side."""

    title = "rotation order explorer"

    def __init__(self, omega=30.0, phi=40.0, kappa=0.0):
        self.controls = {"omega": slider("ω [°]", omega, -180, 180, 1),
                         "phi": slider("φ [°]", phi, -90, 90, 1),
                         "kappa": slider("κ [°]", kappa, -180, 180, 1)}
        self.live = LiveFigure((6.4, 3.2))
        fig = self.live.figure
        self._views = []
        for i, name in enumerate(("ω-φ-κ", "φ-ω-κ")):
            ax = fig.add_subplot(1, 2, i + 1, projection="3d")
            ax.set_title(name, fontsize=10)
            self._views.append(_camera_view(ax, self.live))
        fig.subplots_adjust(0.0, 0.08, 0.96, 0.9, wspace=0.12)
        self.report = None
        self._finish()

    def draw(self, omega, phi, kappa) -> str:
        self.report = order_report(omega, phi, kappa)
        for (frame, pyramid), R in zip(self._views, (self.report["R_opk"], self.report["R_pok"])):
            _move_camera(frame, pyramid, R)
        return self.report["html"]


def plot_frames(rotations, titles, figsize=None):
    """Static figure: one 3-D panel per rotation, object frame dotted, camera frame solid.

    Parameters
    ----------
    rotations : sequence of array_like, each (3, 3)
    titles : sequence of str

    Returns
    -------
    matplotlib.figure.Figure
    """
    import matplotlib.pyplot as plt

    n = len(rotations)
    fig = plt.figure(figsize=figsize or (3.0 * n, 3.0))
    for i, (R, title) in enumerate(zip(rotations, titles)):
        ax = fig.add_subplot(1, n, i + 1, projection="3d")
        setup_axes3d(ax, _LIMITS)
        draw_frame(ax, np.eye(3), length=1.1, labels=("X", "Y", "Z"), style=":")
        draw_frame(ax, R, labels=("x'", "y'", "z'"))
        ax.set_title(title, fontsize=10)
    fig.subplots_adjust(0, 0, 1, 0.92, wspace=0.05)
    return finished(fig)


def plot_rotation_2d(alpha_deg: float, point=(1.0, 0.4)):
    """Static figure: a plane rotation by α of the x, y axes and of one point.

    Returns
    -------
    matplotlib.figure.Figure
    """
    import matplotlib.pyplot as plt

    R = pl.rotation_2d(pl.deg2rad(alpha_deg))
    p = np.asarray(point, dtype=float)
    fig, ax = plt.subplots(figsize=(3.6, 3.6))
    for i, col in enumerate(("#d62728", "#2ca02c")):
        e = np.eye(2)[i]
        ax.annotate("", e, (0, 0), arrowprops={"arrowstyle": "->", "color": "0.6", "ls": ":"})
        ax.annotate("", R @ e, (0, 0), arrowprops={"arrowstyle": "->", "color": col, "lw": 2})
        ax.text(*(1.08 * R @ e), ("x'", "y'")[i], color=col)
    ax.plot(*p, "ko")
    ax.plot(*(R @ p), "o", color="#1f77b4")
    ax.text(*(p + 0.05), "P")
    ax.text(*(R @ p + 0.05), "R(α)·P", color="#1f77b4")
    ax.set(xlim=(-1.2, 1.4), ylim=(-1.2, 1.4), aspect="equal", xlabel="x", ylabel="y",
           title=f"plane rotation, α = {alpha_deg:g}°")
    ax.grid(alpha=0.3)
    return finished(fig)
