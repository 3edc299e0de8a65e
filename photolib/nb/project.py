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
from photolib.nb.live import Explorer, LiveFigure, finished, slider

__all__ = ["BOARD", "Chain", "ChainExplorer", "NoiseExplorer", "PAIRS", "board_points", "calibration", "chain", "corner_grid",
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


def resect(view: int, control, xy=None) -> pl.ResectionResult:
    """Space resection of a view from the control corners ``control`` (corner numbers), with
    the calibration's c, x'0, y'0 on the corrected coordinates (or on ``xy``, (54, 2) px, the
    view's corrected coordinates with something added); start from the plane homography
    (:func:`photolib.testfield.plane_start`)."""
    from photolib.testfield import plane_start
    control = np.asarray(control, dtype=int)
    if control.ndim != 1 or len(np.unique(control)) < 4:
        raise ValueError(f"control must list ≥ 4 distinct corner numbers, got {control.tolist()}")
    r = calibration().result
    xy = image_coordinates(view) if xy is None else xy
    X, xy = board_points()[control], xy[control]
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
    cos = a @ b / np.linalg.norm(a) / np.linalg.norm(b)
    return float(np.degrees(np.arccos(np.clip(cos, -1.0, 1.0))))


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
    ``Σ_qq``: ``Σ_XX = σ_xy²·J_x·J_xᵀ + J_q·Σ_qq·J_qᵀ`` per point, with the derivatives by
    central differences. Each point is intersected on its own, so one step of an image
    coordinate of every point at once gives every point's column of ``J_x``: 32 intersections
    for any m."""
    r = calibration().result
    xa, xb = np.asarray(xa, dtype=float), np.asarray(xb, dtype=float)
    q = np.r_[ra.params, rb.params]
    xy = np.concatenate([xa, xb], axis=1)                     # (m, 4)

    def f(xy, q):
        Ra, Rb = pl.rotation_opk(*q[3:6]), pl.rotation_opk(*q[9:12])
        return pl.forward_intersection(np.stack([xy[:, 0:2], xy[:, 2:4]]), [q[0:3], q[6:9]],
                                       [Ra, Rb], r.c, r.x0, r.y0).points

    J_x = np.stack([(f(xy + 1e-3 * e, q) - f(xy - 1e-3 * e, q)) / 2e-3 for e in np.eye(4)],
                   axis=2)                                     # (m, 3, 4)
    steps = np.tile(np.r_[np.full(3, 1e-3), np.full(3, 1e-7)], 2)
    J_q = np.stack([(f(xy, q + h * e) - f(xy, q - h * e)) / (2 * h)
                    for h, e in zip(steps, np.eye(12))], axis=2)  # (m, 3, 12)
    S_q = np.zeros((12, 12))
    S_q[:6, :6], S_q[6:, 6:] = ra.covariance, rb.covariance
    cov = sigma_xy**2 * J_x @ J_x.transpose(0, 2, 1) + J_q @ S_q @ J_q.transpose(0, 2, 1)
    return np.sqrt(np.diagonal(cov, axis1=1, axis2=2))


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


def chain(view_a: int, view_b: int, check, noise=None) -> Chain:
    """Run the project's chain on two views with the given check points (corner numbers).

    ``noise``: optional (2, 54, 2) px added to the corrected image coordinates of view a and
    of view b before both resections and the intersection (a simulated poorer measurement).
    """
    if int(view_a) == int(view_b):
        raise ValueError(f"the two views must differ, got {view_a!r} twice")
    check = sorted(int(k) for k in check)
    for k in check:
        corner_grid(k)
    if len(set(check)) != len(check):
        raise ValueError(f"check points must be distinct corner numbers, got {check}")
    n = BOARD[0] * BOARD[1]
    xy_a, xy_b = image_coordinates(view_a), image_coordinates(view_b)
    if noise is not None:
        noise = np.asarray(noise, dtype=float)
        if noise.shape != (2, n, 2) or not np.all(np.isfinite(noise)):
            raise ValueError(f"noise must be a finite (2, {n}, 2) array in px, got shape "
                             f"{noise.shape}")
        xy_a, xy_b = xy_a + noise[0], xy_b + noise[1]
    control = [k for k in range(n) if k not in check]
    ra, rb = resect(view_a, control, xy_a), resect(view_b, control, xy_b)
    xa, xb = xy_a[check], xy_b[check]
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


# -- widgets --------------------------------------------------------------------------------------
class ChainExplorer(Explorer):
    """The chain on another pair of views: pick view A and view B and the number of check
    points (``check``: the corners withheld at the start; other numbers are a seeded draw); see
    the pair's geometry (side view: the 14 camera centres, the two rays to the board centre),
    the check points' errors (×200, with their predicted 1σ bars) and RMS against the
    prediction."""

    title = "the chain on a pair of views: geometry and accuracy"
    SCALE = 200.0
    COLOURS = ("tab:blue", "tab:orange")

    def __init__(self, view_a: int = 2, view_b: int = 11, check=None, seed: int = 14):
        from matplotlib.collections import LineCollection

        n = len(calibration().files)
        self.seed = int(seed)
        self.check = None if check is None else tuple(sorted(int(k) for k in check))
        n_check = 6 if check is None else len(self.check)
        if not 3 <= n_check <= 24:
            raise ValueError(f"check must list 3 … 24 corner numbers, got {n_check}")
        self.controls = {
            "view_a": slider("view A (0 = left01)", view_a, 0, n - 1, 1, fmt=".0f"),
            "view_b": slider("view B (0 = left01)", view_b, 0, n - 1, 1, fmt=".0f"),
            "n_check": slider("check points", n_check, 3, 24, 1, fmt=".0f"),
        }
        self.live = live = LiveFigure((7.4, 3.3))
        fig = live.figure
        geo, err = fig.add_subplot(1, 2, 1), fig.add_subplot(1, 2, 2)
        fig.subplots_adjust(0.09, 0.15, 0.98, 0.88, wspace=0.3)
        # still: the board (side view and from above) and the 14 camera centres
        C, X = _centres(), board_points()
        geo.plot([X[:, 0].min(), X[:, 0].max()], [0, 0], lw=4, color="0.3",
                 solid_capstyle="butt")
        geo.plot(C[:, 0], C[:, 2], "o", ms=4, color="0.75")
        geo.set(xlabel="X [mm]", ylabel="Z [mm]", xlim=(-120, 340), ylim=(-30, 420))
        geo.set_aspect("equal")
        err.plot(X[:, 0], X[:, 1], ".", color="0.75", ms=3)
        err.set(xlabel="X [mm]", ylabel="Y [mm]", xlim=(-60, 260), ylim=(-185, 60))
        err.set_aspect("equal")
        # moving: rays, centres and names of A and B; error vectors, their tips and 1σ bars
        self._rays = [live.animate(geo.plot([], [], "-", color=c, lw=1.2)[0])
                      for c in self.COLOURS]
        self._centre = [live.animate(geo.plot([], [], "o", ms=7, color=c)[0])
                        for c in self.COLOURS]
        self._names = [live.animate(geo.annotate(name, (0, 0), textcoords="offset points",
                                                 xytext=(5, 4), color=c, fontsize=9,
                                                 fontweight="bold"))
                       for name, c in zip("AB", self.COLOURS)]
        self._geo_title = live.animate(geo.set_title("", fontsize=9))
        self._vectors = live.animate(err.add_collection(
            LineCollection([], colors="tab:red", linewidths=1.6)))
        self._tips = live.animate(err.plot([], [], "o", ms=3, color="tab:red")[0])
        self._bars = live.animate(err.add_collection(
            LineCollection([], colors="tab:gray", linewidths=1.0)))
        self._err_title = live.animate(err.set_title("", fontsize=9))
        self._message = live.animate(err.text(0.5, 0.5, "one view:\nno intersection",
                                              ha="center", va="center", fontsize=11,
                                              color="tab:red", transform=err.transAxes))
        self.chain = None
        self._finish()

    def check_points(self, n_check: int) -> list[int]:
        """The withheld corners for ``n_check`` check points: the ones given to the widget
        when it has that many, else a seeded draw with corners in both board halves."""
        if self.check is not None and int(n_check) == len(self.check):
            return list(self.check)
        return draw_check_points(np.random.default_rng(self.seed), int(n_check))

    def _geometry(self, views) -> None:
        C, centre = _centres(), board_points().mean(axis=0)
        for i, (ray, dot, name) in enumerate(zip(self._rays, self._centre, self._names)):
            v = views[min(i, len(views) - 1)]
            ray.set_data([C[v, 0], centre[0]], [C[v, 2], centre[2]])
            dot.set_data([C[v, 0]], [C[v, 2]])
            name.xy = (C[v, 0], C[v, 2])

    def _errors(self, ch) -> None:
        if ch is None:
            for art in (self._vectors, self._bars):
                art.set_segments([])
            self._tips.set_data([], [])
            return
        t, s = ch.true[:, :2], ch.predicted[:, :2] * self.SCALE
        tip = t + self.SCALE * ch.errors[:, :2]
        self._vectors.set_segments(np.stack([t, tip], axis=1))
        self._tips.set_data(tip[:, 0], tip[:, 1])
        dx, dy = np.column_stack([s[:, 0], 0 * s[:, 0]]), np.column_stack([0 * s[:, 1], s[:, 1]])
        self._bars.set_segments(np.concatenate([np.stack([tip - dx, tip + dx], axis=1),
                                                np.stack([tip - dy, tip + dy], axis=1)]))

    def draw(self, view_a, view_b, n_check) -> str:
        a, b, m = int(view_a), int(view_b), int(n_check)
        if a == b:
            self.chain = None
            self._geometry((a,))
            self._names[0].set_text("A = B")
            self._names[1].set_visible(False)
            self._errors(None)
            self._message.set_visible(True)
            self._geo_title.set_text(f"A = B = {view_name(a)}")
            self._err_title.set_text("")
            return (f"<b>View A and view B are the same photograph ({view_name(a)}).</b><br>"
                    "Two rays of one camera meet only at its centre: a forward intersection "
                    "needs two views from different places. Move one of the sliders.")
        alpha = intersection_angle(a, b)
        self.chain = ch = chain(a, b, self.check_points(m))
        self._geometry((a, b))
        self._names[0].set_text("A")
        self._names[1].set_visible(True)
        self._errors(ch)
        self._message.set_visible(False)
        self._geo_title.set_text(f"intersection angle {alpha:.1f}°")
        self._err_title.set_text(f"check-point errors ×{self.SCALE:g} (1σ bars)")
        ra, rb = ch.resections
        sz = np.sqrt(np.mean(ch.predicted[:, 2] ** 2))
        warn = ("<br><b>Small intersection angle</b> (&lt; 15°): the rays meet at a glancing "
                "angle, Z along the viewing direction is poorly determined."
                if alpha < MIN_ANGLE_DEG else "")
        return (f"<b>A</b> = {view_name(a)}, <b>B</b> = {view_name(b)}: α = {alpha:.1f}°<br>"
                f"control points {len(ch.control)}, check points {len(ch.check)}<br>"
                f"resection σ0: A {ra.sigma0:.3f} px, B {rb.sigma0:.3f} px "
                f"(r = {ra.redundancy})<br>"
                f"check-point RMS <b>{ch.rms:.3f} mm</b><br>"
                f"predicted from σ0 and Σqq: {ch.predicted_rms:.3f} mm "
                f"(of it σZ {sz:.3f} mm)<br>"
                f"accuracy / precision = {ch.rms / ch.predicted_rms:.2f}" + warn)


class NoiseExplorer(Explorer):
    """A poorer measurement: add Gaussian noise σ to every measured image coordinate of both
    views (one seeded draw, scaled by σ) and run the chain again. The resections' σ0 grows as
    √(σ0,real² + σ²), and the check points' RMS follows the prediction."""

    title = "noise on the measurement: σ0, check-point RMS and their prediction"
    SIGMAS = np.round(np.linspace(0.0, 2.0, 9), 6)

    def __init__(self, view_a: int = 2, view_b: int = 11, check=(4, 13, 20, 31, 39, 48),
                 sigma: float = 0.5, draw: int = 0):
        if int(view_a) == int(view_b):
            raise ValueError(f"the two views must differ, got {view_a!r} twice")
        self.views, self.check = (int(view_a), int(view_b)), tuple(int(k) for k in check)
        self.real = chain(*self.views, self.check)
        self.controls = {
            "sigma": slider("added noise σ [px]", sigma, 0.0, 2.0, 0.05, fmt=".2f"),
            "draw": slider("noise draw", draw, 0, 9, 1, fmt=".0f"),
        }
        self.live = LiveFigure((7.4, 3.1))
        fig = self.live.figure
        self._s0, self._rms = fig.add_subplot(1, 2, 1), fig.add_subplot(1, 2, 2)
        fig.subplots_adjust(0.09, 0.16, 0.98, 0.9, wspace=0.32)
        s = np.linspace(0, 2, 50)
        s0 = np.hypot(self._real_sigma0(), s)
        self._s0.plot(s, s0, "--", color="0.4", label="√(σ0,real² + σ²)")
        self._s0.set(xlabel="added noise σ [px]", ylabel="σ0 [px]", xlim=(0, 2),
                     ylim=(0, 2.2))
        self._s0.set_title("resections' σ0", fontsize=9)
        (self._s0_line,) = self._s0.plot([], [], "o-", color="tab:blue", ms=3,
                                         label="σ0 (A and B pooled)")
        self._s0.legend(loc="upper left", fontsize=7)
        self._rms.set(xlabel="added noise σ [px]", ylabel="RMS [mm]", xlim=(0, 2))
        self._rms.set_title("check points", fontsize=9)
        (self._rms_line,) = self._rms.plot([], [], "o-", color="tab:red", ms=3,
                                           label="RMS of the errors")
        (self._pred_line,) = self._rms.plot([], [], "s--", color="tab:gray", ms=3,
                                            label="predicted")
        self._rms.legend(loc="upper left", fontsize=7)
        self._marks = [self.live.animate(ax.axvline(0, color="tab:green", lw=1.2))
                       for ax in (self._s0, self._rms)]
        self._curve_draw = None
        self.chain = None
        self._finish()

    def _real_sigma0(self) -> float:
        return _pooled_sigma0(self.real)

    def noise(self, sigma: float, draw: int) -> np.ndarray:
        """(2, 54, 2) px: draw number ``draw`` of standard normal numbers, times ``sigma``."""
        n = BOARD[0] * BOARD[1]
        return float(sigma) * np.random.default_rng(1000 + int(draw)).standard_normal((2, n, 2))

    def _curve(self, draw: int) -> None:
        runs = [chain(*self.views, self.check, self.noise(s, draw)) for s in self.SIGMAS]
        self._s0_line.set_data(self.SIGMAS, [_pooled_sigma0(c) for c in runs])
        self._rms_line.set_data(self.SIGMAS, [c.rms for c in runs])
        self._pred_line.set_data(self.SIGMAS, [c.predicted_rms for c in runs])
        top = max(max(c.rms for c in runs), max(c.predicted_rms for c in runs))
        self._rms.set_ylim(0, 1.15 * top)
        self._curve_draw = draw
        self.live.invalidate()

    def draw(self, sigma, draw) -> str:
        draw = int(draw)
        if draw != self._curve_draw:
            self._curve(draw)
        self.chain = ch = chain(*self.views, self.check, self.noise(sigma, draw))
        for mark in self._marks:
            mark.set_xdata([sigma, sigma])
        s0 = _pooled_sigma0(ch)
        expect = float(np.hypot(self._real_sigma0(), sigma))
        return (f"views {view_name(self.views[0])}, {view_name(self.views[1])}; "
                f"added σ = {sigma:.2f} px (draw {draw})<br>"
                f"resections' σ0 {s0:.3f} px (expected √({self._real_sigma0():.3f}² + "
                f"{sigma:.2f}²) = {expect:.3f} px)<br>"
                f"check-point RMS <b>{ch.rms:.3f} mm</b>, predicted {ch.predicted_rms:.3f} mm<br>"
                f"without added noise: {self.real.rms:.3f} mm, predicted "
                f"{self.real.predicted_rms:.3f} mm")


def _pooled_sigma0(ch: Chain) -> float:
    """σ0 of both resections pooled by redundancy, px."""
    ra, rb = ch.resections
    return float(np.sqrt((ra.sigma0**2 * ra.redundancy + rb.sigma0**2 * rb.redundancy)
                         / (ra.redundancy + rb.redundancy)))
