"""Chapter 10 pictures and widgets: bundle adjustment (Bündelblockausgleichung).

A small aerial block: ``strips`` strips of ``per_strip`` nadir-ish images (c = 100 mm,
100 mm × 100 mm format, 600 m above a gently rolling terrain), forward overlap ``overlap``
(Längsüberdeckung) and 30 % side overlap (Querüberdeckung); object points on a 100 m grid,
kept where at least two images see them. :func:`simulate_block` makes the block (seeded),
:func:`block_report` counts it, :func:`blunder_report` adjusts it with one gross error
injected and runs data snooping on it (:func:`photolib.bundle.data_snooping`).
"""

from __future__ import annotations

import functools
from dataclasses import dataclass

import numpy as np

import photolib as pl
from photolib import bundle as bd
from photolib.nb.draw import format_corners, lines_xyz
from photolib.nb.live import Explorer, LiveFigure, finished, slider

__all__ = [
    "C_MM",
    "HALF_MM",
    "HEIGHT_M",
    "Block",
    "BlockExplorer",
    "BlunderExplorer",
    "PrecisionExplorer",
    "adjust",
    "block_report",
    "blunder_effect",
    "blunder_report",
    "control_cases",
    "coarse_pattern",
    "control_order",
    "plot_block",
    "plot_ellipses",
    "standard_ellipses",
    "plot_reliability",
    "plot_sparsity",
    "precision_report",
    "reliability_report",
    "plot_statistics",
    "simulate_block",
    "terrain",
]

#: camera constant, mm; half the (square) image format, mm; flying height above datum, m
C_MM, HALF_MM, HEIGHT_M = 100.0, 50.0, 600.0
_GROUND = 2 * HALF_MM / C_MM * HEIGHT_M  # footprint side, m (600 m)
_SIDE = 0.3
_SPACING = 60.0


def terrain(X, Y):
    """Terrain height (m) of the chapter's block: smooth hills of ±15 m around 20 m.

    >>> round(float(terrain(0.0, 0.0)), 6)
    20.0
    """
    return 20.0 + 10.0 * np.sin(X / 170.0) * np.cos(Y / 230.0) + 5.0 * np.sin((X + Y) / 90.0)


@dataclass(frozen=True)
class Block:
    """A simulated block: true values, observations and start values."""

    xy: np.ndarray  #: (N, 2) observed image coordinates, mm (with noise)
    image_index: np.ndarray  #: (N,)
    point_index: np.ndarray  #: (N,)
    exterior: np.ndarray  #: (M, 6) true X0, Y0, Z0 (m), ω, φ, κ (rad)
    points: np.ndarray  #: (P, 3) true object points, m
    exterior_start: np.ndarray  #: (M, 6) approximate values
    points_start: np.ndarray  #: (P, 3) approximate values (exact for control points)
    strips: int
    per_strip: int
    noise_um: float

    @property
    def n_images(self) -> int:
        return len(self.exterior)


@functools.lru_cache(maxsize=64)
def _geometry(strips: int, per_strip: int, overlap: float, seed: int, A1: float = 0.0,
              flat: bool = False):
    rng = np.random.default_rng(seed)
    base = (1.0 - overlap) * _GROUND
    gap = (1.0 - _SIDE) * _GROUND
    ext = np.array([[k * base, s * gap, HEIGHT_M + rng.normal(0, 3.0),
                     *np.radians(rng.normal(0, 0.5, 2)), np.radians(rng.normal(0, 1.0))]
                    for s in range(strips) for k in range(per_strip)])
    half = _GROUND / 2 - 20.0
    gx = np.arange(-half, (per_strip - 1) * base + half + 1e-9, _SPACING)
    gy = np.arange(-half, (strips - 1) * gap + half + 1e-9, _SPACING)
    XY = np.array([(x, y) for y in gy for x in gx])
    P = np.column_stack([XY, np.full(len(XY), 20.0) if flat else terrain(XY[:, 0], XY[:, 1])])
    xy, ji, pi = [], [], []
    for j, e in enumerate(ext):
        p = pl.project(P, e[:3], pl.rotation_opk(*e[3:]), C_MM,
                       distortion=pl.Distortion(A1=A1) if A1 else None)
        ok = np.all(np.abs(p) < HALF_MM, axis=1)
        xy.append(p[ok])
        ji.append(np.full(int(ok.sum()), j))
        pi.append(np.flatnonzero(ok))
    ji, pi = np.concatenate(ji), np.concatenate(pi)
    seen = np.bincount(pi, minlength=len(P)) >= 2
    renumber = np.cumsum(seen) - 1
    keep = seen[pi]
    return (np.vstack(xy)[keep], ji[keep], renumber[pi[keep]], ext, P[seen])


def control_order(points, n: int | None = None) -> np.ndarray:
    """Indices of the points in the order control points are added: the four corners, then
    the edge points farthest from those chosen, then the interior (greedy farthest point);
    the first ``n`` (default all).

    >>> control_order([[0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0], [0.5, 0.5, 0]])[:4].tolist()
    [0, 3, 1, 2]
    """
    XY = np.asarray(points, float)[:, :2]
    s, d = XY.sum(axis=1), XY[:, 0] - XY[:, 1]
    order = []
    for k in (int(np.argmin(s)), int(np.argmax(s)), int(np.argmax(d)), int(np.argmin(d))):
        if k not in order:
            order.append(k)
    n = len(XY) if n is None else min(int(n), len(XY))
    dist = np.min(np.linalg.norm(XY[:, None] - XY[order][None], axis=2), axis=1)
    while len(order) < n:
        k = int(np.argmax(dist))
        order.append(k)
        dist = np.minimum(dist, np.linalg.norm(XY - XY[k], axis=1))
    return np.array(order[:n], dtype=int)


def simulate_block(strips: int = 2, per_strip: int = 3, overlap: float = 0.6,
                   noise_um: float = 3.0, seed: int = 10, A1: float = 0.0,
                   flat: bool = False) -> Block:
    """The chapter's block with Gaussian image noise (µm) and start values.

    ``A1`` (mm⁻²) puts radial distortion Δr' = A1·r'³ into the images (for self-calibration);
    ``flat`` puts all points on the plane Z = 20 m instead of the rolling terrain (same
    images, same tilts).

    Start values: projection centres 5 m and angles 0.5° off, new points 3 m off (as from
    GNSS/IMU and a coarse terrain model). Noise is ``noise_um·1e-3·z`` with a fixed z.

    >>> b = simulate_block()
    >>> b.n_images, len(b.points), len(b.xy)
    (6, 194, 485)
    """
    xy, ji, pi, ext, P = _geometry(int(strips), int(per_strip), float(overlap), int(seed),
                                   float(A1), bool(flat))
    rng = np.random.default_rng(seed + 1)
    z = rng.standard_normal(xy.shape)
    ext0 = ext + rng.normal(0.0, 1.0, ext.shape) * np.r_[5.0, 5.0, 5.0, np.radians([0.5] * 3)]
    P0 = P + rng.normal(0.0, 3.0, P.shape)
    return Block(xy + noise_um * 1e-3 * z, ji, pi, ext, P, ext0, P0, int(strips),
                 int(per_strip), float(noise_um))


def adjust(block: Block, n_control: int = 6, *, blunder=None, datum=None, start=None,
           c: float = C_MM, **kwargs):
    """Adjust ``block`` with its first ``n_control`` points of :func:`control_order` as
    control points (0: free network). ``blunder = (observation, coordinate, mm)`` adds a
    gross error. ``start = (exterior, points)`` overrides the approximate values; ``c`` is
    the camera constant used (start value with self-calibration); ``kwargs`` go to
    :func:`photolib.bundle_adjustment`. Returns ``(result, control indices)``."""
    xy = block.xy.copy()
    if blunder is not None:
        k, e, size = blunder
        xy[int(k), int(e)] += size
    control = control_order(block.points, int(n_control))
    ext0, P0 = (block.exterior_start, block.points_start) if start is None else start
    P0 = np.array(P0, copy=True)
    P0[control] = block.points[control]
    datum = datum or ("free" if n_control == 0 else "control")
    return bd.bundle_adjustment(xy, block.image_index, block.point_index, ext0, P0, c,
                                control=control, datum=datum, **kwargs), control


def block_report(strips: int = 2, per_strip: int = 3, overlap: float = 0.6,
                 n_control: int = 4, calibrate: int = 0) -> dict:
    """Counts of a block (no adjustment): observations, unknowns, datum defect, redundancy.

    ``calibrate`` is the number of self-calibration parameters (0 … 5: c, x'0, y'0, A1, A2).

    Returns
    -------
    dict
        ``n_images``, ``n_points``, ``n_rays``, ``n`` (observations), ``u``, ``d``, ``r``,
        ``pattern`` (boolean N pattern), ``html``.

    Examples
    --------
    >>> rep = block_report(2, 3, 0.6, 4)
    >>> rep["n"], rep["u"], rep["r"]
    (970, 606, 364)
    """
    b = simulate_block(strips, per_strip, overlap, 0.0)
    nc = int(round(n_control))
    k = int(round(calibrate))
    control = control_order(b.points, nc)
    M, P, rays = b.n_images, len(b.points), len(b.xy)
    free = nc == 0
    n, u = 2 * rays, 6 * M + 3 * (P - nc) + k
    d = 7 if free else 0
    r = n - u + d
    pattern = bd.normal_matrix_pattern(b.image_index, b.point_index, M, P, k, fixed=control)
    problem = ""
    if 0 < nc < 3:
        problem = ("<br><b style='color:#b00'>datum not fixed: at least 3 control points "
                   "(7 datum parameters), or a free network</b>")
    datum = "free network, 7 inner constraints" if free else f"{nc} control points"
    html = (f"<p>{M} images ({strips} strip(s) × {per_strip}), {P} object points, "
            f"{rays} rays<br>observations n = 2·{rays} = <b>{n}</b><br>"
            f"unknowns u = 6·{M} + 3·{P - nc} + {k} = <b>{u}</b><br>"
            f"datum: {datum}, defect d = {d}<br>redundancy r = n − u + d = <b>{r}</b><br>"
            f"N: {u}×{u}, {pattern.mean() * 100:.1f} % non-zero{problem}</p>")
    return {"n_images": M, "n_points": P, "n_rays": rays, "n": n, "u": u, "d": d, "r": r,
            "pattern": pattern, "html": html}


@functools.lru_cache(maxsize=8)
def _clean(n_control: int):
    block = simulate_block()
    res, _ = adjust(block, n_control)
    return block, res


@functools.lru_cache(maxsize=256)
def _blunder_adjustment(blunder_um: float, k: int, alpha: float, n_control: int):
    """The block adjusted with ``blunder_um`` on x′ of observation k (from the clean solution)
    and its τ and w snooping; cached, so that a slider moved back to a value redraws without
    adjusting again (the results are read, never changed)."""
    block, clean = _clean(n_control)
    res, _ = adjust(block, n_control, blunder=(k, 0, blunder_um * 1e-3),
                    start=(clean.exterior, clean.points))
    tau = bd.data_snooping(res, alpha)
    w = bd.data_snooping(res, alpha, sigma=block.noise_um * 1e-3)
    return res, tau, w


def blunder_report(blunder_um: float = 30.0, observation: int = 157, alpha: float = 0.001,
                   n_control: int = 6) -> dict:
    """Adjust the chapter's block with a gross error on x' of one observation; snoop.

    The adjustment starts from the solution without the blunder. Returns ``result``,
    ``snooping`` (τ test, σ̂0 of the adjustment), ``w`` (Baarda's w with σ = 3 µm),
    ``observation``, ``image``, ``found`` (the flagged worst is the blundered one), ``html``.

    Examples
    --------
    >>> rep = blunder_report(40.0, 157)
    >>> rep["found"], rep["w"].worst
    (True, (157, 0))
    """
    block, _ = _clean(int(n_control))
    k = int(np.clip(round(observation), 0, len(block.xy) - 1))
    res, tau, w = _blunder_adjustment(float(blunder_um), k, float(alpha), int(n_control))
    found = tau.worst == (k, 0)
    verdict = ("<b style='color:#2ca02c'>found: the largest |τ| is the blundered x′</b>" if found
               else ("<b style='color:#b00'>another observation is flagged worst</b>"
                     if tau.worst else "not detected"))
    html = (f"<p>blunder {blunder_um:.0f} µm on x′ of observation {k} (image "
            f"{block.image_index[k]}, point {block.point_index[k]})<br>"
            f"redundancy number r<sub>x′</sub> = {res.redundancy_numbers[k, 0]:.3f}<br>"
            f"σ̂0 = {res.sigma0 * 1e3:.2f} µm (noise 3 µm)<br>"
            f"τ of it: {tau.statistic[k, 0]:+.2f}, critical τ = {tau.critical:.2f} "
            f"(α = {alpha:g}, r = {res.redundancy})<br>"
            f"w of it: {w.statistic[k, 0]:+.2f}, critical k = {w.critical:.2f}<br>"
            f"flagged: {len(tau.flagged)} (τ), {len(w.flagged)} (w)<br>{verdict}</p>")
    return {"result": res, "snooping": tau, "w": w, "observation": k,
            "image": int(block.image_index[k]), "found": found, "html": html, "block": block}


def reliability_report(n_control: int = 6, alpha: float = 0.001, beta: float = 0.80) -> dict:
    """Internal and external reliability of the chapter's block (σ = 3 µm a priori).

    Returns ``result``, ``reliability`` (:class:`photolib.bundle.ReliabilityResult`),
    ``rays`` (N,) the number of rays of each observation's point, ``table`` (rays → mean
    r, median ∇0 in µm and median δ̄0, for x′ and y′), ``html``.

    Examples
    --------
    >>> rep = reliability_report()
    >>> round(rep["reliability"].delta0, 2), bool(rep["table"][4]["mdb_y"] < 30)
    (4.13, True)
    """
    block, res = _clean(int(n_control))
    rel = bd.reliability(res, alpha, beta, sigma=block.noise_um * 1e-3)
    rays = np.bincount(block.point_index)[block.point_index]
    rn = res.redundancy_numbers
    table = {}
    for k in (2, 3, 4):
        m = rays == k if k < 4 else rays >= 4
        table[k] = {"r_x": float(rn[m, 0].mean()), "r_y": float(rn[m, 1].mean()),
                    "mdb_x": float(np.median(rel.mdb[m, 0]) * 1e3),
                    "mdb_y": float(np.median(rel.mdb[m, 1]) * 1e3),
                    "ext_x": float(np.median(rel.external[m, 0])),
                    "ext_y": float(np.median(rel.external[m, 1]))}
    rows = "".join(f"<tr><td>{k}{'+' if k == 4 else ''}</td><td>{t['r_x']:.2f} / {t['r_y']:.2f}"
                   f"</td><td>{t['mdb_x']:.0f} / {t['mdb_y']:.0f}</td><td>{t['ext_x']:.1f} / "
                   f"{t['ext_y']:.1f}</td></tr>" for k, t in table.items())
    html = (f"<p>δ0 = {rel.delta0:.2f} (α = {alpha:g}, β = {beta:g}), σ = "
            f"{rel.sigma * 1e3:.0f} µm</p><table><tr><th>rays</th><th>mean r x′ / y′</th>"
            f"<th>median ∇0 x′ / y′ [µm]</th><th>median δ̄0 x′ / y′</th></tr>{rows}</table>")
    return {"result": res, "reliability": rel, "rays": rays, "table": table, "html": html,
            "block": block}


def _design_matrix(block: Block, result, control):
    """Dense A (2N, 6M + 3·new points) at ``result`` from :func:`photolib.collinearity_jacobian`
    (rows x′, y′ interleaved; columns: images, then the new points in index order)."""
    M = block.n_images
    free = np.setdiff1d(np.arange(len(block.points)), control)
    slot = np.full(len(block.points), -1)
    slot[free] = np.arange(len(free))
    A = np.zeros((2 * len(block.xy), 6 * M + 3 * len(free)))
    for j in range(M):
        rows = np.flatnonzero(block.image_index == j)
        e = result.exterior[j]
        J = pl.collinearity_jacobian(result.points[block.point_index[rows]], e[:3],
                                     pl.rotation_opk(*e[3:]), result.c, angles=tuple(e[3:]))
        for n, k in enumerate(rows):
            A[2 * k:2 * k + 2, 6 * j:6 * j + 6] = J[n, :, :6]
            s = slot[block.point_index[k]]
            if s >= 0:
                A[2 * k:2 * k + 2, 6 * M + 3 * s:6 * M + 3 * s + 3] = J[n, :, 6:]
    return A, free


def blunder_effect(observation: int = 35, coordinate: int = 0, n_control: int = 6,
                   alpha: float = 0.001, beta: float = 0.80) -> dict:
    """External reliability of one image coordinate: the effect of an undetected blunder of
    the size ∇0 (its minimal detectable blunder) on the unknowns, two ways.

    *Re-adjusted*: ∇0 added to the observation, the block adjusted again (from the clean
    solution). *Linearised*: ``∇x = (AᵀA)⁻¹Aᵀe_k·∇0`` with the dense design matrix A built
    from :func:`photolib.collinearity_jacobian` (not the library's reduced normal equations).

    Returns ``size`` (∇0, mm), ``r`` (redundancy number), ``point``, ``points_readjusted``
    and ``points_linear`` (P, 3) shifts in m (0 for control points), ``exterior_readjusted``,
    ``exterior_linear`` (M, 6), ``external`` (δ̄0 from r), ``external_linear``
    (√(∇xᵀN∇x)/σ), ``adjusted_shift`` (‖∇l̂‖, mm), ``html``.

    Examples
    --------
    >>> rep = blunder_effect(35, 0)
    >>> bool(np.allclose(rep["points_readjusted"], rep["points_linear"], atol=1e-3))
    True
    """
    block, res = _clean(int(n_control))
    rel = bd.reliability(res, alpha, beta, sigma=block.noise_um * 1e-3)
    k = int(np.clip(round(observation), 0, len(block.xy) - 1))
    e = int(coordinate)
    size = float(rel.mdb[k, e])
    if not np.isfinite(size):
        raise ValueError(f"observation {k}, coordinate {e} has redundancy number 0: no blunder "
                         "on it can be detected (∇0 = inf)")
    again, control = adjust(block, n_control, blunder=(k, e, size),
                            start=(res.exterior, res.points))
    A, free = _design_matrix(block, res, control)
    N = A.T @ A
    dx = np.linalg.solve(N, A[2 * k + e]) * size
    M = block.n_images
    lin_pts = np.zeros_like(block.points)
    lin_pts[free] = dx[6 * M:].reshape(-1, 3)
    moved = block.xy.copy()
    moved[k, e] += size
    shift = float(np.linalg.norm(moved + again.residuals - (block.xy + res.residuals)))
    dP = again.points - res.points
    p = int(block.point_index[k])
    html = (f"<p>∇0 = {size * 1e3:.1f} µm on {'x′y′'[2 * e:2 * e + 2]} of observation {k} "
            f"(point {p}, r = {res.redundancy_numbers[k, e]:.3f})<br>"
            f"shift of point {p}: re-adjusted {np.round(dP[p] * 1e3, 1).tolist()} mm, "
            f"linearised {np.round(lin_pts[p] * 1e3, 1).tolist()} mm<br>"
            f"δ̄0 = {rel.external[k, e]:.2f} (formula), "
            f"{np.sqrt(dx @ N @ dx) / rel.sigma:.2f} (√(∇xᵀN∇x)/σ)</p>")
    return {"size": size, "r": float(res.redundancy_numbers[k, e]), "point": p,
            "points_readjusted": dP, "points_linear": lin_pts,
            "exterior_readjusted": again.exterior - res.exterior,
            "exterior_linear": dx[:6 * M].reshape(M, 6), "external": float(rel.external[k, e]),
            "external_linear": float(np.sqrt(dx @ N @ dx) / rel.sigma),
            "adjusted_shift": shift, "html": html}


@functools.lru_cache(maxsize=2)
def control_cases(sigma_gnss: float = 0.02) -> dict:
    """The chapter's block with four kinds of control (σ image = 3 µm a priori):

    * ``'6 XYZ fixed'``: six full control points, error-free (as before);
    * ``'6 XYZ, σ = 2 cm (GNSS)'``: the same six observed with σ = ``sigma_gnss`` m (their
      given coordinates carry seeded errors of that size);
    * ``'6 XYZ + 6 Z'``: the six fixed plus six height control points (Höhenpasspunkte);
    * ``'4 XY + 6 Z'``: plan control (Lagepasspunkte) at the four corners, heights at six
      other points.

    Returns ``{name: {'result', 'control_sigma', 'new' (indices of the points without any
    control), 'std_new' (mean σX, σY, σZ of them, mm, scaled to σ = 3 µm), 'std_control'
    (mean σ of the control coordinates that are not fixed, mm; NaN if none)}}``.

    Examples
    --------
    >>> [c["result"].redundancy for c in control_cases().values()]
    [370, 370, 376, 366]
    """
    block = simulate_block()
    P, sig_img = len(block.points), block.noise_um * 1e-3
    order = control_order(block.points, 12)
    rng = np.random.default_rng(42)
    cases = {}
    specs = {"6 XYZ fixed": [(order[:6], [0, 1, 2], 0.0)],
             f"6 XYZ, σ = {sigma_gnss * 100:g} cm (GNSS)": [(order[:6], [0, 1, 2], sigma_gnss)],
             "6 XYZ + 6 Z": [(order[:6], [0, 1, 2], 0.0), (order[6:], [2], 0.0)],
             "4 XY + 6 Z": [(order[:4], [0, 1], 0.0), (order[4:10], [2], 0.0)]}
    for name, spec in specs.items():
        sig = np.full((P, 3), np.inf)
        P0 = block.points_start.copy()
        for pts, coords, s in spec:
            sel = np.ix_(pts, coords)
            sig[sel] = s
            P0[sel] = block.points[sel] + (rng.normal(0.0, s, (len(pts), len(coords)))
                                           if s > 0 else 0.0)
        res = bd.bundle_adjustment(block.xy, block.image_index, block.point_index,
                                   block.exterior_start, P0, C_MM, control_sigma=sig,
                                   sigma_image=sig_img)
        scale = sig_img / res.sigma0
        new = np.flatnonzero(np.all(np.isinf(sig), axis=1))
        loose = (sig > 0) & np.isfinite(sig)
        std = res.point_std * scale * 1e3
        cases[name] = {"result": res, "control_sigma": sig, "new": new,
                       "std_new": std[new].mean(axis=0),
                       "std_control": float(std[loose].mean()) if loose.any() else float("nan")}
    return cases


# -- static figures -------------------------------------------------------------------------------

def _footprint(e):
    corners = np.column_stack([format_corners(HALF_MM, HALF_MM), np.full(5, -C_MM)])
    R = pl.rotation_opk(*e[3:])
    rays = corners @ R.T
    lam = (20.0 - e[2]) / rays[:, 2]
    return e[:2] + lam[:, None] * rays[:, :2]


def plot_block(block: Block, control=(), title="block / Bildverband"):
    """Plan view: image footprints, projection centres, new points and control points."""
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(5.6, 4.2))
    for j, e in enumerate(block.exterior):
        ax.plot(*_footprint(e).T, color=f"C{j % 10}", lw=1, alpha=0.7)
        ax.plot(*e[:2], "+", color=f"C{j % 10}", ms=8)
    ax.plot(*block.points[:, :2].T, ".", color="0.4", ms=4, label="new points")
    if len(control):
        ax.plot(*block.points[np.asarray(control)][:, :2].T, "^", color="#d62728", ms=7,
                label="control points")
    ax.set(aspect="equal", xlabel="X [m]", ylabel="Y [m]", title=title)
    ax.legend(fontsize=8, loc="upper right")
    return finished(fig)


def plot_sparsity(pattern, reduced_size=None, title="normal matrix N / Normalgleichungsmatrix"):
    """``spy`` of the normal matrix; the reduced (orientation) part outlined."""
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(4.2, 4.2))
    ax.spy(pattern, markersize=float(np.clip(150.0 / len(pattern), 0.6, 5.0)), color="#1f77b4")
    if reduced_size:
        s = reduced_size - 0.5
        ax.plot([-0.5, s, s, -0.5, -0.5], [-0.5, -0.5, s, s, -0.5], color="#d62728", lw=1)
    ax.set_title(title, fontsize=10)
    ax.grid(False)
    return finished(fig)


def plot_statistics(statistic, critical, flagged=(), title="standardised residuals"):
    """|statistic| per observation coordinate (x′ and y′ interleaved) and the critical value."""
    import matplotlib.pyplot as plt

    s = np.abs(np.asarray(statistic, float)).ravel()
    fig, ax = plt.subplots(figsize=(6.4, 2.8))
    ax.plot(np.arange(len(s)), s, ".", color="#1f77b4", ms=3)
    for k, e in np.asarray(flagged, int).reshape(-1, 2):
        ax.plot(2 * k + e, s[2 * k + e], "o", color="#d62728", ms=7, mfc="none", mew=1.5)
    ax.axhline(critical, color="#d62728", lw=1, ls="--", label=f"critical {critical:.2f}")
    ax.set(xlabel="observation coordinate (x′, y′ interleaved)", ylabel="|statistic|",
           title=title)
    ax.legend(fontsize=8)
    return finished(fig)


def plot_reliability(report, title="internal reliability: minimal detectable blunder ∇0"):
    """∇0 per image coordinate (x′, y′ interleaved) of :func:`reliability_report`, log scale,
    coloured by the number of rays of the point; ∞ (r = 0) drawn at the top."""
    import matplotlib.pyplot as plt

    rel, rays = report["reliability"], report["rays"]
    mdb = rel.mdb.ravel() * 1e3
    ray2 = np.repeat(rays, 2)
    top = float(np.max(mdb[np.isfinite(mdb)])) * 1.5
    fig, ax = plt.subplots(figsize=(6.4, 2.8))
    idx = np.arange(len(mdb))
    for k, colour in ((2, "#d62728"), (3, "#ff7f0e"), (4, "#1f77b4")):
        m = ray2 == k if k < 4 else ray2 >= 4
        ax.plot(idx[m], np.where(np.isfinite(mdb[m]), mdb[m], top), ".", color=colour, ms=3,
                label=f"{k}{'+' if k == 4 else ''} rays")
    ax.axhline(rel.delta0 * rel.sigma * 1e3, color="0.3", lw=1, ls="--",
               label=f"δ0·σ = {rel.delta0 * rel.sigma * 1e3:.1f} µm (r = 1)")
    ax.set(yscale="log", xlabel="observation coordinate (x′, y′ interleaved)",
           ylabel="∇0 [µm]", title=title)
    ax.legend(fontsize=7, ncol=4, loc="upper right")
    return finished(fig)


def standard_ellipses(cov2, scale: float = 1.0, n: int = 41) -> np.ndarray:
    """Outlines of the standard (1σ) ellipses of 2 × 2 covariance matrices, ``scale`` times
    enlarged, about the origin: ``cov2`` (m, 2, 2) → (m, n, 2) (or (2, 2) → (n, 2)).

    ``Σ = V·diag(λ)·Vᵀ`` (``eigh``): the outline is ``V·diag(√λ)·(cos t, sin t)``, semi-axes
    √λ₁, √λ₂ along the eigenvectors (a negative rounding of λ counts as 0).

    >>> e = standard_ellipses(np.diag([4.0, 1.0]), n=5)
    >>> np.round(np.abs(e).max(axis=0), 12).tolist()
    [2.0, 1.0]
    """
    cov2 = np.asarray(cov2, dtype=float)
    if cov2.shape[-2:] != (2, 2):
        raise ValueError(f"cov2 must be (m, 2, 2) or (2, 2), got shape {cov2.shape}")
    w, V = np.linalg.eigh(cov2)
    t = np.linspace(0.0, 2.0 * np.pi, n)
    circle = np.stack([np.cos(t), np.sin(t)])
    return np.swapaxes(V @ (np.sqrt(np.maximum(w, 0.0))[..., None] * circle), -1, -2) * scale


def plot_ellipses(block: Block, result, control=(), scale: float = 1000.0,
                  title="standard ellipses of the points / Fehlerellipsen"):
    """Plan-view standard ellipses (σX, σY, ``scale`` times enlarged) and σZ as colour."""
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(5.8, 4.2))
    pts = result.points
    sz = result.point_std[:, 2] * 1e3
    segs = [pts[p, :2] + standard_ellipses(result.point_covariance[p, :2, :2], scale)
            for p in range(len(pts)) if p not in set(np.asarray(control, int).tolist())]
    for s in segs:
        ax.plot(*s.T, color="#1f77b4", lw=0.8)
    sc = ax.scatter(*pts[:, :2].T, c=sz, s=10, cmap="viridis")
    fig.colorbar(sc, ax=ax, label="σZ [mm]")
    if len(control):
        ax.plot(*pts[np.asarray(control)][:, :2].T, "^", color="#d62728", ms=7)
    ax.set(aspect="equal", xlabel="X [m]", ylabel="Y [m]", title=f"{title} (×{scale:g})")
    return finished(fig)


# -- widgets --------------------------------------------------------------------------------------

def coarse_pattern(pattern, size: int = 200) -> np.ndarray:
    """``pattern`` pooled to at most ``size``×``size`` cells (a cell is set if any entry is).

    >>> coarse_pattern(np.eye(400, dtype=bool), 100).shape
    (100, 100)
    """
    p = np.asarray(pattern, bool)
    f = max(1, -(-p.shape[0] // size))
    n = -(-p.shape[0] // f) * f
    q = np.zeros((n, n), bool)
    q[:p.shape[0], :p.shape[1]] = p
    return q.reshape(n // f, f, n // f, f).any(axis=(1, 3))


class BlockExplorer(Explorer):
    """Strips, images per strip, forward overlap, control points → counts and the N pattern."""

    title = "block explorer"

    def __init__(self, strips=2.0, per_strip=3.0, overlap=60.0, n_control=4.0):
        self.controls = {"strips": slider("strips", strips, 1, 3, 1, fmt=".0f"),
                         "per_strip": slider("images / strip", per_strip, 2, 4, 1, fmt=".0f"),
                         "overlap": slider("overlap [%]", overlap, 55, 80, 5, fmt=".0f"),
                         "n_control": slider("control points", n_control, 0, 12, 1, fmt=".0f")}
        self.live = LiveFigure((7.2, 3.4))
        fig = self.live.figure
        ax = fig.add_subplot(1, 2, 1)
        bx = fig.add_subplot(1, 2, 2)
        fig.subplots_adjust(0.1, 0.14, 0.98, 0.9, wspace=0.3)
        ax.set(xlim=(-400, 1400), ylim=(-400, 1300), aspect="equal", xlabel="X [m]",
               ylabel="Y [m]", title="plan")
        (self._pts,) = ax.plot([], [], ".", color="0.4", ms=3)
        (self._ctrl,) = ax.plot([], [], "^", color="#d62728", ms=6)
        (self._prints,) = ax.plot([], [], color="#1f77b4", lw=0.8)
        self._image = bx.imshow(np.zeros((2, 2)), cmap="Greys", vmin=0, vmax=1,
                                interpolation="nearest", extent=(0, 1, 1, 0))
        bx.set(xlim=(0, 1), ylim=(1, 0), title="N (non-zero black)", xticks=[], yticks=[])
        bx.grid(False)
        (self._box,) = bx.plot([], [], color="#d62728", lw=1)
        for artist in (self._pts, self._ctrl, self._prints, self._image, self._box):
            self.live.animate(artist)
        self.report = None
        self._finish()

    def draw(self, strips, per_strip, overlap, n_control) -> str:
        s, k = int(round(strips)), int(round(per_strip))
        self.report = rep = block_report(s, k, overlap / 100.0, n_control)
        b = simulate_block(s, k, overlap / 100.0, 0.0)
        control = control_order(b.points, int(round(n_control)))
        self._pts.set_data(*b.points[:, :2].T)
        self._ctrl.set_data(*b.points[control][:, :2].T)
        seg = [np.vstack([_footprint(e), [np.nan, np.nan]]) for e in b.exterior]
        self._prints.set_data(*np.vstack(seg).T)
        self._image.set_data(coarse_pattern(rep["pattern"]).astype(float))
        self._image.set_extent((0, 1, 1, 0))
        m = 6 * rep["n_images"] / rep["u"]
        self._box.set_data([0, m, m, 0, 0], [0, 0, m, m, 0])
        return rep["html"]


class BlunderExplorer(Explorer):
    """Size and place of a gross error → standardised residuals, which observation is flagged."""

    title = "gross-error explorer"
    scale = 500.0

    def __init__(self, blunder_um=30.0, observation=157.0):
        block, _ = _clean(6)
        self.controls = {"blunder_um": slider("blunder [µm]", blunder_um, 0, 100, 1, fmt=".0f"),
                         "observation": slider("observation", observation, 0, len(block.xy) - 1,
                                               1, fmt=".0f")}
        self.live = LiveFigure((7.2, 3.2))
        fig = self.live.figure
        ax = fig.add_subplot(1, 2, 1)
        bx = fig.add_subplot(1, 2, 2)
        fig.subplots_adjust(0.09, 0.15, 0.98, 0.9, wspace=0.3)
        ax.plot(*format_corners(HALF_MM, HALF_MM).T, color="0.5", lw=1)
        ax.set(xlim=(-55, 55), ylim=(-55, 55), aspect="equal", xlabel="x' [mm]",
               ylabel="y' [mm]", title=f"residuals ×{self.scale:g}")
        (self._points,) = ax.plot([], [], "o", color="#8c564b", ms=2)
        (self._vectors,) = ax.plot([], [], color="#1f77b4", lw=1)
        (self._target,) = ax.plot([], [], "o", color="#d62728", ms=7, mfc="none")
        n = 2 * len(block.xy)
        bx.set(xlim=(0, n), ylim=(0, 12), xlabel="observation coordinate", ylabel="|τ|",
               title="τ test (Pope)")
        (self._stats,) = bx.plot([], [], ".", color="#1f77b4", ms=2)
        (self._flagged,) = bx.plot([], [], "o", color="#d62728", ms=6, mfc="none")
        (self._critical,) = bx.plot([], [], "--", color="#d62728", lw=1)
        for artist in (self._points, self._vectors, self._target, self._stats, self._flagged,
                       self._critical):
            self.live.animate(artist)
        self.report = None
        self._finish()

    def draw(self, blunder_um, observation) -> str:
        self.report = rep = blunder_report(blunder_um, observation)
        block, res, tau = rep["block"], rep["result"], rep["snooping"]
        rows = np.flatnonzero(block.image_index == rep["image"])
        xy = block.xy[rows]
        self._points.set_data(*xy.T)
        seg = np.stack([xy, xy + self.scale * res.residuals[rows]], axis=1)
        self._vectors.set_data(*lines_xyz(seg)[:2])
        self._target.set_data(*block.xy[rep["observation"]][:, None])
        s = np.abs(np.nan_to_num(tau.statistic)).ravel()
        self._stats.set_data(np.arange(len(s)), np.minimum(s, 11.9))
        f = tau.flagged
        self._flagged.set_data(2 * f[:, 0] + f[:, 1], np.minimum(s[2 * f[:, 0] + f[:, 1]], 11.9))
        self._critical.set_data([0, len(s)], [tau.critical] * 2)
        return rep["html"]


@functools.lru_cache(maxsize=16)
def _precision(n_control: int):
    block = simulate_block()
    # only Q_xx matters (rescaled to the slider's σ): one step from the truth is enough
    res, control = adjust(block, n_control, start=(block.exterior, block.points), max_iter=1,
                          check=False)
    return block, res, control


def precision_report(n_control: int = 6, noise_um: float = 3.0) -> dict:
    """Precision of the chapter's block's points for a control configuration.

    ``n_control`` control points of :func:`control_order` (0: free network, 1–2: datum not
    fixed); covariances scaled to an a-priori image precision ``noise_um`` (µm), i.e.
    ``σ²·Q_xx``. Returns ``result`` (None without datum), ``cov`` (P, 3, 3) m², ``std``
    (P, 3) mm, ``control``, ``html``.

    Examples
    --------
    >>> rep = precision_report(4, 3.0)
    >>> bool(precision_report(4, 6.0)["std"].max() > 1.99 * rep["std"].max())
    True
    """
    nc = int(round(n_control))
    block = simulate_block()
    if 0 < nc < 3:
        html = ("<p style='color:#b00'>datum not fixed: at least 3 control points (7 datum "
                "parameters), or 0 for a free network</p>")
        return {"result": None, "cov": None, "std": np.full((len(block.points), 3), np.nan),
                "control": control_order(block.points, nc), "html": html}
    _, res, control = _precision(nc)
    cov = res.point_covariance * (noise_um * 1e-3 / res.sigma0) ** 2
    std = np.sqrt(np.einsum("pii->pi", cov)) * 1e3
    new = np.setdiff1d(np.arange(len(std)), control)
    mean = std[new].mean(axis=0)
    worst = std[new].max(axis=0)
    datum = "free network (inner precision)" if nc == 0 else f"{nc} control points"
    html = (f"<p>{datum}, image precision σ = {noise_um:.0f} µm<br>"
            f"mean σX, σY, σZ = {mean[0]:.0f}, {mean[1]:.0f}, {mean[2]:.0f} mm<br>"
            f"largest σX, σY, σZ = {worst[0]:.0f}, {worst[1]:.0f}, {worst[2]:.0f} mm</p>")
    return {"result": res, "cov": cov, "std": std, "control": control, "html": html}


class PrecisionExplorer(Explorer):
    """Control configuration and image precision → standard ellipses and σZ of the points."""

    title = "precision explorer"
    scale = 1000.0

    def __init__(self, n_control=4.0, noise_um=3.0):
        self.controls = {"n_control": slider("control points", n_control, 0, 12, 1, fmt=".0f"),
                         "noise_um": slider("σ image [µm]", noise_um, 1, 10, 1, fmt=".0f")}
        self.live = LiveFigure((6.4, 3.6))
        fig = self.live.figure
        ax = fig.add_subplot(1, 1, 1)
        fig.subplots_adjust(0.1, 0.13, 0.88, 0.9)
        block = simulate_block()
        ax.set(xlim=(-350, 850), ylim=(-350, 750), aspect="equal", xlabel="X [m]",
               ylabel="Y [m]", title=f"standard ellipses ×{self.scale:g}, σZ in colour")
        (self._ellipses,) = ax.plot([], [], color="#1f77b4", lw=0.7)
        self._dots = ax.scatter(*block.points[:, :2].T, c=np.zeros(len(block.points)), s=9,
                                cmap="viridis", vmin=0, vmax=150)
        fig.colorbar(self._dots, ax=ax, label="σZ [mm]")
        (self._ctrl,) = ax.plot([], [], "^", color="#d62728", ms=6)
        for artist in (self._ellipses, self._dots, self._ctrl):
            self.live.animate(artist)
        self.report = None
        self._finish()

    def draw(self, n_control, noise_um) -> str:
        self.report = rep = precision_report(n_control, noise_um)
        block = simulate_block()
        pts = block.points
        self._ctrl.set_data(*pts[rep["control"]][:, :2].T)
        if rep["cov"] is None:
            self._ellipses.set_data([], [])
            self._dots.set_array(np.full(len(pts), np.nan))
            return rep["html"]
        ell = standard_ellipses(rep["cov"][:, :2, :2], self.scale, n=25) + pts[:, None, :2]
        keep = np.setdiff1d(np.arange(len(pts)), rep["control"])
        seg = np.concatenate([ell[keep], np.full((len(keep), 1, 2), np.nan)], axis=1)
        self._ellipses.set_data(*seg.reshape(-1, 2).T)
        self._dots.set_array(rep["std"][:, 2])
        return rep["html"]
