"""Real photographs in chapters 05 and 08: the chessboard camera of :func:`photolib.data.chessboard`.

OpenCV is the measuring tool only: ``cv2.findChessboardCorners`` and ``cv2.cornerSubPix`` find
the 54 inner corners of each view (pixels, (col, row), (0, 0) at the centre of the top-left
pixel: OpenCV's pixel origin is the course's). Everything else is the course's mathematics —
:func:`photolib.testfield.plane_field_calibration` (the bundle adjustment with the board
points fixed) and :func:`photolib.space_resection` — and OpenCV's own ``calibrateCamera`` and
``solvePnP`` are run beside it for comparison, through the mapping of docs/conventions.md
(OpenCV row): ``c = f``, ``x'0 = cx − (W − 1)/2``, ``y'0 = (H − 1)/2 − cy``,
``R_cv = diag(1, −1, −1)·Rᵀ``, ``t = −R_cv·X0``.

The pixel pitch of this camera is not published, so the image unit is the pixel: c, x'0, y'0
and σ0 are in px, A1 in px⁻², A2 in px⁻⁴, A3 in px⁻⁶, B1, B2 in px⁻¹.
"""

from __future__ import annotations

import functools
from dataclasses import dataclass

import numpy as np

import photolib as pl
import photolib.data as pdata
from photolib.nb.live import finished

__all__ = [
    "SUBPIX_WINDOW",
    "ChessboardCalibration",
    "Resection",
    "chessboard_calibration",
    "detect_corners",
    "interior_rows",
    "opencv_radial_distortion",
    "plot_corner",
    "show_task_corner",
    "plot_real_distortion",
    "plot_real_residuals",
    "radial_comparison",
    "ray_difference",
    "resect_view",
]

#: half window of cornerSubPix (px): an 11 × 11 search window. (OpenCV's tutorial passes
#: (11, 11), a 23 × 23 window, which reaches past the neighbouring corners of this board's
#: small squares: chapter 05 shows what that does.)
SUBPIX_WINDOW = (5, 5)
#: cornerSubPix stops after 30 iterations or a step below 0.001 px
SUBPIX_CRITERIA = (3, 30, 0.001)  # cv2.TERM_CRITERIA_EPS + cv2.TERM_CRITERIA_MAX_ITER == 3


def _cv2():
    try:
        import cv2
    except ModuleNotFoundError:
        raise pdata.DataPackageMissing(
            f"the corner measurement needs OpenCV (opencv-python-headless): run "
            f"{pdata.INSTALL}") from None
    return cv2


def detect_corners(image, board=(9, 6), window=SUBPIX_WINDOW) -> np.ndarray:
    """Inner chessboard corners of a grey image, (col, row) px, shape (columns·rows, 2).

    ``cv2.findChessboardCorners`` (default flags) then ``cv2.cornerSubPix`` with the half
    window ``window`` (px; the search window is ``2·window + 1`` wide) and
    :data:`SUBPIX_CRITERIA`. Corner ``k = columns·j + i`` is the i-th of the j-th row as OpenCV
    orders them.

    Raises
    ------
    ValueError
        When the image is not a 2-D uint8 array or the board is not found.
    """
    cv2 = _cv2()
    img = np.asarray(image)
    if img.ndim != 2 or img.dtype != np.uint8:
        raise ValueError(f"image must be a grey (H, W) uint8 array, got shape {img.shape} and "
                         f"dtype {img.dtype}")
    found, corners = cv2.findChessboardCorners(img, tuple(board))
    if not found:
        raise ValueError(f"cv2.findChessboardCorners found no {board[0]} × {board[1]} board")
    corners = cv2.cornerSubPix(img, corners, tuple(window), (-1, -1), SUBPIX_CRITERIA)
    return corners.reshape(-1, 2).astype(float)


@dataclass(frozen=True)
class ChessboardCalibration:
    """The chessboard camera calibrated by the course and by OpenCV from the same corners."""

    files: tuple  #: the views used
    width: int  #: px
    height: int  #: px
    object_points: np.ndarray  #: (54, 3) mm, Z = 0
    corners: tuple  #: per view (54, 2) (col, row), px
    xy: tuple  #: per view (54, 2) image coordinates (x' right, y' up, origin image centre), px
    result: object  #: BundleResult of plane_field_calibration (image unit px, object mm)
    opencv: dict  #: cv2.calibrateCamera on the same corners: rms, K, dist, rvecs, tvecs
    published: object  #: photolib.data.OpenCVCalibration of left_intrinsics.yml

    @property
    def sigma(self) -> dict:
        """Standard deviation of each estimated interior parameter (its unit), σ0-scaled."""
        r = self.result
        return dict(zip(r.calibrate, np.sqrt(np.diag(r.interior_covariance))))

    def opencv_interior(self, which: str = "opencv") -> dict:
        """``{'c', 'x0', 'y0'}`` (px) of OpenCV's (``'opencv'``) or the published calibration
        (``'published'``) in the course's frame: ``x'0 = cx − (W − 1)/2``, ``y'0 = (H − 1)/2 − cy``."""
        K = self.opencv["K"] if which == "opencv" else self.published.camera_matrix
        if which not in ("opencv", "published"):
            raise ValueError(f"which must be 'opencv' or 'published', got {which!r}")
        return {"c": float(K[0, 0]), "x0": float(K[0, 2] - (self.width - 1) / 2),
                "y0": float((self.height - 1) / 2 - K[1, 2])}

    @property
    def r_data(self) -> float:
        """Largest distance of a measured corner from the principal point, px: beyond it the
        distortion polynomials are extrapolated."""
        pp = np.array([self.result.x0, self.result.y0])
        return float(max(np.hypot(*(q - pp).T).max() for q in self.xy))

    def opencv_sigma0(self) -> float:
        """OpenCV's residuals as σ0 of one image coordinate, px: ``rms·√(n_points/r)``.

        ``calibrateCamera`` returns ``rms = √(Σ|e|²/n_points)`` (per point, both coordinates);
        with ``n = 2·n_points`` coordinates and the redundancy r of the same adjustment
        (OpenCV estimates the same number of unknowns here: f, cx, cy, k1, k2, p1, p2, k3 and
        6 per view), ``σ0² = Σ|e|²/r``.
        """
        n_points = sum(len(c) for c in self.corners)
        return float(self.opencv["rms"] * np.sqrt(n_points / self.result.redundancy))


@functools.lru_cache(maxsize=4)
def chessboard_calibration(window=SUBPIX_WINDOW) -> ChessboardCalibration:
    """Calibrate the chessboard camera from all 14 views (cached per ``window``).

    ``window`` is the half window of ``cornerSubPix`` (:func:`detect_corners`).

    The course: :func:`photolib.testfield.plane_field_calibration` with c, x'0, y'0, A1–A3,
    B1, B2 (Seidel, r0 = 0) on the image coordinates ``x' = col − 319.5``, ``y' = 239.5 − row``
    (px). OpenCV: ``cv2.calibrateCamera`` on the same corners and board points with the
    model of the same size (``CALIB_FIX_ASPECT_RATIO``: fx = fy, as the published file).
    """
    cv2 = _cv2()
    from photolib.testfield import plane_field_calibration
    cb = pdata.chessboard()
    W, H = cb.sizes[0]
    corners = tuple(detect_corners(im, window=window) for im in cb.images)
    xy = tuple(pl.image_from_pixel(c, W, H, 1.0) for c in corners)
    obj = cb.extra["object_points"]
    result = plane_field_calibration(xy, obj)
    rms, K, dist, rvecs, tvecs = cv2.calibrateCamera(
        [obj.astype(np.float32)] * len(corners), [c.astype(np.float32) for c in corners], (W, H),
        np.diag([500.0, 500.0, 1.0]), None, flags=cv2.CALIB_FIX_ASPECT_RATIO)
    opencv = {"rms": float(rms), "K": K, "dist": dist.ravel(),
              "rvecs": [r.ravel() for r in rvecs], "tvecs": [t.ravel() for t in tvecs]}
    return ChessboardCalibration(cb.files, W, H, obj, corners, xy, result, opencv,
                                 cb.calibration)


def interior_rows(cal: ChessboardCalibration) -> list[str]:
    """Printable rows: c, x'0, y'0 (px, 0.01 px) of the course (± σ), OpenCV and the published
    file, and the differences in units of the course's σ."""
    r, s = cal.result, cal.sigma
    ours = {"c": r.c, "x0": r.x0, "y0": r.y0}
    cv, pub = cal.opencv_interior("opencv"), cal.opencv_interior("published")
    rows = [f"{'[px]':10s} {'photolib ± σ':>16s} {'OpenCV':>9s} {'published':>10s}"
            f" {'(OpenCV − ours)/σ':>18s} {'(published − ours)/σ':>21s}"]
    for k, label in (("c", "c"), ("x0", "x'0"), ("y0", "y'0")):
        rows.append(f"{label:10s} {ours[k]:8.2f} ± {s[k]:5.2f} {cv[k]:9.2f} {pub[k]:10.2f}"
                    f" {(cv[k] - ours[k]) / s[k]:+18.1f} {(pub[k] - ours[k]) / s[k]:+21.1f}")
    return rows


def opencv_radial_distortion(coefficients, f, r) -> np.ndarray:
    """OpenCV's radial distortion Δr′ = r − ρ at **measured** radii r (px).

    OpenCV maps the ideal normalised radius ρ/f to ``r = ρ(1 + k1ρn² + k2ρn⁴ + k3ρn⁶)``,
    ``ρn = ρ/f``; ρ is found by Newton's method (10 steps from ρ = r; monotone over the
    format of this lens). Tangential terms are left out (they are not radial).
    """
    k1, k2, _, _, k3 = (float(v) for v in coefficients)
    r = np.asarray(r, dtype=float)
    rho = r.copy()
    for _ in range(10):
        n2 = (rho / f) ** 2
        g = rho * (1 + k1 * n2 + k2 * n2**2 + k3 * n2**3) - r
        dg = 1 + 3 * k1 * n2 + 5 * k2 * n2**2 + 7 * k3 * n2**3
        rho = rho - g / dg
    return r - rho


def radial_comparison(cal: ChessboardCalibration, radii) -> dict:
    """Δr′ (px) at measured radii r (px): the course's with its σ, OpenCV's, the published.

    The course's ``Δr′ = A1r³ + A2r⁵ + A3r⁷`` (r0 = 0), ``σ² = gᵀCg`` with
    ``g = (r³, r⁵, r⁷)`` and C the covariance of A1–A3 from the adjustment.
    """
    r = np.asarray(radii, dtype=float)
    res = cal.result
    idx = [res.calibrate.index(t) for t in ("A1", "A2", "A3")]
    C = res.interior_covariance[np.ix_(idx, idx)]
    g = np.stack([r**3, r**5, r**7], axis=-1)
    return {"r": r, "ours": res.distortion.radial_profile(r),
            "sigma": np.sqrt(np.einsum("...i,ij,...j->...", g, C, g)),
            "opencv": opencv_radial_distortion(cal.opencv["dist"], cal.opencv["K"][0, 0], r),
            "published": opencv_radial_distortion(cal.published.distortion,
                                                  cal.published.f_px, r)}


def ray_difference(cal: ChessboardCalibration, step: int = 20) -> dict:
    """How far apart the two calibrations put the ray of each pixel, px, where there are data.

    For a grid of measured pixels (every ``step`` px) within ``cal.r_data`` of the principal
    point (outside, both polynomials are extrapolated), the course's ideal point
    ``(x' − x'0 − Δx', y' − y'0 − Δy')/c`` and OpenCV's ``cv2.undistortPointsIter`` (y down,
    so y flipped) are normalised image coordinates of the ray; their difference times c is
    reported (max and RMS, px). It contains the differences of c and the principal point
    too: what the exterior orientations of the images do not absorb.
    """
    cv2 = _cv2()
    res = cal.result
    cols, rows = np.meshgrid(np.arange(0, cal.width, step, dtype=float),
                             np.arange(0, cal.height, step, dtype=float))
    px = np.column_stack([cols.ravel(), rows.ravel()])
    xy = pl.image_from_pixel(px, cal.width, cal.height, 1.0) - [res.x0, res.y0]
    inside = np.hypot(*xy.T) <= cal.r_data
    px, xy = px[inside], xy[inside]
    ours = res.distortion.correct(xy) / res.c
    ours[:, 1] *= -1.0
    crit = (cv2.TERM_CRITERIA_COUNT + cv2.TERM_CRITERIA_EPS, 200, 1e-12)
    theirs = cv2.undistortPoints(px.reshape(-1, 1, 2), cal.opencv["K"], cal.opencv["dist"],
                                 None, None, None, crit).reshape(-1, 2)
    d = np.hypot(*(ours - theirs).T) * res.c
    return {"max_px": float(d.max()), "rms_px": float(np.sqrt(np.mean(d**2))),
            "pixels": px, "difference_px": d}


def plot_corner(file: str, col: float, row: float, half: int = 24):
    """A chessboard view with one measured corner: the whole image and a zoom on the corner.

    ``file`` is a view of :func:`photolib.data.chessboard` (``"left05.jpg"``), ``col, row`` the
    corner in px (pixel centres at integers, row down), ``half`` the zoom's half width in px.
    """
    import matplotlib.pyplot as plt

    cb = pdata.chessboard()
    if file not in cb.files:
        raise ValueError(f"no view {file!r} in the chessboard set; views: {list(cb.files)}")
    image = cb.images[list(cb.files).index(file)]
    fig, (whole, zoom) = plt.subplots(1, 2, figsize=(8.0, 3.2),
                                      gridspec_kw={"width_ratios": (1.5, 1)})
    whole.imshow(image, cmap="gray")
    whole.plot([col], [row], "+", color="#d62728", ms=14, mew=2)
    whole.add_patch(plt.Rectangle((col - half, row - half), 2 * half, 2 * half, fill=False,
                                  color="#ff7f0e", lw=1))
    whole.set(title=f"{file}: the corner at ({col:.2f}, {row:.2f}) px", xlabel="col [px]",
              ylabel="row [px]")
    zoom.imshow(image, cmap="gray", interpolation="nearest")
    zoom.plot([col], [row], "+", color="#d62728", ms=18, mew=1.5)
    zoom.set(xlim=(col - half, col + half), ylim=(row + half, row - half),
             title=f"zoom ±{half} px: pixel centres at integers", xlabel="col [px]")
    fig.tight_layout()
    return finished(fig)


def show_task_corner(params):
    """:func:`plot_corner` of a task's numbers (``p_corner = task("io.real-corner")``).

    While ``STUDENT_ID`` is empty the task issues no numbers: one line says so, no figure.
    """
    from photolib.grading.notebook import NO_STUDENT_ID, NoParameters

    if type(params) is NoParameters:
        print(f"no image to show: {NO_STUDENT_ID}")
        return None
    return plot_corner(params["file"], params["col"], params["row"])


def plot_real_residuals(cal: ChessboardCalibration, scale: float = 100.0):
    """Residual vectors v of all views in the image format (× ``scale``), and their histogram."""
    import matplotlib.pyplot as plt

    res = cal.result
    xy = np.vstack(cal.xy)
    v = res.residuals
    fig, (ax, ax2) = plt.subplots(1, 2, figsize=(8.0, 3.2),
                                  gridspec_kw={"width_ratios": (1.5, 1)})
    ax.quiver(xy[:, 0], xy[:, 1], v[:, 0], v[:, 1], np.hypot(*v.T), angles="xy",
              scale_units="xy", scale=1.0 / scale, width=0.003, cmap="viridis")
    hw, hh = cal.width / 2, cal.height / 2
    ax.plot([-hw, hw, hw, -hw, -hw], [-hh, -hh, hh, hh, -hh], color="0.5", lw=1)
    ax.set(aspect="equal", xlabel="x' [px]", ylabel="y' [px]",
           title=f"residuals v of {len(cal.xy)} views (× {scale:g})")
    edges = np.linspace(-4, 4, 41) * res.sigma0
    ax2.hist(v.ravel(), bins=edges, color="#1f77b4", alpha=0.8)
    ax2.set(xlabel="v [px]", ylabel="count", title=f"σ0 = {res.sigma0:.2f} px")
    fig.tight_layout()
    return finished(fig)


def plot_real_distortion(cal: ChessboardCalibration, n_lines: int = 9):
    """Left: a straight grid over the format as this lens images it (true size, no
    exaggeration); right: Δr′(r′) of the course (± 3σ band), OpenCV and the published file,
    up to ``cal.r_data`` (no extrapolation)."""
    import matplotlib.pyplot as plt

    res = cal.result
    hw, hh = (cal.width - 1) / 2, (cal.height - 1) / 2
    pp = np.array([res.x0, res.y0])
    fig, (ax, ax2) = plt.subplots(1, 2, figsize=(8.0, 3.2),
                                  gridspec_kw={"width_ratios": (1.3, 1)})
    t = np.linspace(-1.0, 1.0, 41)
    for u in np.linspace(-1.0, 1.0, n_lines):
        for line in (np.column_stack([t * hw, np.full_like(t, u * hh)]),
                     np.column_stack([np.full_like(t, u * hw), t * hh])):
            ax.plot(*line.T, color="0.8", lw=0.8)
            ax.plot(*(pp + res.distortion.distort(line - pp)).T, color="#1f77b4", lw=1)
    ax.plot([-hw, hw, hw, -hw, -hw], [-hh, -hh, hh, hh, -hh], color="0.5", lw=1)
    ax.set(aspect="equal", xlabel="x' [px]", ylabel="y' [px]",
           title="a straight grid, imaged (true size)")
    rc = radial_comparison(cal, np.linspace(0.0, cal.r_data, 60))
    ax2.fill_between(rc["r"], rc["ours"] - 3 * rc["sigma"], rc["ours"] + 3 * rc["sigma"],
                     color="#1f77b4", alpha=0.25, lw=0, label="photolib ± 3σ")
    ax2.plot(rc["r"], rc["ours"], color="#1f77b4", label="photolib")
    ax2.plot(rc["r"], rc["opencv"], "--", color="#d62728", label="OpenCV, same corners")
    ax2.plot(rc["r"], rc["published"], ":", color="k", label="published file")
    ax2.set(xlabel="measured r' [px]", ylabel="Δr' [px]",
            title="radial distortion")
    ax2.legend(fontsize=8, loc="lower left")
    fig.tight_layout()
    return finished(fig)


@dataclass(frozen=True)
class Resection:
    """One view resected by the course and by ``cv2.solvePnP``, poses in the course's frame."""

    index: int  #: the view (0-based)
    ours: object  #: photolib ResectionResult (object unit mm, image unit px)
    same_input: tuple  #: (X0, R) of solvePnP on the corrected points with the course's c, x'0, y'0
    opencv_own: tuple  #: (X0, R) of solvePnP on the raw corners with OpenCV's own K, dist
    bundle: tuple  #: (X0, R) of the view in the calibration, and its (6, 6) covariance


def _pose(cv2, rvec, tvec):
    R_cv, _ = cv2.Rodrigues(np.asarray(rvec, dtype=float).reshape(3, 1))
    return pl.exterior_from_opencv_pose(R_cv, np.asarray(tvec, dtype=float).ravel())


def resect_view(cal: ChessboardCalibration, index: int = 0) -> Resection:
    """Space resection of one chessboard view with the calibration, and OpenCV's solvePnP.

    The course: :func:`photolib.space_resection` with c, x'0, y'0 and the distortion of
    ``cal.result`` (start from the plane homography, :func:`photolib.testfield.plane_start`).
    OpenCV, converted by :func:`photolib.exterior_from_opencv_pose`: (1) the same input —
    the distortion-corrected points back in pixels, ``K`` of the course's c, x'0, y'0, no
    distortion, ``SOLVEPNP_ITERATIVE`` then ``solvePnPRefineLM`` to 1e-12; (2) OpenCV's
    own calibration (K, dist of ``calibrateCamera``) on the raw corners.
    """
    from photolib.rotations import rotation_opk
    from photolib.testfield import plane_start
    cv2 = _cv2()
    if not 0 <= index < len(cal.xy):
        raise ValueError(f"index must be 0 … {len(cal.xy) - 1}, got {index!r}")
    res, X, xy = cal.result, cal.object_points, cal.xy[index]
    pp = np.array([res.x0, res.y0])
    ideal = pp + res.distortion.correct(xy - pp)
    _, start = plane_start([ideal - pp], X[:, :2], c=res.c)
    ours = pl.space_resection(X, xy, res.c, res.x0, res.y0, res.distortion, initial=start[0])
    # (1) the same input in OpenCV's terms
    W, H = cal.width, cal.height
    K = np.array([[res.c, 0.0, res.x0 + (W - 1) / 2], [0.0, res.c, (H - 1) / 2 - res.y0],
                  [0.0, 0.0, 1.0]])
    px = pl.pixel_from_image(ideal, W, H, 1.0)
    ok, rvec, tvec = cv2.solvePnP(X, px, K, None, flags=cv2.SOLVEPNP_ITERATIVE)
    crit = (cv2.TERM_CRITERIA_COUNT + cv2.TERM_CRITERIA_EPS, 200, 1e-15)
    rvec, tvec = cv2.solvePnPRefineLM(X, px, K, None, rvec, tvec, crit)
    same = _pose(cv2, rvec, tvec)
    # (2) OpenCV's own calibration on the raw corners
    ok2, rvec2, tvec2 = cv2.solvePnP(X, cal.corners[index], cal.opencv["K"], cal.opencv["dist"],
                                     flags=cv2.SOLVEPNP_ITERATIVE)
    if not (ok and ok2):
        raise ValueError(f"cv2.solvePnP failed on view {index}")
    own = _pose(cv2, rvec2, tvec2)
    e = res.exterior[index]
    bundle = (e[:3].copy(), rotation_opk(*e[3:]), res.exterior_covariance[index])
    return Resection(index, ours, same, own, bundle)
