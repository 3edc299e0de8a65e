"""Geometry of the pictures: coordinate frames, camera frusta, image formats, grids, objects.

Pure NumPy functions that return line segments in object coordinates, plus small helpers
that turn them into matplotlib artists. The chapters' figures and widgets are built from
these, so each picture shows the course's conventions (R camera → object, image vector
``x* = (x', y', −c)``, positive image plane in front of the projection centre).
"""

from __future__ import annotations

import numpy as np

__all__ = [
    "AXIS_COLOURS",
    "format_corners",
    "frame_segments",
    "frustum_segments",
    "grid_lines",
    "house_edges",
    "lines_xyz",
    "setup_axes3d",
]

#: colours of the x, y, z axes (red, green, blue as in most 3-D software)
AXIS_COLOURS = ("#d62728", "#2ca02c", "#1f77b4")


def frame_segments(R, origin=(0.0, 0.0, 0.0), length: float = 1.0) -> np.ndarray:
    """End points of the three axes of a frame whose axes are the columns of ``R``.

    Parameters
    ----------
    R : array_like, shape (3, 3)
        Columns: the frame's x, y, z axes in object coordinates.
    origin : array_like, shape (3,)
    length : float

    Returns
    -------
    ndarray, shape (3, 2, 3)
        ``[axis, (start, end), xyz]``.

    Examples
    --------
    >>> frame_segments(np.eye(3), length=2.0)[2].tolist()
    [[0.0, 0.0, 0.0], [0.0, 0.0, 2.0]]
    """
    R = np.asarray(R, dtype=float)
    o = np.asarray(origin, dtype=float)
    return np.stack([np.stack([o, o + length * R[:, i]]) for i in range(3)])


def format_corners(half_width: float, half_height: float) -> np.ndarray:
    """Corners of the image format (x', y'), counter-clockwise from bottom left, closed.

    >>> format_corners(18, 12)[:2].tolist()
    [[-18.0, -12.0], [18.0, -12.0]]
    """
    w, h = float(half_width), float(half_height)
    return np.array([[-w, -h], [w, -h], [w, h], [-w, h], [-w, -h]])


def frustum_segments(X0, R, c: float, half_width: float, half_height: float,
                     scale: float) -> np.ndarray:
    """Edges of the viewing pyramid of a camera, in object coordinates.

    The image corners ``x* = (±w, ±h, −c)`` (positive image plane) are mapped by
    ``X = X0 + scale·R·x*``; the pyramid has the projection centre at its apex.

    Parameters
    ----------
    X0 : array_like, shape (3,)
    R : array_like, shape (3, 3)
        Camera → object rotation.
    c, half_width, half_height : float
        Camera constant and half format, image unit.
    scale : float
        Object units per image unit of the drawn pyramid (``m`` of ``X = X0 + m·R·x*``).

    Returns
    -------
    ndarray, shape (8, 2, 3)
        Four edges from the apex, then the four sides of the format rectangle.

    Examples
    --------
    >>> seg = frustum_segments([0, 0, 10], np.eye(3), 5.0, 1.0, 1.0, scale=2.0)
    >>> seg[0].tolist()    # apex to the first corner, which lies below the camera
    [[0.0, 0.0, 10.0], [-2.0, -2.0, 0.0]]
    """
    X0 = np.asarray(X0, dtype=float)
    R = np.asarray(R, dtype=float)
    corners = format_corners(half_width, half_height)[:4]
    xstar = np.column_stack([corners, np.full(4, -float(c))])
    P = X0 + scale * xstar @ R.T
    edges = [np.stack([X0, p]) for p in P]
    sides = [np.stack([P[i], P[(i + 1) % 4]]) for i in range(4)]
    return np.stack(edges + sides)


def grid_lines(half_width: float, half_height: float, n: int = 9, samples: int = 25):
    """Straight lines of a grid over the format, sampled densely enough to show curvature.

    Returns
    -------
    list of ndarray, each shape (samples, 2)
        ``n`` vertical then ``n`` horizontal lines.

    >>> len(grid_lines(18, 12, n=5)), grid_lines(18, 12, n=5)[0].shape
    (10, (25, 2))
    """
    w, h = float(half_width), float(half_height)
    t = np.linspace(-1.0, 1.0, samples)
    out = []
    for u in np.linspace(-1.0, 1.0, n):
        out.append(np.column_stack([np.full(samples, u * w), t * h]))
    for v in np.linspace(-1.0, 1.0, n):
        out.append(np.column_stack([t * w, np.full(samples, v * h)]))
    return out


def house_edges(size: float = 10.0) -> np.ndarray:
    """Edges of a simple house (box with a gable roof) standing on Z = 0, object unit.

    Returns
    -------
    ndarray, shape (E, 2, 3)

    >>> house_edges().shape
    (17, 2, 3)
    """
    a = float(size) / 2
    h = float(size) * 0.6
    base = [(-a, -a), (a, -a), (a, a), (-a, a)]
    P = [np.array([x, y, 0.0]) for x, y in base] + [np.array([x, y, h]) for x, y in base]
    ridge = [np.array([-a, 0.0, h + 0.5 * a]), np.array([a, 0.0, h + 0.5 * a])]
    edges = []
    for i in range(4):
        edges.append((P[i], P[(i + 1) % 4]))          # floor
        edges.append((P[4 + i], P[4 + (i + 1) % 4]))  # eaves
        edges.append((P[i], P[4 + i]))                # walls
    edges += [(ridge[0], ridge[1]), (P[4], ridge[0]), (P[7], ridge[0]),
              (P[5], ridge[1]), (P[6], ridge[1])]
    return np.array([np.stack(e) for e in edges])


def lines_xyz(segments) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Segments (E, 2, 3) as three NaN-separated coordinate arrays for one ``plot`` call.

    One artist per picture element keeps the widgets fast.

    >>> [v.tolist() for v in lines_xyz(np.zeros((1, 2, 3)))][0]
    [0.0, 0.0, nan]
    """
    s = np.asarray(segments, dtype=float)
    pad = np.full((s.shape[0], 1, s.shape[2]), np.nan)
    flat = np.concatenate([s, pad], axis=1).reshape(-1, s.shape[2])
    return tuple(flat[:, i] for i in range(s.shape[2]))


def setup_axes3d(ax, limits, labels=("X", "Y", "Z"), elev: float = 22, azim: float = -60,
                 nbins: int = 4):
    """Fixed limits, equal aspect, a fixed view and axis labels for a 3-D axes.

    At most ``nbins`` + 1 ticks per axis: in the small 3-D panels of the widgets more tick
    labels (such as −40, −30, …, 40) run into each other (``tests/test_nb.py`` checks).
    """
    from matplotlib.ticker import MaxNLocator

    (x0, x1), (y0, y1), (z0, z1) = limits
    ax.set_xlim(x0, x1)
    ax.set_ylim(y0, y1)
    ax.set_zlim(z0, z1)
    ax.set_box_aspect((x1 - x0, y1 - y0, z1 - z0))
    ax.set_xlabel(labels[0])
    ax.set_ylabel(labels[1])
    ax.set_zlabel(labels[2])
    ax.view_init(elev=elev, azim=azim)
    for axis in (ax.xaxis, ax.yaxis, ax.zaxis):
        axis.set_major_locator(MaxNLocator(nbins=nbins, steps=[1, 2, 2.5, 5, 10]))
    ax.tick_params(labelsize=7, pad=0)
    return ax
