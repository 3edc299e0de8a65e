"""The capstone project (chapter 14) and the real-image tasks of chapter 08: the chain on the
chessboard images of :func:`photolib.data.chessboard` (mvtb-data, left01 … left14).

The chain / die Auswertekette, every step done by photolib:

1. measure the 54 inner corners of each view (OpenCV's ``findChessboardCorners`` and
   ``cornerSubPix`` are the measuring tool, :func:`photolib.nb.realdata.detect_corners`);
2. interior orientation (innere Orientierung) from the self-calibrating bundle adjustment of
   chapter 05 (:func:`photolib.nb.realdata.chessboard_calibration`): pixel → image
   coordinates ``x' = col − (W − 1)/2``, ``y' = (H − 1)/2 − row`` (px), then the distortion
   correction ``x_ideal = x_meas − Δ(x_meas − x'0)``;
3. space resection (Rückwärtsschnitt) of two views from the *control points* — the board
   corners not withheld — with :func:`photolib.space_resection` (σ0, redundancy r = 2n − 6);
4. forward intersection (Vorwärtsschnitt) of the *check points* — withheld corners — from
   both views with :func:`photolib.forward_intersection`;
5. the accuracy statement: the check points' differences from their true positions on the
   board (square side 25 mm, from the data set's metadata), beside the precision predicted
   by propagating σ0 and the orientations' covariance.

Object unit mm (board frame: X along the rows of corners, Y = −25·row, Z = 0 on the board),
image unit px (the camera's pixel pitch is not published).
"""

from __future__ import annotations

import functools
from dataclasses import dataclass

import numpy as np

import photolib as pl
from photolib.nb.live import finished

__all__ = ["BOARD", "Chain", "PAIRS", "board_points", "calibration", "chain", "corner_grid",
           "draw_check_points", "draw_pair", "image_coordinates", "intersection_angle",
           "pixel_corners", "plot_check_errors", "plot_views", "predicted_precision", "resect",
           "view_name"]

#: inner corners of the board (columns, rows)
BOARD = (9, 6)
#: the smallest angle (degrees) between the two views' rays to the board centre of a pair
MIN_ANGLE_DEG = 15.0


@functools.lru_cache(maxsize=1)
def calibration():
    """The chapter-05 calibration of the chessboard camera (cached): c, x'0, y'0 (px) and the
    distortion A1–A3, B1, B2 of :func:`photolib.testfield.plane_field_calibration`."""
    from photolib.nb.realdata import chessboard_calibration
    return chessboard_calibration()


def view_name(view: int) -> str:
    """File name of a view, 0-based: ``view_name(0) == 'left01.jpg'``."""
    cal = calibration()
    if not 0 <= int(view) < len(cal.files):
        raise ValueError(f"view must be 0 … {len(cal.files) - 1}, got {view!r}")
    return cal.files[int(view)]


def board_points() -> np.ndarray:
    """(54, 3) true board positions of the corners, mm: corner k at row k // 9, column k % 9,
    ``X = 25·col``, ``Y = −25·row``, ``Z = 0`` (square side from the data set's metadata)."""
    return calibration().object_points.copy()


def corner_grid(k) -> tuple[int, int]:
    """(row, column) of corner number k (0 … 53), numbered row by row as OpenCV finds them.

    >>> corner_grid(0), corner_grid(10), corner_grid(53)
    ((0, 0), (1, 1), (5, 8))
    """
    k = int(k)
    if not 0 <= k < BOARD[0] * BOARD[1]:
        raise ValueError(f"corner number must be 0 … {BOARD[0] * BOARD[1] - 1}, got {k!r}")
    return k // BOARD[0], k % BOARD[0]


def pixel_corners(view: int) -> np.ndarray:
    """(54, 2) measured corners (col, row) of a view, px (OpenCV as the measuring tool)."""
    view_name(view)
    return calibration().corners[int(view)].copy()


def image_coordinates(view: int) -> np.ndarray:
    """(54, 2) distortion-corrected image coordinates (x', y') of a view's corners, px.

    ``x' = col − (W − 1)/2``, ``y' = (H − 1)/2 − row``, then
    ``x_ideal = x'0 + (x − x'0) − Δ(x − x'0)`` with the calibration's distortion.
    """
    view_name(view)
    cal = calibration()
    r = cal.result
    pp = np.array([r.x0, r.y0])
    return pp + r.distortion.correct(cal.xy[int(view)] - pp)


def resect(view: int, control) -> pl.ResectionResult:
    """Space resection of a view from the control corners ``control`` (corner numbers), with
    the calibration's c, x'0, y'0 on the corrected coordinates; start from the plane
    homography (:func:`photolib.testfield.plane_start`)."""
    from photolib.testfield import plane_start
    control = np.asarray(control, dtype=int)
    if control.ndim != 1 or len(np.unique(control)) < 4:
        raise ValueError(f"control must list ≥ 4 distinct corner numbers, got {control.tolist()}")
    r = calibration().result
    X, xy = board_points()[control], image_coordinates(view)[control]
    pp = np.array([r.x0, r.y0])
    _, start = plane_start([xy - pp], X[:, :2], c=r.c)
    return pl.space_resection(X, xy, r.c, r.x0, r.y0, initial=start[0])


def _centres() -> np.ndarray:
    return calibration().result.exterior[:, :3]


def intersection_angle(view_a: int, view_b: int) -> float:
    """Angle (degrees) between the rays of two views to the board centre (calibration's X0)."""
    C = _centres()
    centre = board_points().mean(axis=0)
    a, b = C[int(view_a)] - centre, C[int(view_b)] - centre
    return float(np.degrees(np.arccos(a @ b / np.linalg.norm(a) / np.linalg.norm(b))))


def _pairs():
    n = len(calibration().files)
    return tuple((a, b) for a in range(n) for b in range(n)
                 if a != b and intersection_angle(a, b) >= MIN_ANGLE_DEG)


class _Pairs:
    """Ordered view pairs whose rays meet at ≥ :data:`MIN_ANGLE_DEG` (computed on first use)."""

    def __iter__(self):
        return iter(_pairs_cached())

    def __len__(self):
        return len(_pairs_cached())

    def __getitem__(self, i):
        return _pairs_cached()[i]


_pairs_cached = functools.lru_cache(maxsize=1)(_pairs)
PAIRS = _Pairs()


def draw_pair(rng) -> tuple[int, int]:
    """A pair of views (0-based) drawn from :data:`PAIRS`."""
    return tuple(int(v) for v in PAIRS[int(rng.integers(len(PAIRS)))])


def draw_check_points(rng, m: int = 6) -> list[int]:
    """``m`` check-point corner numbers, sorted, at least one per board half (rows 0–2, 3–5)."""
    n = BOARD[0] * BOARD[1]
    while True:
        chk = sorted(int(k) for k in rng.choice(n, m, replace=False))
        rows = {corner_grid(k)[0] // 3 for k in chk}
        if len(rows) == 2:
            return chk


def _intersection(ra, rb, xa, xb):
    r = calibration().result
    return pl.forward_intersection(np.stack([xa, xb]), np.stack([ra.X0, rb.X0]),
                                   np.stack([ra.R, rb.R]), r.c, r.x0, r.y0).points


def predicted_precision(ra, rb, xa, xb, sigma_xy: float) -> np.ndarray:
    """(m, 3) standard deviations (mm) of the intersected points, by linear propagation of
    σ_xy on the four image coordinates of each point and of both resections' covariance
    ``Σ_qq`` (numerical derivatives, central differences)."""
    r = calibration().result
    qa, qb = ra.params, rb.params
    out = []
    for i in range(len(xa)):
        x = np.r_[xa[i], xb[i], qa, qb]

        def f(z):
            Ra, Rb = pl.rotation_opk(*z[7:10]), pl.rotation_opk(*z[13:16])
            return pl.forward_intersection([z[0:2], z[2:4]], [z[4:7], z[10:13]], [Ra, Rb],
                                           r.c, r.x0, r.y0).points
        steps = np.r_[np.full(4, 1e-3), np.tile(np.r_[np.full(3, 1e-3), np.full(3, 1e-7)], 2)]
        J = np.column_stack([(f(x + h * e) - f(x - h * e)) / (2 * h)
                             for h, e in zip(steps, np.eye(16))])
        S = np.zeros((16, 16))
        S[:4, :4] = sigma_xy**2 * np.eye(4)
        S[4:10, 4:10], S[10:, 10:] = ra.covariance, rb.covariance
        out.append(np.sqrt(np.diag(J @ S @ J.T)))
    return np.array(out)


@dataclass(frozen=True)
class Chain:
    """The result of :func:`chain`: both resections, the intersected check points and their
    differences from the board geometry."""

    views: tuple  #: (view_a, view_b), 0-based
    check: tuple  #: check-point corner numbers
    control: tuple  #: control-point corner numbers (the others)
    resections: tuple  #: ResectionResult of view a and of view b (mm, px)
    xy: tuple  #: corrected image coordinates of the check points in view a and b, (m, 2) px
    points: np.ndarray  #: (m, 3) intersected check points, mm
    true: np.ndarray  #: (m, 3) their positions on the board, mm
    predicted: np.ndarray  #: (m, 3) predicted standard deviations, mm

    @property
    def errors(self) -> np.ndarray:
        """(m, 3) intersected − true, mm."""
        return self.points - self.true

    @property
    def rms(self) -> float:
        """RMS of the 3-D distances ``sqrt(Σ|ΔX|²/m)``, mm."""
        return float(np.sqrt(np.mean(np.sum(self.errors**2, axis=1))))

    @property
    def predicted_rms(self) -> float:
        """RMS predicted from σ0 and the orientations: ``sqrt(Σ(σX² + σY² + σZ²)/m)``, mm."""
        return float(np.sqrt(np.mean(np.sum(self.predicted**2, axis=1))))


def chain(view_a: int, view_b: int, check) -> Chain:
    """Run the project's chain on two views with the given check points (corner numbers)."""
    if int(view_a) == int(view_b):
        raise ValueError(f"the two views must differ, got {view_a!r} twice")
    check = sorted(int(k) for k in check)
    for k in check:
        corner_grid(k)
    control = [k for k in range(BOARD[0] * BOARD[1]) if k not in check]
    ra, rb = resect(view_a, control), resect(view_b, control)
    xa, xb = image_coordinates(view_a)[check], image_coordinates(view_b)[check]
    points = _intersection(ra, rb, xa, xb)
    sigma = float(np.sqrt((ra.sigma0**2 * ra.redundancy + rb.sigma0**2 * rb.redundancy)
                          / (ra.redundancy + rb.redundancy)))
    return Chain((int(view_a), int(view_b)), tuple(check), tuple(control), (ra, rb), (xa, xb),
                 points, board_points()[check], predicted_precision(ra, rb, xa, xb, sigma))


# -- figures --------------------------------------------------------------------------------------
def plot_views(ch: Chain):
    """The two views with their measured control (blue) and check points (red), and the
    resection's residuals (×100) at the control points."""
    import matplotlib.pyplot as plt
    import photolib.data as pdata
    images = pdata.chessboard().images
    fig, axes = plt.subplots(1, 2, figsize=(10, 3.9))
    for ax, view, res in zip(axes, ch.views, ch.resections):
        px = pixel_corners(view)
        ax.imshow(images[view], cmap="gray")
        ctrl, chk = np.array(ch.control), np.array(ch.check)
        ax.plot(*px[ctrl].T, "o", ms=3, mfc="none", color="tab:blue", label="control points")
        ax.plot(*px[chk].T, "x", ms=7, mew=2, color="tab:red", label="check points")
        v = res.residuals * np.array([1.0, -1.0])       # y' up → row down
        ax.quiver(*px[ctrl].T, *v.T, angles="xy", scale_units="xy", scale=0.01,
                  color="tab:orange", width=0.004)
        ax.set_title(f"{view_name(view)}: σ0 = {res.sigma0:.3f} px, r = {res.redundancy} "
                     "(residuals ×100)")
        ax.set_axis_off()
    axes[0].legend(loc="lower left", fontsize=8)
    fig.tight_layout()
    return finished(fig)


def plot_check_errors(ch: Chain, scale: float = 200.0):
    """The board from above: the check points' errors in X, Y (×scale) with their predicted
    1σ ellipses' axes (error bars), and Z errors as numbers."""
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(figsize=(6.5, 4.2))
    X = board_points()
    ax.plot(X[:, 0], X[:, 1], ".", color="0.7")
    e, s = ch.errors, ch.predicted
    ax.quiver(ch.true[:, 0], ch.true[:, 1], e[:, 0], e[:, 1], angles="xy", scale_units="xy",
              scale=1 / scale, color="tab:red", width=0.005)
    ax.errorbar(ch.true[:, 0] + scale * e[:, 0], ch.true[:, 1] + scale * e[:, 1],
                xerr=scale * s[:, 0], yerr=scale * s[:, 1], fmt="none", color="tab:gray")
    for t, dz in zip(ch.true, e[:, 2]):
        ax.annotate(f"ΔZ {dz:+.2f}", t[:2], textcoords="offset points", xytext=(4, -12),
                    fontsize=8)
    ax.set_aspect("equal")
    ax.set_xlabel("X [mm]")
    ax.set_ylabel("Y [mm]")
    ax.set_title(f"check-point errors ×{scale:g} (1σ bars): RMS {ch.rms:.3f} mm, "
                 f"predicted {ch.predicted_rms:.3f} mm")
    fig.tight_layout()
    return finished(fig)
