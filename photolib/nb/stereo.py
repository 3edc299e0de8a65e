"""Chapter 09 pictures and widgets: stereo photogrammetry (Stereophotogrammetrie).

The normal case (Normalfall) of the course: camera 1 at the origin, camera 2 at (B, 0, 0),
both with R = I, looking down −Z; an object point at distance h has Z = −h. A camera with
c = 50 mm and a 36 mm × 24 mm format. :func:`pair_report` computes parallax, Z and the
accuracy with :func:`photolib.height_from_parallax` and :func:`photolib.normal_case_accuracy`;
:func:`epipolar_report` the epipolar line of a point of image 1 in a rotated image 2 with
:func:`photolib.essential_matrix`, :func:`photolib.fundamental_matrix` and
:func:`photolib.epipolar_lines`. :func:`pair_scene` is the convergent pair of the relative and
absolute orientation sections.
"""

from __future__ import annotations

import functools

import numpy as np

import photolib as pl
from photolib.nb.draw import format_corners, house_edges, lines_xyz
from photolib.nb.live import Explorer, LiveFigure, finished, slider
from photolib.nb.text import matrix_html

__all__ = [
    "BASE_M",
    "C_MM",
    "HALF",
    "EpipolarExplorer",
    "StereoPairExplorer",
    "epipolar_ray_orientation",
    "epipolar_report",
    "object_orientations",
    "pair_report",
    "pair_scene",
    "plot_normal_case",
    "plot_relative_convergence",
    "digitise_house",
    "plot_digitised",
    "relative_history",
]

#: camera constant of the chapter's camera, mm, and its half format, mm
C_MM = 50.0
HALF = (18.0, 12.0)
#: base of the epipolar explorer's pair, m, and the object distance of its point, m
BASE_M = 4.0
_DEPTH_M = 20.0
#: distances (factors of _DEPTH_M) of the points marked along the ray in image 2
_DEPTH_MARKS = (0.6, 0.8, 1.0, 1.3, 1.8)


def pair_report(B: float = 20.0, h: float = 100.0, sigma_px_um: float = 4.0) -> dict:
    """The normal case for a point below the middle of the base, at distance h (m).

    Parameters
    ----------
    B : float
        Base, m.
    h : float
        Object distance (for aerial images: flying height above the point), m.
    sigma_px_um : float
        σ of the x-parallax, µm; one image coordinate is taken as ``σ_px'/√2``
        (x'1 and x'2 measured independently, ``luhmann:example-3.7`` old reading).

    Returns
    -------
    dict
        ``px_mm``, ``Z_m``, ``m``, ``h_over_B``, ``sigma_Z_mm``, ``sigma_XY_mm``,
        ``overlap`` (forward overlap of the two formats, fraction), ``x1_mm``, ``x2_mm``, ``html``.

    Examples
    --------
    >>> rep = pair_report(20.0, 100.0, 4.0)
    >>> round(rep["px_mm"], 6), round(rep["Z_m"], 9), round(rep["sigma_Z_mm"], 6)
    (10.0, -100.0, 40.0)
    """
    x1 = C_MM * (B / 2) / h              # x' = −c·X/Z with X = B/2, Z = −h
    x2 = C_MM * (B / 2 - B) / h
    px = x1 - x2
    Z = pl.height_from_parallax(px, C_MM, B)
    s_px = sigma_px_um * 1e-3
    acc = pl.normal_case_accuracy(h * 1e3, B * 1e3, C_MM, s_px, s_px / np.sqrt(2))
    footprint = 2 * HALF[0] * acc.m * 1e-3          # m along the base
    overlap = max(0.0, 1.0 - B / footprint)
    html = (f"<p>parallax p<sub>x</sub>' = x'<sub>1</sub> − x'<sub>2</sub> = "
            f"{x1:.3f} − ({x2:.3f}) = <b>{px:.3f} mm</b><br>"
            f"Z = −c·B/p<sub>x</sub>' = <b>{Z:.2f} m</b><br>"
            f"scale number m = h/c = {acc.m:.0f}, h/B = {acc.base_ratio:.2f}<br>"
            f"σ<sub>Z</sub> = (h/B)·m·σ<sub>px</sub>' = <b>{acc.sigma_Z:.1f} mm</b><br>"
            f"σ<sub>XY</sub> = m·σ<sub>x</sub>' = {acc.sigma_XY:.1f} mm "
            f"(σ<sub>x</sub>' = σ<sub>px</sub>'/√2)<br>"
            f"forward overlap: {100 * overlap:.0f} %</p>")
    return {"px_mm": px, "Z_m": Z, "m": acc.m, "h_over_B": acc.base_ratio,
            "sigma_Z_mm": acc.sigma_Z, "sigma_XY_mm": acc.sigma_XY, "overlap": overlap,
            "x1_mm": x1, "x2_mm": x2, "html": html}


def _second_camera(phi_deg: float, kappa_deg: float, omega_deg: float = 0.0):
    return np.array([BASE_M, 0.0, 0.0]), pl.rotation_opk(*np.radians([omega_deg, phi_deg,
                                                                      kappa_deg]))


def epipolar_report(x1: float = 5.0, y1: float = 3.0, phi_deg: float = 8.0,
                    kappa_deg: float = 5.0) -> dict:
    """Epipolar line in image 2 of the point (x1, y1) of image 1 (mm).

    Camera 1 at the origin with R = I, camera 2 at (BASE_M, 0, 0) with φ2, κ2 (degrees).

    Returns
    -------
    dict
        ``E``, ``F`` (3, 3); ``line`` (a, b, d) in image 2 with a·x' + b·y' + d = 0;
        ``marks`` (K, 2): the images in image 2 of points on the ray at the distances
        ``_DEPTH_M·_DEPTH_MARKS``; ``segment`` (2, 2): the line clipped to the drawing;
        ``py_mm``: y'2 − y'1 of the mark at ``_DEPTH_M`` (minus the y-parallax
        p_y' = y'1 − y'2); ``html``.

    Examples
    --------
    >>> rep = epipolar_report(5.0, 3.0, 0.0, 0.0)     # the normal case: a horizontal line
    >>> np.round(rep["line"], 12).tolist(), round(rep["py_mm"], 12)
    ([0.0, -1.0, 3.0], 0.0)
    """
    X02, R2 = _second_camera(phi_deg, kappa_deg)
    E = pl.essential_matrix(np.zeros(3), np.eye(3), X02, R2)
    F = pl.fundamental_matrix(E, C_MM, C_MM)
    line = pl.epipolar_lines(F, [x1, y1], image=2)
    ray = np.array([x1, y1, -C_MM]) / C_MM
    pts = np.array([ray * _DEPTH_M * f for f in _DEPTH_MARKS])   # X = λ·x* (R1 = I)
    marks, _ = pl.project(pts, X02, R2, C_MM, return_valid=True)
    a, b, d = line
    if abs(b) >= abs(a):
        xs = np.array([-30.0, 30.0])
        seg = np.column_stack([xs, -(a * xs + d) / b])
    else:
        ys = np.array([-20.0, 20.0])
        seg = np.column_stack([-(b * ys + d) / a, ys])
    mid = marks[_DEPTH_MARKS.index(1.0)]
    py = float(mid[1] - y1)
    html = (f"<p>point in image 1: ({x1:.1f}, {y1:.1f}) mm<br>"
            f"epipolar line in image 2:<br>&nbsp;{a:+.4f}·x' {b:+.4f}·y' {d:+.3f} = 0<br>"
            f"y'<sub>2</sub> − y'<sub>1</sub> of the point at {_DEPTH_M:g} m "
            f"(−p<sub>y</sub>'): <b>{py:+.3f} mm</b><br>"
            f"(0 in the normal case φ2 = κ2 = 0)</p>"
            + matrix_html(E / np.linalg.norm(E), "E / |E| (x*1ᵀ E x*2 = 0)", 3))
    return {"E": E, "F": F, "line": line, "marks": marks, "segment": seg, "py_mm": py,
            "html": html}


def pair_scene(n: int = 20, seed: int = 9, noise_um: float = 2.0):
    """A convergent stereo pair over a field with relief, for the orientation sections.

    Returns
    -------
    dict
        ``X`` (n, 3) object points, m; ``X01``, ``X02`` (3,); ``R1``, ``R2`` (3, 3);
        ``xy1``, ``xy2`` (n, 2) image points, mm, with Gaussian noise ``noise_um`` (µm).

    Examples
    --------
    >>> s = pair_scene()
    >>> s["X"].shape, bool(np.all(np.abs(s["xy1"]) < HALF))
    ((20, 3), True)
    """
    rng = np.random.default_rng(seed)
    X = np.column_stack([rng.uniform(-14.0, 14.0, (n, 2)) * [1.0, 0.65], rng.uniform(0, 6, n)])
    X01, X02 = np.array([-5.0, 0.5, 60.0]), np.array([5.5, -0.5, 61.0])
    R1 = pl.rotation_opk(*np.radians([1.0, -2.0, 3.0]))
    R2 = pl.rotation_opk(*np.radians([-1.5, 2.5, 1.0]))
    z = rng.standard_normal((2, n, 2)) * noise_um * 1e-3
    return {"X": X, "X01": X01, "X02": X02, "R1": R1, "R2": R2,
            "xy1": pl.project(X, X01, R1, C_MM) + z[0],
            "xy2": pl.project(X, X02, R2, C_MM) + z[1]}


def relative_history(xy1, xy2, c, bx, max_iter: int = 8):
    """Parameters (by, bz, ω2, φ2, κ2) after each Gauss–Newton iteration (row 0: start 0).

    Each row k is :func:`photolib.relative_orientation` run with ``max_iter = k``.

    >>> s = pair_scene(noise_um=0.0)
    >>> hist = relative_history(s["xy1"], s["xy2"], C_MM, 1.0, 3)
    >>> hist.shape
    (4, 5)
    """
    rows = [np.zeros(5)]
    for k in range(1, max_iter + 1):
        ro = pl.relative_orientation(xy1, xy2, c, bx, max_iter=k, check=False)
        rows.append(ro.params)
        if ro.converged:
            break
    return np.array(rows)


def digitise_house(B: float = 20.0, h: float = 100.0, noise_um: float = 3.0, seed: int = 4):
    """Stereo digitising (Stereodigitalisierung) of a house in a normal-case pair.

    The house of :func:`photolib.nb.draw.house_edges` (10 m, on the ground at Z = −h) is
    imaged by the normal-case pair; the "operator" sets the floating mark on each corner in
    both images with ``noise_um`` of Gaussian error, and the corners come back by
    :func:`photolib.normal_case_points`.

    Returns
    -------
    dict
        ``edges`` (E, 2, 3) true edges; ``corners`` (P, 3) true corners; ``xy1``, ``xy2``
        (P, 2) measured image points, mm; ``measured`` (P, 3) digitised corners, m;
        ``measured_edges`` (E, 2, 3); ``error_mm`` (P, 3) measured − true; ``sigma`` (σ_XY,
        σ_Z) in mm of :func:`photolib.normal_case_accuracy` (σ_XY = m·σ_x', exact only below
        a projection centre); ``sigma_corners`` (P, 3) σ_X, σ_Y, σ_Z in mm of each corner by
        propagation from the measured x'1, y'1, x'2
        (:func:`photolib.derive.stereo.covariance_two_images`); ``sigma_rms`` (3,) their RMS
        over the corners, the prediction of the RMS error.

    Examples
    --------
    >>> d = digitise_house(noise_um=0.0)
    >>> float(np.abs(d["error_mm"]).max()) < 1e-9
    True
    >>> np.round(digitise_house()["sigma_rms"], 1).tolist()  # mm; X below the base: < m·σ
    [4.6, 6.0, 39.2]
    """
    edges = house_edges(10.0) + np.array([B / 2, 0.0, -h])
    corners, index = np.unique(edges.reshape(-1, 3), axis=0, return_inverse=True)
    z = np.random.default_rng(seed).standard_normal((2, len(corners), 2)) * noise_um * 1e-3
    xy1 = pl.project(corners, np.zeros(3), np.eye(3), C_MM) + z[0]
    xy2 = pl.project(corners, [B, 0.0, 0.0], np.eye(3), C_MM) + z[1]
    measured = pl.normal_case_points(xy1, xy2, C_MM, B)
    s = max(noise_um, 1e-9) * 1e-3
    acc = pl.normal_case_accuracy(h * 1e3, B * 1e3, C_MM, np.sqrt(2) * s, s)
    true1 = pl.project(corners, np.zeros(3), np.eye(3), C_MM)
    true2 = pl.project(corners, [B, 0.0, 0.0], np.eye(3), C_MM)
    per_corner = predicted_sigma_two_images(true1, true2, C_MM, B, s) * 1e3
    return {"edges": edges, "corners": corners, "xy1": xy1, "xy2": xy2, "measured": measured,
            "measured_edges": measured[index.reshape(-1, 2)],
            "error_mm": (measured - corners) * 1e3, "sigma": (acc.sigma_XY, acc.sigma_Z),
            "sigma_corners": per_corner,
            "sigma_rms": np.sqrt(np.mean(per_corner**2, axis=0))}


def epipolar_ray_orientation(X01, R1, X02, R2, c: float, Z: float) -> dict:
    r"""Orientation by epipolar rays (Orientierung nach Kernstrahlen) of an oriented pair.

    The three steps of the German summary, computed: (1) the principal points H1' of image 1
    and H2'' of image 2 (the origins of the image coordinates, which must be reduced to the
    principal point); (2) each is transferred into the neighbouring image: the ground point
    on its axis at height ``Z`` (monoplotting, :func:`photolib.monoplot`) is projected into
    the other image, giving H2' in image 1 and H1'' in image 2; (3) each image is turned in
    its plane about its principal point until its epipolar ray (Kernstrahl) H1'→H2' (image
    1), H1''→H2'' (image 2) runs along +x'. Both rays then lie on the one line y' = 0.

    Both rays are images of the same ground line P1P2, so points on it get no y-parallax.
    For vertical images (ω = φ = 0) the axes are parallel, O1, O2, P1 and P2 lie in one
    epipolar plane and the rays are epipolar lines; with bz = 0 as well the turned pair is
    the normal case. Tilts are not removed: for them see
    :func:`photolib.normal_case_rotation`.

    Parameters
    ----------
    X01, X02 : array_like, shape (3,)
        Projection centres, object unit.
    R1, R2 : array_like, shape (3, 3)
        Rotations camera → object (``R_ω·R_φ·R_κ``).
    c : float
        Camera constant of both images, image unit (> 0).
    Z : float
        Height of the ground plane the principal points are transferred on, object unit.

    Returns
    -------
    dict
        ``H2_in_1`` (2,): H2' in image 1; ``H1_in_2`` (2,): H1'' in image 2 (image unit);
        ``theta`` (2,): direction of each epipolar ray, rad, counter-clockwise from +x';
        ``turn`` (2, 2, 2): the plane rotations ``R(−θ_i)``, so that the turned coordinates
        of image i are ``xy @ turn[i].T``.

    Examples
    --------
    Two vertical images, turned by κ = 10° and −5°, base along X and Y: the turned pair is
    the normal case, all y-parallaxes vanish.

    >>> R1, R2 = (pl.rotation_opk(0.0, 0.0, np.radians(k)) for k in (10.0, -5.0))
    >>> X01, X02 = np.array([0.0, 0.0, 100.0]), np.array([12.0, 5.0, 100.0])
    >>> o = epipolar_ray_orientation(X01, R1, X02, R2, 50.0, 0.0)
    >>> np.round(np.degrees(o["theta"]), 4).tolist()    # atan2(5, 12) − κ_i
    [12.6199, 27.6199]
    >>> X = np.array([[3.0, -8.0, 2.0], [10.0, 9.0, -1.0]])
    >>> a1 = pl.project(X, X01, R1, 50.0) @ o["turn"][0].T
    >>> a2 = pl.project(X, X02, R2, 50.0) @ o["turn"][1].T
    >>> bool(np.abs(a1[:, 1] - a2[:, 1]).max() < 1e-12)
    True
    """
    X01, X02 = (np.asarray(v, float) for v in (X01, X02))
    R1, R2 = (np.asarray(v, float) for v in (R1, R2))
    if not np.isfinite(Z):
        raise ValueError(f"Z must be a finite height, got {Z}")
    P1 = pl.monoplot(np.zeros(2), X01, R1, c, Z=Z)       # ground point of H1'
    P2 = pl.monoplot(np.zeros(2), X02, R2, c, Z=Z)       # ground point of H2''
    H2_in_1 = pl.project(P2, X01, R1, c)
    H1_in_2 = pl.project(P1, X02, R2, c)
    for name, v in (("H2' (in image 1)", H2_in_1), ("H1'' (in image 2)", H1_in_2)):
        if np.hypot(*v) < 1e-9 * c:
            raise ValueError(f"{name} falls on the principal point: the two axes meet the "
                             f"ground plane Z = {Z} in one point, the epipolar ray has no "
                             "direction")
    theta = np.array([np.arctan2(H2_in_1[1], H2_in_1[0]), np.arctan2(-H1_in_2[1], -H1_in_2[0])])
    return {"H2_in_1": H2_in_1, "H1_in_2": H1_in_2, "theta": theta,
            "turn": np.stack([pl.rotation_2d(-t) for t in theta])}


def object_orientations(ro, T):
    r"""Exterior orientations of both images from the relative and absolute orientation.

    Luhmann 4.76 (rotation of a bundle / Drehung eines Bündels): in the model of
    :func:`photolib.relative_orientation` image i has the projection centre
    :math:`\mathbf x_{0i}` (``0`` and ``ro.base``) and the rotation :math:`A_i` (``I`` and
    ``ro.R2``); its rays are :math:`\mathbf x = \mathbf x_{0i} + λA_i\mathbf x^*`. The
    absolute orientation :math:`\mathbf X = \mathbf X_0 + m\,R(ξ, η, ζ)\,\mathbf x` carries
    each ray into :math:`\mathbf X = (\mathbf X_0 + mR\mathbf x_{0i}) + λm\,(RA_i)\mathbf x^*`:
    the projection centre :math:`\mathbf X_{0i} = T(\mathbf x_{0i})` and the rotation

    .. math:: R_i = R(ξ, η, ζ)\,A_i .

    Parameters
    ----------
    ro : photolib.stereo.RelativeOrientation
        Relative orientation (image 1: centre 0, R = I), model unit.
    T : photolib.stereo.AbsoluteOrientation
        Absolute orientation model → object.

    Returns
    -------
    X0 : ndarray, shape (2, 3)
        Projection centres of images 1 and 2, object unit.
    R : ndarray, shape (2, 3, 3)
        Rotations camera → object of images 1 and 2.

    Examples
    --------
    From exact image points the chapter's pair comes back:

    >>> s = pair_scene(noise_um=0.0)
    >>> ro = pl.relative_orientation(s["xy1"], s["xy2"], C_MM, bx=1.0)
    >>> X0, R = object_orientations(ro, pl.absolute_orientation(ro.model, s["X"]))
    >>> bool(np.abs(X0 - [s["X01"], s["X02"]]).max() < 1e-8)
    True
    >>> bool(np.abs(R - [s["R1"], s["R2"]]).max() < 1e-10)
    True
    """
    A = np.stack([np.eye(3), np.asarray(ro.R2, float)])
    X0 = np.stack([T(np.zeros(3)), T(np.asarray(ro.base, float))])
    return X0, np.einsum("ij,njk->nik", np.asarray(T.R, float), A)


@functools.lru_cache(maxsize=1)
def _sigma_two_images_function():
    """The lambdified σ_X, σ_Y, σ_Z of :func:`photolib.derive.stereo.covariance_two_images`."""
    import sympy as sp

    from photolib.derive import stereo as ds
    cov = ds.covariance_two_images()
    return sp.lambdify((ds.x1, ds.y1, ds.x2, ds.B, ds.c, ds.s_x),
                       [sp.sqrt(cov[i, i]) for i in range(3)], "numpy")


def predicted_sigma_two_images(xy1, xy2, c: float, B: float, sigma: float) -> np.ndarray:
    """σ_X, σ_Y, σ_Z of normal-case points whose x'1, y'1, x'2 are measured with σ ``sigma``.

    The diagonal of :func:`photolib.derive.stereo.covariance_two_images`, lambdified; image
    coordinates reduced to the principal point, ``sigma`` and ``c`` in the image unit, B and
    the result in the object unit. Shape (N, 3).

    >>> s = predicted_sigma_two_images([[5.0, 0.0]], [[-5.0, 0.0]], 50.0, 20.0, 0.003)
    >>> np.round(s * 1e3, 3).tolist()          # mm: m·σ/√2, m·σ, √2·(h/B)·m·σ
    [[4.243, 6.0, 42.426]]
    """
    f = _sigma_two_images_function()
    a, b = np.atleast_2d(np.asarray(xy1, float)), np.atleast_2d(np.asarray(xy2, float))
    out = f(a[:, 0], a[:, 1], b[:, 0], float(B), float(c), float(sigma))
    return np.column_stack([np.broadcast_to(np.asarray(v, float), (len(a),)) for v in out])


# -- static figures -------------------------------------------------------------------------------

def plot_normal_case(B=20.0, h=100.0, title="normal case / Normalfall (X–Z section)"):
    """Side view of the normal case: two cameras, their fields of view and one point."""
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(6.0, 3.2))
    _draw_pair(ax, B, h)
    ax.set_title(title)
    return finished(fig)


def _draw_pair(ax, B, h):
    w = HALF[0] / C_MM
    for X0, colour in ((0.0, "#1f77b4"), (B, "#d62728")):
        ax.plot([X0 - w * h, X0, X0 + w * h], [-h, 0, -h], color=colour, lw=1)
        ax.plot([X0 - w * 0.1 * h, X0 + w * 0.1 * h], [-0.1 * h] * 2, color=colour, lw=2)
        ax.plot([X0, B / 2], [0, -h], "--", color=colour, lw=1)
    ax.plot([B / 2], [-h], "o", color="k", ms=4)
    ax.annotate("", xy=(B, 0.05 * h), xytext=(0, 0.05 * h),
                arrowprops={"arrowstyle": "<->", "color": "0.3"})
    ax.text(B / 2, 0.08 * h, "B", ha="center", va="bottom")
    ax.set(xlabel="X [m]", ylabel="Z [m]", aspect="equal", ylim=(-1.08 * h, 0.25 * h))


def plot_digitised(d, title="stereo digitising: plan and elevation"):
    """Plan (X–Y) and side view (X–Z) of the true and the digitised house."""
    import matplotlib.pyplot as plt

    fig, (ax, bx) = plt.subplots(1, 2, figsize=(7.0, 3.0))
    for axis, (i, j) in ((ax, (0, 1)), (bx, (0, 2))):
        true, meas = lines_xyz(d["edges"]), lines_xyz(d["measured_edges"])
        axis.plot(true[i], true[j], color="0.6", lw=3, label="true")
        axis.plot(meas[i], meas[j], color="#d62728", lw=1, label="digitised")
        axis.set(aspect="equal", xlabel="XYZ"[i] + " [m]", ylabel="XYZ"[j] + " [m]")
    ax.legend(fontsize=8)
    fig.suptitle(title)
    return finished(fig)


def plot_relative_convergence(history, reference, title="relative orientation: convergence"):
    """‖q − q̂‖ per iteration of :func:`relative_history` (q = by, bz, ω2, φ2, κ2)."""
    import matplotlib.pyplot as plt

    err = np.maximum(np.linalg.norm(np.asarray(history) - np.asarray(reference), axis=1), 1e-16)
    fig, ax = plt.subplots(figsize=(5.2, 3.0))
    ax.semilogy(np.arange(len(err)), err, "o-", ms=4)
    ax.set(xlabel="iteration", ylabel="‖q − q̂‖ [model unit, rad]", title=title,
           ylim=(1e-16, 1.0))
    return finished(fig)


# -- widgets --------------------------------------------------------------------------------------

class StereoPairExplorer(Explorer):
    """Base B, object distance h and parallax σ → parallax, Z and σ_Z with both fields of view."""

    title = "stereo pair explorer"
    B_RANGE = np.linspace(2.0, 80.0, 79)
    EXAGGERATE = 100.0

    def __init__(self, B=20.0, h=100.0, sigma_px_um=4.0):
        self.controls = {"B": slider("base B [m]", B, 2, 80, 1, fmt=".0f"),
                         "h": slider("distance h [m]", h, 20, 300, 5, fmt=".0f"),
                         "sigma_px_um": slider("σ px' [µm]", sigma_px_um, 0.5, 20, 0.5)}
        self.live = LiveFigure((7.4, 3.0))
        fig = self.live.figure
        ax = fig.add_subplot(1, 2, 1)
        bx = fig.add_subplot(1, 2, 2)
        fig.subplots_adjust(0.1, 0.17, 0.98, 0.9, wspace=0.35)
        ax.set(xlim=(-120, 200), ylim=(-320, 30), xlabel="X [m]", ylabel="Z [m]",
               title="fields of view (X–Z)")
        self._fov = [ax.plot([], [], color=col, lw=1)[0] for col in ("#1f77b4", "#d62728")]
        self._rays = [ax.plot([], [], "--", color=col, lw=1)[0] for col in ("#1f77b4", "#d62728")]
        (self._point,) = ax.plot([], [], "o", color="k", ms=4)
        (self._band,) = ax.plot([], [], color="#2ca02c", lw=6, alpha=0.6)
        bx.set(xlim=(0, 82), ylim=(1, 1e4), yscale="log", xlabel="base B [m]",
               ylabel="σ_Z [mm]", title="σ_Z over the base at this h")
        (self._curve,) = bx.plot([], [], color="#2ca02c")
        (self._marker,) = bx.plot([], [], "o", color="#d62728", ms=6)
        for artist in (*self._fov, *self._rays, self._point, self._band, self._curve,
                       self._marker):
            self.live.animate(artist)
        self.report = None
        self._finish()

    def draw(self, B, h, sigma_px_um) -> str:
        self.report = rep = pair_report(B, h, sigma_px_um)
        w = HALF[0] / C_MM
        for line, X0 in zip(self._fov, (0.0, B)):
            line.set_data([X0 - w * h, X0, X0 + w * h], [-h, 0.0, -h])
        for line, X0 in zip(self._rays, (0.0, B)):
            line.set_data([X0, B / 2], [0.0, -h])
        self._point.set_data([B / 2], [-h])
        half = rep["sigma_Z_mm"] * 1e-3 * self.EXAGGERATE   # σ_Z (mm) as metres, enlarged
        self._band.set_data([B / 2, B / 2], [-h - half, -h + half])
        # σ_Z ∝ 1/B at fixed h: one library value scaled over the base range
        self._curve.set_data(self.B_RANGE, rep["sigma_Z_mm"] * B / self.B_RANGE)
        self._marker.set_data([B], [rep["sigma_Z_mm"]])
        return rep["html"] + f"<p style='color:#2ca02c'>green bar: ±σ<sub>Z</sub> ×{self.EXAGGERATE:g}</p>"


class EpipolarExplorer(Explorer):
    """A point in image 1 and the rotation of image 2 → its epipolar line in image 2."""

    title = "epipolar line explorer"

    def __init__(self, x1=5.0, y1=3.0, phi_deg=8.0, kappa_deg=5.0):
        self.controls = {"x1": slider("x'1 [mm]", x1, -18, 18, 0.5),
                         "y1": slider("y'1 [mm]", y1, -12, 12, 0.5),
                         "phi_deg": slider("φ2 [°]", phi_deg, -20, 20, 0.5),
                         "kappa_deg": slider("κ2 [°]", kappa_deg, -30, 30, 0.5)}
        self.live = LiveFigure((7.4, 2.8))
        fig = self.live.figure
        a1 = fig.add_subplot(1, 2, 1)
        a2 = fig.add_subplot(1, 2, 2)
        fig.subplots_adjust(0.08, 0.17, 0.98, 0.9, wspace=0.25)
        for ax, name in ((a1, "image 1 (R = I)"), (a2, "image 2 (φ2, κ2)")):
            ax.plot(*format_corners(*HALF).T, color="0.5", lw=1)
            ax.set(xlim=(-24, 24), ylim=(-16, 16), aspect="equal", xlabel="x' [mm]",
                   ylabel="y' [mm]", title=name)
        (self._p1,) = a1.plot([], [], "o", color="#d62728", ms=6)
        (self._line,) = a2.plot([], [], color="#1f77b4", lw=1.5)
        (self._marks,) = a2.plot([], [], "o", color="#d62728", ms=4)
        (self._same,) = a2.plot([], [], "+", color="0.4", ms=9)
        for artist in (self._p1, self._line, self._marks, self._same):
            self.live.animate(artist)
        self.report = None
        self._finish()

    def draw(self, x1, y1, phi_deg, kappa_deg) -> str:
        self.report = rep = epipolar_report(x1, y1, phi_deg, kappa_deg)
        self._p1.set_data([x1], [y1])
        self._line.set_data(*rep["segment"].T)
        self._marks.set_data(*rep["marks"].T)
        self._same.set_data([x1], [y1])
        return rep["html"] + ("<p>red dots: the ray of the point at 12 … 36 m; "
                              "+: the same x', y' as in image 1</p>")


def plot_artificial_stereo(eye_base: float = 65.0, viewing: float = 250.0,
                           separation: float = 40.0, title="artificial stereoscopic viewing / "
                           "künstliches stereoskopisches Sehen (plan view)"):
    """Two images, one per eye, whose homologous rays meet in a fused point (Raumbild).

    Plan view (mm): the eyes at ``(±eye_base/2, 0)``, the two images side by side in the plane
    ``y = viewing``, each seen by one eye only. The homologous image points (homologe
    Bildpunkte) are ``separation`` apart; the rays from the eyes through them (homologe
    Strahlen) meet at the fused point at the distance
    ``viewing·eye_base/(eye_base − separation)`` (similar triangles), behind the image plane
    for ``0 < separation < eye_base`` — the observer sees the point in space. A smaller
    separation (a larger parallax) brings the point closer.

    >>> fig = plot_artificial_stereo()
    >>> len(fig.axes), round(fig.fused[1], 1)
    (1, 650.0)
    """
    import matplotlib.pyplot as plt

    e, d = float(eye_base), float(viewing)
    if not 0.0 < separation < e:
        raise ValueError(f"separation must lie in (0, eye_base) = (0, {e}), got {separation}")
    xl, xr = -separation / 2, separation / 2                       # homologous image points
    dist = d * e / (e - separation)                                # where the rays meet
    fused = (0.0, dist)
    fig, ax = plt.subplots(figsize=(5.6, 3.6))
    for x_eye, x_img, colour, name in ((-e / 2, xl, "#1f77b4", "left"),
                                       (e / 2, xr, "#d62728", "right")):
        centre = x_eye                                             # each image in front of its eye
        ax.plot([centre - 26, centre + 26], [d, d], color=colour, lw=4, alpha=0.5)
        ax.text(centre, d + 14, f"{name} image\n({name} eye only)", ha="center",
                va="bottom", fontsize=7, color=colour)
        ax.plot([x_eye], [0], "o", color=colour, ms=7)
        ax.text(x_eye, -12, f"{name} eye", ha="center", va="top", fontsize=8)
        ax.plot([x_eye, x_img], [0, d], color=colour, lw=1.2)
        ax.plot([x_img, 0.0], [d, dist], "--", color=colour, lw=1.0)
        ax.plot([x_img], [d], "s", color=colour, ms=4)
    ax.plot([fused[0]], [fused[1]], "*", color="k", ms=12)
    ax.annotate("homologous point P\n(fused: Raumbild)", fused, xytext=(10, dist - 60),
                fontsize=8)
    ax.text(-e / 2 - 8, d * 0.3, "homologous rays\n(homologe Strahlen)", fontsize=8,
            ha="right")
    ax.set(xlabel="x [mm]", ylabel="distance from the eyes [mm]", title=title,
           xlim=(-e - 70, e + 70), ylim=(-60, dist + 40))
    ax.title.set_fontsize(9)
    fig.tight_layout()
    fig.fused = fused
    return finished(fig)


# -- chapter 09, real photographs: the Middlebury motorcycle pair and rocks2 ---------------------

__all__ += ["RealDepth", "real_depth", "plot_real_depth", "plot_depth_histogram",
            "real_epipolar", "plot_real_epipolar", "compare_orientations",
            "plot_orientation_comparison"]


@functools.lru_cache(maxsize=1)
def _motorcycle_grey():
    from photolib import data
    p = data.motorcycle()
    return p, p.left.mean(axis=2), p.right.mean(axis=2)


class RealDepth(dict):
    """Depth from the measured disparities of the motorcycle pair (a dict of arrays)."""


def real_depth(n: int = 300, half: int = 5, spacing: int = 9) -> RealDepth:
    """Measure disparities at ``n`` textured points of the motorcycle pair, depth and errors.

    Points: :func:`photolib.stereo._disparity.textured_points` (grid of ``spacing`` px, the
    smallest structure-tensor eigenvalue, ground truth known). Disparities: NCC along the row
    (the epipolar line of a rectified pair) over the disparity range of the scene, subpixel by
    the correlation parabola (:func:`photolib.correlation.ncc_match`). σ_d comes from the data:
    the robust σ (1.4826·MAD, insensitive to the few gross mismatches at occlusions) of
    ``d − d_true`` over all points, in px; the prediction ``σ_Z = Z²/(f·B)·σ_d`` then says how
    the depth error grows with the distance, which the near and the far points test.
    """
    from photolib.stereo._disparity import (depth_from_disparity, depth_sigma,
                                            match_disparities, textured_points)
    p, L, R = _motorcycle_grey()
    cal, gt = p.calibration, p.disparity
    pts = textured_points(L, n, half=half, spacing=spacing, valid=np.isfinite(gt), border=70)
    d_range = (float(np.floor(np.nanmin(gt))) - 2.0, float(np.ceil(np.nanmax(gt))) + 2.0)
    d, _, rho = match_disparities(L, R, pts, d_range, half=half, lsm=False)
    ok = np.isfinite(d)
    pts, d, rho = pts[ok], d[ok], rho[ok]
    d_true = gt[pts[:, 1].astype(int), pts[:, 0].astype(int)]
    e = d - d_true
    sigma_d = float(1.4826 * np.median(np.abs(e - np.median(e))))
    f, B, doffs = cal.f_px, cal.baseline_mm, cal.doffs_px
    Z = depth_from_disparity(d, f, B, doffs)
    Z_true = depth_from_disparity(d_true, f, B, doffs)
    sZ = depth_sigma(Z_true, f, B, sigma_d)
    return RealDepth(points=pts, d=d, d_true=d_true, rho=rho, Z=Z, Z_true=Z_true,
                     dZ=Z - Z_true, sigma_d=sigma_d, sigma_Z=sZ,
                     f=f, B=B, doffs=doffs, d_range=d_range, image=p.left)


def plot_real_depth(r: RealDepth, clip_mm: float = 50.0):
    """The left image with the sample points, coloured by the depth error Z − Z_true (mm)."""
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(7.0, 4.8))
    ax.imshow(r["image"])
    sc = ax.scatter(r["points"][:, 0], r["points"][:, 1], c=np.clip(r["dZ"], -clip_mm, clip_mm),
                    cmap="coolwarm", vmin=-clip_mm, vmax=clip_mm, s=14, edgecolors="k",
                    linewidths=0.3)
    fig.colorbar(sc, ax=ax, label="Z − Z_true [mm]", shrink=0.8)
    ax.set(title=f"motorcycle: {len(r['d'])} matched points, depth error", xticks=[], yticks=[])
    fig.tight_layout()
    return finished(fig)


def plot_depth_histogram(r: RealDepth):
    """Normalised depth errors (Z − Z_true)/σ_Z of the points beside N(0, 1)."""
    import matplotlib.pyplot as plt

    t = np.ones(len(r["d"]), bool)
    z = r["dZ"] / r["sigma_Z"]
    fig, (ax, ax2) = plt.subplots(1, 2, figsize=(8.0, 3.2))
    edges = np.linspace(-5, 5, 41)
    ax.hist(np.clip(z, -5, 5), bins=edges, density=True, color="#1f77b4", alpha=0.8,
            label="(Z − Z_true)/σ_Z")
    g = np.linspace(-5, 5, 201)
    ax.plot(g, np.exp(-g**2 / 2) / np.sqrt(2 * np.pi), color="#d62728", label="N(0, 1)")
    ax.set(xlabel="normalised depth error", ylabel="density",
           title=f"{len(z)} points, σ_d = {r['sigma_d']:.2f} px")
    ax.legend(fontsize=8)
    ax2.scatter(-r["Z_true"][t], np.abs(r["dZ"][t]), s=8, color="#1f77b4", label="|Z − Z_true|")
    h = np.linspace(-r["Z_true"].max(), -r["Z_true"].min(), 50)
    ax2.plot(h, h**2 / (r["f"] * r["B"]) * r["sigma_d"], color="#d62728",
             label="σ_Z = Z²/(f·B)·σ_d")
    ax2.set(xlabel="distance −Z [mm]", ylabel="[mm]", ylim=(0, 6 * h.max()**2 / (r["f"] * r["B"])
                                                            * r["sigma_d"]))
    ax2.legend(fontsize=8)
    fig.tight_layout()
    return finished(fig)


def real_epipolar(name: str = "building2", scale: float = 0.5, threshold: float = 1.0,
                  seed: int = 0) -> dict:
    """F of an unrectified real pair from SIFT matches (OpenCV measures, photolib estimates).

    ``name``: ``"building2"`` (views 1 and 2 of mvtb-data's building2) or ``"rocks2"``.
    OpenCV's SIFT finds and matches features (ratio test 0.75) in the pair scaled by
    ``scale``; :func:`photolib.stereo.estimate_fundamental_ransac` estimates F
    (``h1ᵀ F h2 = 0``, pixel coordinates (col, row) of the scaled images) with RANSAC.
    """
    import cv2

    from photolib import data
    from photolib.stereo import epipolar_distances, estimate_fundamental_ransac
    if name == "building2":
        images = data.building2().images[:2]
    elif name == "rocks2":
        p = data.stereo_pair("rocks2")
        images = (p.left, p.right)
    else:
        raise ValueError(f"name must be 'building2' or 'rocks2', got {name!r}")
    grey = []
    for im in images:
        im = np.asarray(im)
        if im.ndim == 3:
            im = cv2.cvtColor(np.ascontiguousarray(im[..., :3]), cv2.COLOR_RGB2GRAY)
        if im.dtype != np.uint8:
            im = np.clip(im * (255.0 if im.max() <= 1.0 else 1.0), 0, 255).astype(np.uint8)
        grey.append(cv2.resize(im, None, fx=scale, fy=scale, interpolation=cv2.INTER_AREA))
    sift = cv2.SIFT_create(nfeatures=800)
    (k1, d1), (k2, d2) = (sift.detectAndCompute(g, None) for g in grey)
    pairs = [m for m, n in cv2.BFMatcher().knnMatch(d1, d2, k=2) if m.distance < 0.75 * n.distance]
    x1 = np.array([k1[m.queryIdx].pt for m in pairs])
    x2 = np.array([k2[m.trainIdx].pt for m in pairs])
    F, inl = estimate_fundamental_ransac(x1, x2, threshold, rng=seed)
    return {"name": name, "F": F, "x1": x1, "x2": x2, "inliers": inl, "images": grey,
            "distances": epipolar_distances(F, x1[inl], x2[inl])}


def _draw_lines(ax, lines, width, colour):
    u = np.array([0.0, width - 1.0])
    for a, b, d in lines:
        ax.plot(u, -(a * u + d) / b, color=colour, lw=0.8)


def plot_real_epipolar(e: dict, rectified: RealDepth | None = None, n: int = 8):
    """Epipolar lines of ``n`` points of image 1 drawn in image 2 (unrectified), and on the
    rectified motorcycle pair the same lines: rows."""
    import matplotlib.pyplot as plt

    panels = 2 if rectified is None else 3
    fig, axes = plt.subplots(1, panels, figsize=(3.6 * panels, 3.4))
    inl = np.flatnonzero(e["inliers"])
    pick = inl[np.linspace(0, len(inl) - 1, n).astype(int)]
    g1, g2 = e["images"]
    colours = plt.cm.tab10(np.arange(n) % 10)
    axes[0].imshow(g1, cmap="gray")
    axes[0].scatter(*e["x1"][pick].T, c=colours, s=25, edgecolors="w")
    axes[0].set(title=f"{e['name']}, image 1: points", xticks=[], yticks=[])
    axes[1].imshow(g2, cmap="gray")
    lines = pl.epipolar_lines(e["F"], e["x1"][pick], image=2)
    for ln, col in zip(lines, colours):
        _draw_lines(axes[1], [ln], g2.shape[1], col)
    axes[1].scatter(*e["x2"][pick].T, c=colours, s=25, edgecolors="w")
    axes[1].set(xlim=(0, g2.shape[1] - 1), ylim=(g2.shape[0] - 1, 0), xticks=[], yticks=[],
                title="image 2: epipolar lines l2 = Fᵀh1")
    if rectified is not None:
        img = rectified["image"]
        both = np.hstack([img, img[:, :0]])
        axes[2].imshow(both)
        rows = rectified["points"][:: max(len(rectified["points"]) // n, 1)][:n, 1]
        for r_ in rows:
            axes[2].axhline(r_, color="y", lw=0.8)
        axes[2].set(title="motorcycle (rectified): the lines are rows", xticks=[], yticks=[])
    fig.tight_layout()
    return finished(fig)


def compare_orientations(s=None, noise_um: float = 2.0):
    """Dependent and independent relative orientation of the same pair, and their models.

    The independent model rotated by R1ᵀ (into the frame of image 1) and scaled by the
    dependent base length |b|/bx is compared with the dependent model: they are one model.
    """
    s = pair_scene(noise_um=noise_um) if s is None else s
    dep = pl.relative_orientation(s["xy1"], s["xy2"], C_MM, bx=1.0)
    ind = pl.independent_relative_orientation(s["xy1"], s["xy2"], C_MM, bx=1.0)
    scale = np.linalg.norm(dep.base) / ind.base[0]
    mapped = scale * ind.model @ ind.R1          # rows: R1ᵀ·x, scaled
    return {"dependent": dep, "independent": ind, "mapped": mapped,
            "difference": np.abs(mapped - dep.model).max()}


def plot_orientation_comparison(cmp: dict):
    """Both models in the X–Z and X–Y view: the dependent model and the mapped independent one."""
    import matplotlib.pyplot as plt

    dep, mp = cmp["dependent"].model, cmp["mapped"]
    fig, axes = plt.subplots(1, 2, figsize=(8.0, 3.2))
    for ax, (i, j, lab) in zip(axes, ((0, 1, "Y"), (0, 2, "Z"))):
        ax.scatter(dep[:, i], dep[:, j], s=40, facecolors="none", edgecolors="#1f77b4",
                   label="dependent (Folgebildanschluss)")
        ax.scatter(mp[:, i], mp[:, j], s=8, color="#d62728",
                   label="independent, rotated by R1ᵀ and scaled")
        ax.set(xlabel="X [model]", ylabel=f"{lab} [model]", aspect="equal")
    handles, labels = axes[0].get_legend_handles_labels()
    fig.legend(handles, labels, loc="lower center", ncol=2, fontsize=7, frameon=False)
    fig.suptitle(f"one model: largest difference {cmp['difference']:.1e} model units")
    fig.tight_layout(rect=(0, 0.08, 1, 1))
    return finished(fig)
