r"""The block structure of a bundle adjustment: layout of the unknowns, normal equations by
blocks, the reduced camera system and the statistics from its inverse.

Unknowns: ``y`` = the exterior orientation of every image (6 each), the k interior
parameters and, for a free network, the d = 7 Lagrange multipliers of the inner
constraints (the *global* columns, e = k + d of them), and the 3 coordinates of every point
that is not fixed. Per observation n (image a = j(n), point p = i(n)) the Jacobian has the
blocks ``A_n`` (2 × 6 camera, 2 × k interior) and ``Ap_n`` (2 × 3 point). The normal
matrix is accumulated in blocks, never as a matrix over all unknowns:

.. math::
    U_a = \sum_{n \in a} [A_n\ l_n]^T [A_n\ l_n],\quad
    V_p = \sum_{n \in p} Ap_n^T Ap_n,\quad W_n = Ap_n^T A_n^{cam}\ (3×6),\quad
    E_p = [\textstyle\sum_{n \in p} Ap_n^T A_n^{int} \mid B_p]\ (3×e)

The points are eliminated point by point (Schur complement) with ``Y_n = V_p^{-1} W_n``,
``Z_p = V_p^{-1} E_p``: the reduced camera system ``K dy = b_y − Σ Tᵀ V⁻¹ b_p`` has
6 × 6 blocks only for the image pairs (a, b) that share a new point,

.. math::
    K_{ab} = δ_{ab} U_a - \sum_{p \ni a, b} W_{n(a,p)}^T Y_{n(b,p)},\qquad
    K_{a,g} = U_{a,int} - \sum_{n \in a} W_n^T Z_p,\qquad
    K_{gg} = \textstyle\sum_a U_{int,int} - \sum_p E_p^T Z_p

solved by a dense Cholesky (LU for the indefinite system of a free network) while it is
small and by a sparse LU (SuperLU, symmetric ordering, no pivoting when it is positive
definite) when it is not. Of Q = K⁻¹ the statistics need only the 6 × 6 blocks of the image
pairs that share a point, the image–global and the global blocks: from the dense inverse
while K is small (and for a free network), else from a block-tridiagonal selected inverse
(:mod:`~photolib.bundle._selinv`, no matrix of size ny × ny). The covariance blocks follow
from the same structure: the camera–point cross covariance per observation and the point
covariance per point,

.. math::
    Q_{a p} = -\sum_{m \in p} Q_{a, j(m)} Y_m^T - Q_{a g} Z_p^T,\qquad
    Q_{pp} = V_p^{-1} - \sum_{n \in p} Y_n Q_{j(n) p} - Z_p Q_{g p},

and the diagonal of ``A Q_xx Aᵀ`` per observation from its 2 × 2 block
``[A_n\ Ap_n] Q_{(a,g,p)} [A_n\ Ap_n]^T``: O(Σ_p rays_p²) work, no matrix over all unknowns
or all observations.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.linalg as sla
import scipy.sparse as sps
import scipy.sparse.linalg as spla

from photolib.bundle._datum import DatumError, _check_point_blocks, _inner_constraints
from photolib.bundle._selinv import BorderedCholesky, InverseBlocks, camera_groups

#: the reduced camera system is solved densely (Cholesky / LU) up to this many unknowns
#: (about 160 images with self-calibration), above by the block-tridiagonal Cholesky of
#: :mod:`~photolib.bundle._selinv` (fixed datum, at least ``MIN_GROUPS`` camera groups) or
#: a sparse LU (free network, or a block too compact for groups)
DENSE_LIMIT = 1000
#: the blocks of K⁻¹ for the statistics come from the block-tridiagonal selected inverse
#: (:mod:`~photolib.bundle._selinv`) above this many unknowns (fixed datum, at least 3
#: camera groups), from the dense inverse below (and for a free network)
BANDED_LIMIT = 1000
#: fewest camera groups for which the banded route pays (fewer: the dense inverse)
MIN_GROUPS = 3
#: largest number of observation pairs whose 6 × 6 products are formed at once (memory)
PAIR_CHUNK = 1 << 16


def _indicator(groups, n_groups):
    """Sparse (n_groups × len(groups)) 0/1 matrix S with S[g, n] = 1 if groups[n] = g:
    ``S @ x`` sums the rows of x by group (empty groups give 0)."""
    n = len(groups)
    return sps.csr_matrix((np.ones(n), (groups, np.arange(n))), shape=(n_groups, n))


def _group_sum(S, x):
    """Sums of the rows of x (n, …) by the groups of the indicator S: (n_groups, …)."""
    flat = x.reshape(len(x), int(np.prod(x.shape[1:], dtype=int)))
    return np.asarray(S @ flat).reshape((S.shape[0],) + x.shape[1:])


@dataclass(frozen=True)
class Layout:
    """The unknowns and the observation structure of a block, fixed for all iterations.

    ``y`` = 6M camera unknowns, then the k interior parameters and the d Lagrange
    multipliers (``e = k + d`` global columns, ``ny = 6M + e``); the points with unknowns
    are ``free`` (slot ``slot[i]``, −1: fixed). The observations of free points are ``mo``,
    sorted by point and, within a point, by image; ``q1 ≤ q2`` (positions in ``mo``) run
    over every pair of observations of one point (the diagonal included), sorted by the
    image pair ``pid`` (images ``pair_a[pid] ≤ pair_b[pid]``)."""

    M: int
    P: int
    k: int
    d: int
    calib: tuple
    free: np.ndarray
    slot: np.ndarray
    fixc: np.ndarray
    wts: np.ndarray
    colmask: np.ndarray
    control_obs: np.ndarray
    partial: bool
    observed: bool
    n_obs: int
    n_c: int
    u: int
    r: int
    extent: float
    mo: np.ndarray
    ps: np.ndarray
    jm: np.ndarray
    q1: np.ndarray
    q2: np.ndarray
    pid: np.ndarray
    pair_a: np.ndarray
    pair_b: np.ndarray
    by_image: object  # indicator (M × N)
    by_point: object  # indicator (Pf × Nm)
    by_cam_free: object  # indicator (M × Nm)
    by_pair: object  # indicator (pairs × T), CSC: sliced by chunks of pairs
    by_q1: np.ndarray  # (T,) the pairs in the order of q1 (non-decreasing)
    by_q2: np.ndarray  # (T_off,) the pairs with q1 ≠ q2 in the order of q2
    diag_pair: np.ndarray  # (M,) pid of (a, a)

    @property
    def e(self) -> int:
        return self.k + self.d

    @property
    def ny(self) -> int:
        return 6 * self.M + self.k + self.d


def make_layout(j, i, M, pts, sig, weighted, calib, datum, sigma_image) -> Layout:
    """The :class:`Layout` of a block of M images: the unknowns (u), the redundancy
    r = n + n_c − u + d and the pair structure of the observations (image j, point i).
    ``sig`` (P, 3) σ per control coordinate (0 fixed, inf unknown), ``weighted`` (P, 3)
    0 < σ < ∞. Raises ``DatumError`` if r < 0."""
    P, k = len(pts), len(calib)
    rays = np.bincount(i, minlength=P)
    # points without unknowns: all coordinates fixed, or known and in no image
    ctrl = np.all(sig == 0, axis=1) | (np.all(np.isfinite(sig), axis=1) & (rays == 0))
    free = np.flatnonzero(~ctrl)
    slot = np.full(P, -1)
    slot[free] = np.arange(len(free))
    fixc = sig[free] == 0
    wts = np.zeros((len(free), 3))
    wts[weighted[free]] = (sigma_image / sig[free][weighted[free]]) ** 2
    n_obs, n_c = 2 * len(j), int(np.count_nonzero(wts))
    u = 6 * M + 3 * len(free) - int(fixc.sum()) + k
    d = 7 if datum == "free" else 0
    r = n_obs + n_c - u + d
    if r < 0:
        raise DatumError(f"more unknowns than observations: n = {n_obs} + {n_c} (control), "
                         f"u = {u}, d = {d}")
    m = np.flatnonzero(~ctrl[i])
    mo = m[np.lexsort((j[m], slot[i[m]]))]
    ps, jm = slot[i[mo]], j[mo]
    counts = np.bincount(ps, minlength=len(free))
    start = np.r_[0, np.cumsum(counts)[:-1]]
    # all pairs q1 ≤ q2 of observations of one point: q1 repeated (end − q1) times
    reps = (start + counts)[ps] - np.arange(len(mo))
    q1 = np.repeat(np.arange(len(mo)), reps)
    q2 = q1 + np.arange(len(q1)) - np.repeat(np.cumsum(reps) - reps, reps)
    key = jm[q1] * M + jm[q2]
    ukeys, pid = np.unique(np.r_[key, np.arange(M) * (M + 1)], return_inverse=True)
    pid = pid[:len(key)]
    order = np.argsort(pid, kind="stable")
    q1, q2, pid = q1[order], q2[order], pid[order]
    by_q1 = np.empty_like(order)
    by_q1[order] = np.arange(len(order))  # the enumeration above was q1-major
    off = np.flatnonzero(q1 != q2)
    return Layout(
        M=M, P=P, k=k, d=d, calib=calib, free=free, slot=slot, fixc=fixc, wts=wts,
        colmask=(sig != 0).astype(float), control_obs=pts[free].copy(),
        partial=bool(fixc.any()), observed=bool(np.any(wts > 0)), n_obs=n_obs, n_c=n_c, u=u,
        r=r, extent=float(np.max(np.ptp(pts, axis=0))) or 1.0, mo=mo, ps=ps, jm=jm, q1=q1,
        q2=q2, pid=pid, pair_a=ukeys // M, pair_b=ukeys % M,
        by_image=_indicator(j, M), by_point=_indicator(ps, len(free)),
        by_cam_free=_indicator(jm, M), by_pair=_indicator(pid, len(ukeys)).tocsc(),
        by_q1=by_q1, by_q2=off[np.argsort(q2[off], kind="stable")],
        diag_pair=np.searchsorted(ukeys, np.arange(M) * (M + 1)))


def _subtract_sorted(out, targets, values):
    """``out[targets[k]] −= values[k]`` for non-decreasing ``targets``: a sum by group into
    the contiguous range of ``out`` they cover (work O(len(targets)), not O(len(out)))."""
    if not len(targets):
        return
    lo, hi = int(targets[0]), int(targets[-1]) + 1
    counts = np.bincount(targets - lo, minlength=hi - lo)
    S = sps.csr_matrix((np.ones(len(targets)), np.arange(len(targets)),
                        np.r_[0, np.cumsum(counts)]), shape=(hi - lo, len(targets)))
    out[lo:hi] -= _group_sum(S, values)


def _chunks(n):
    return [slice(s, min(s + PAIR_CHUNK, n)) for s in range(0, n, PAIR_CHUNK)] or [slice(0, 0)]


@dataclass
class Normals:
    """The normal equations in blocks (see the module): ``Ninv`` (Pf, 3, 3) = V_p⁻¹,
    ``Y`` (Nm, 3, 6), ``Z`` (Pf, 3, e), ``t`` (Pf, 3) = V_p⁻¹ b_p; the reduced system as
    ``Kc`` (pairs, 6, 6), ``Kg`` (M, 6, e), ``Kgg`` (e, e) and its right side ``rhs`` (ny,)."""

    Ninv: np.ndarray
    Y: np.ndarray
    Z: np.ndarray
    t: np.ndarray
    Kc: np.ndarray
    Kg: np.ndarray
    Kgg: np.ndarray
    rhs: np.ndarray


def normals(lay: Layout, v, A, Ap, pts) -> Normals:
    """Normal equations by blocks and the Schur complement onto y (formulas: the module).

    ``v`` (N, 2) residuals, ``A`` (N, 2, 6 + k), ``Ap`` (N, 2, 3) the Jacobian blocks.
    ``DatumError`` names the new points whose 3 × 3 blocks are singular."""
    M, k, d, e = lay.M, lay.k, lay.d, lay.e
    lv = -v[:, :, None]
    U = _group_sum(lay.by_image, A.transpose(0, 2, 1) @ np.concatenate([A, lv], axis=2))
    mo = lay.mo
    Apm = Ap[mo]
    S = _group_sum(lay.by_point, Apm.transpose(0, 2, 1) @ np.concatenate([Apm, A[mo], lv[mo]],
                                                                         axis=2))
    Npp, bp = S[:, :, :3], S[:, :, -1]
    if lay.partial or lay.observed:
        Npp = Npp + (lay.wts + lay.fixc)[:, :, None] * np.eye(3)
        bp = bp - lay.wts * (pts[lay.free] - lay.control_obs)
    _check_point_blocks(Npp, lay.free)
    Ninv = np.linalg.inv(Npp)
    W = Apm.transpose(0, 2, 1) @ A[mo, :, :6]  # (Nm, 3, 6)
    Y = np.take(Ninv, lay.ps, axis=0) @ W
    Wt = np.ascontiguousarray(W.transpose(0, 2, 1))
    E = np.concatenate([S[:, :, 9:9 + k], np.zeros((len(lay.free), 3, d))], axis=2)
    if d:
        E[:, :, k:] = _inner_constraints(pts).reshape(lay.P, 3, 7)[lay.free]
    Z, t = Ninv @ E, (Ninv @ bp[:, :, None])[:, :, 0]
    Kc = np.zeros((len(lay.pair_a), 6, 6))
    for c in _chunks(len(lay.q1)):
        prod = np.take(Wt, lay.q1[c], axis=0) @ np.take(Y, lay.q2[c], axis=0)
        Kc -= _group_sum(lay.by_pair[:, c], prod)
    Kc[lay.diag_pair] += U[:, :6, :6]
    Kg = np.zeros((M, 6, e))
    Kg[:, :, :k] = U[:, :6, 6:6 + k]
    Kg -= _group_sum(lay.by_cam_free, Wt @ np.take(Z, lay.ps, axis=0))
    Kgg = np.zeros((e, e))
    Kgg[:k, :k] = U[:, 6:6 + k, 6:6 + k].sum(axis=0)
    Kgg -= np.einsum("pia,pib->ab", E, Z)
    rhs = np.zeros(lay.ny)
    rhs[:6 * M] = (U[:, :6, -1] - _group_sum(lay.by_cam_free, (W.transpose(0, 2, 1)
                                                              @ t[lay.ps][:, :, None])[:, :, 0])
                   ).ravel()
    rhs[6 * M:6 * M + k] = U[:, 6:6 + k, -1].sum(axis=0)
    rhs[6 * M:] -= np.einsum("pia,pi->a", E, t)
    return Normals(Ninv, Y, Z, t, Kc, Kg, Kgg, rhs)


def back_substitute(lay: Layout, nrm: Normals, dy):
    """Point corrections ``dp_p = t_p − Σ_{n∈p} Y_n dy_{j(n)} − Z_p dy_g`` (Pf, 3)."""
    dyc = dy[:6 * lay.M].reshape(lay.M, 6)
    dp = nrm.t - _group_sum(lay.by_point, (nrm.Y @ dyc[lay.jm][:, :, None])[:, :, 0])
    return dp - nrm.Z @ dy[6 * lay.M:]


def _entries(lay: Layout, nrm: Normals):
    """Row, column and value of every non-zero of the reduced matrix K (both triangles)."""
    M, e = lay.M, lay.e
    r6 = np.arange(6)
    ra = (6 * lay.pair_a[:, None, None] + r6[None, :, None]) + 0 * r6[None, None, :]
    cb = (6 * lay.pair_b[:, None, None] + r6[None, None, :]) + 0 * r6[None, :, None]
    off = lay.pair_a != lay.pair_b
    rg = np.broadcast_to((6 * np.arange(M)[:, None] + r6)[:, :, None], (M, 6, e))
    cg = np.broadcast_to(6 * M + np.arange(e), (M, 6, e))
    gg_r, gg_c = np.meshgrid(6 * M + np.arange(e), 6 * M + np.arange(e), indexing="ij")
    rows = np.concatenate([ra.ravel(), cb[off].ravel(), rg.ravel(), cg.ravel(), gg_r.ravel()])
    cols = np.concatenate([cb.ravel(), ra[off].ravel(), cg.ravel(), rg.ravel(), gg_c.ravel()])
    vals = np.concatenate([nrm.Kc.ravel(), nrm.Kc[off].ravel(), nrm.Kg.ravel(), nrm.Kg.ravel(),
                           nrm.Kgg.ravel()])
    return rows, cols, vals


class ReducedSystem:
    """The reduced camera system K, Jacobi-scaled (``K_s = D K D``, ``D = |diag K|^{-1/2}``)
    and factorised once: dense Cholesky (LU if indefinite, free network) for
    ``ny ≤ DENSE_LIMIT``; above, for a fixed datum, the sparse Cholesky of
    :class:`~photolib.bundle._selinv.BorderedCholesky` (cameras in block-tridiagonal groups,
    the interior parameters as a border) when the block has at least ``MIN_GROUPS`` camera
    groups, else SuperLU with a symmetric (minimum-degree) ordering.

    The factorisation is accepted if two inverse iterations on random vectors put the
    condition ``‖K_s‖_F·‖K_s⁻¹‖`` below 1e10; otherwise the singular values of K_s decide:
    ``σ_min ≤ 1e-12·σ_max`` raises :class:`DatumError`, else a dense LU is used."""

    def __init__(self, lay: Layout, nrm: Normals):
        self.lay, self.nrm = lay, nrm
        rows, cols, vals = _entries(lay, nrm)
        ny = lay.ny
        diag = np.zeros(ny)
        on = rows == cols
        np.add.at(diag, rows[on], vals[on])
        self.scale = 1.0 / np.sqrt(np.where(np.abs(diag) > 0, np.abs(diag), 1.0))
        vals = vals * self.scale[rows] * self.scale[cols]
        self.sparse = ny > DENSE_LIMIT
        if self.sparse:
            self.Ks = sps.csc_matrix((vals, (rows, cols)), shape=(ny, ny))
        else:
            self.Ks = np.zeros((ny, ny))
            self.Ks[rows, cols] = vals
        self.kind = None
        probe = np.random.default_rng(0).standard_normal((ny, 2))
        try:
            self._factor()
            z = self._solve_s(probe)
            z2 = self._solve_s(z / np.linalg.norm(z, axis=0))
            fro = (sps.linalg.norm(self.Ks) if self.sparse else np.linalg.norm(self.Ks))
            if fro * np.max(np.linalg.norm(z2, axis=0)) < 1e10 and np.all(np.isfinite(z2)):
                return
        except (np.linalg.LinAlgError, RuntimeError, ValueError):
            pass
        self._check_singular()

    def _scaled_blocks(self):
        """``Kc`` (pairs, 6, 6), ``Kg`` (M, 6, e), ``Kgg`` (e, e) of K_s and the scales
        ``(sa, sb, scg, sgg)`` that multiply them."""
        lay, nrm, M = self.lay, self.nrm, self.lay.M
        sc, sg = self.scale[:6 * M].reshape(M, 6), self.scale[6 * M:]
        sa, sb = sc[lay.pair_a][:, :, None], sc[lay.pair_b][:, None, :]
        scg, sgg = sc[:, :, None] * sg, sg[:, None] * sg
        return (nrm.Kc * sa * sb, nrm.Kg * scg, nrm.Kgg * sgg), (sa, sb, scg, sgg)

    def _banded(self, cg) -> BorderedCholesky:
        (Kc, Kg, Kgg), _ = self._scaled_blocks()
        return BorderedCholesky(cg, Kc, Kg, Kgg, self.lay.pair_a, self.lay.pair_b)

    def _factor(self):
        lay = self.lay
        if self.sparse and lay.d == 0:
            cg = camera_groups(lay.M, lay.pair_a, lay.pair_b)
            if cg.G >= MIN_GROUPS:
                self.kind, self.fac = "banded", self._banded(cg)
                return
        if self.sparse:
            pivot = 0.0 if self.lay.d == 0 else 1.0
            self.kind = "splu"
            self.fac = spla.splu(self.Ks, permc_spec="MMD_AT_PLUS_A", diag_pivot_thresh=pivot,
                                 options={"SymmetricMode": self.lay.d == 0})
        elif self.lay.d == 0:
            self.kind = "cholesky"
            self.fac = sla.cho_factor(self.Ks, check_finite=False)
        else:
            self.kind = "lu"
            self.fac = sla.lu_factor(self.Ks, check_finite=False)

    def _solve_s(self, b):
        if self.kind in ("banded", "splu"):
            return self.fac.solve(b)
        if self.kind == "cholesky":
            return sla.cho_solve(self.fac, b, check_finite=False)
        return sla.lu_solve(self.fac, b, check_finite=False)

    def _check_singular(self):
        Ks = self.Ks.toarray() if self.sparse else self.Ks
        sv = np.linalg.svd(Ks, compute_uv=False)
        if sv[-1] <= 1e-12 * sv[0]:
            what = ("the inner constraints do not remove the defect" if self.lay.d else
                    "the control points do not fix the datum")
            raise DatumError(f"the reduced normal matrix is singular (condition "
                             f"{sv[0] / max(sv[-1], 1e-300):.3g}): {what}, or the geometry is "
                             "degenerate (e.g. self-calibration parameters not determined)")
        self.sparse, self.Ks, self.kind = False, Ks, "lu"
        self.fac = sla.lu_factor(Ks, check_finite=False)

    def solve(self, rhs):
        """``K⁻¹ rhs`` (ny,)."""
        return self.scale * self._solve_s(self.scale * rhs)

    def inverse_blocks(self, route: str | None = None) -> InverseBlocks:
        """The blocks of K⁻¹ the statistics use (:class:`~photolib.bundle._selinv.InverseBlocks`).

        ``route`` ``"banded"``: the block-tridiagonal selected inverse of
        :mod:`~photolib.bundle._selinv` (fixed datum only; O(M·s²)); ``"dense"``: from
        :meth:`inverse`; ``None`` chooses banded for ``ny > BANDED_LIMIT`` with at least
        ``MIN_GROUPS`` camera groups and a fixed datum. A banded factorisation that finds K
        not positive definite falls back to the dense route (which names a singular
        system)."""
        lay = self.lay
        M = lay.M
        if route == "banded" and lay.d:
            raise ValueError("the banded selected inverse needs a fixed datum (d = 0)")
        if route is None and self.kind == "banded":
            route = "banded"
        cg = None
        if route is None and lay.d == 0 and lay.ny > BANDED_LIMIT:
            cg = camera_groups(M, lay.pair_a, lay.pair_b)
            route = "banded" if cg.G >= MIN_GROUPS else "dense"
        if route == "banded":
            try:
                fac = self.fac if self.kind == "banded" else self._banded(
                    cg or camera_groups(M, lay.pair_a, lay.pair_b))
                blk = fac.inverse_blocks()
                _, (sa, sb, scg, sgg) = self._scaled_blocks()
                return InverseBlocks(blk.pairs * sa * sb, blk.cam_global * scg,
                                     blk.global_global * sgg)
            except np.linalg.LinAlgError:
                pass
        Kinv = self.inverse()
        r6 = np.arange(6)
        pairs = Kinv[6 * lay.pair_a[:, None, None] + r6[:, None],
                     6 * lay.pair_b[:, None, None] + r6]
        return InverseBlocks(pairs, Kinv[:6 * M, 6 * M:].reshape(M, 6, lay.e),
                             Kinv[6 * M:, 6 * M:])

    def inverse(self):
        """The dense ``K⁻¹`` (ny × ny), for :meth:`inverse_blocks`' dense route. Always by
        LAPACK (Cholesky and ``dpotri``, or LU for a free network), also after a sparse
        solve: its blocked inverse costs less than ny sparse triangular solves."""
        ny = self.lay.ny
        Ks = self.Ks.toarray() if self.sparse else self.Ks
        fac = self.fac if self.kind == "cholesky" else None
        if fac is None and self.lay.d == 0:
            try:
                fac = sla.cho_factor(Ks, check_finite=False)
            except np.linalg.LinAlgError:
                fac = None
        if fac is not None:
            inv, info = sla.lapack.dpotri(fac[0], lower=fac[1])
            if info:
                raise DatumError(f"the reduced normal matrix could not be inverted (dpotri "
                                 f"info {info})")
            inv = np.tril(inv) + np.tril(inv, -1).T if fac[1] else np.triu(inv) + np.triu(inv, 1).T
        else:
            lu = self.fac if self.kind == "lu" else sla.lu_factor(Ks, check_finite=False)
            inv = sla.lu_solve(lu, np.eye(ny), check_finite=False)
            inv = 0.5 * (inv + inv.T)  # K is symmetric: LU leaves rounding asymmetry
        return self.scale[:, None] * inv * self.scale[None, :]


@dataclass(frozen=True)
class Covariances:
    """Cofactor blocks (not yet scaled by σ0²): ``Qcam`` (M, 6, 6) of each image,
    ``Qint`` (k, k) of the interior parameters, ``Qpp`` (Pf, 3, 3) of each free point,
    ``Qcp`` (Nm, 6, 3) image–point cross cofactors of the observations ``mo`` and ``qhat``
    (N, 2) = diag(A Q_xx Aᵀ) per observation."""

    Qcam: np.ndarray
    Qint: np.ndarray
    Qpp: np.ndarray
    Qcp: np.ndarray
    qhat: np.ndarray


def covariances(lay: Layout, nrm: Normals, inv: InverseBlocks, A, Ap, j) -> Covariances:
    """The cofactor blocks of the module's formulas from the blocks ``inv`` of K⁻¹
    (:meth:`ReducedSystem.inverse_blocks`) and the Jacobian blocks ``A`` (N, 2, 6 + k),
    ``Ap`` (N, 2, 3) of the observations (images j)."""
    M, k = lay.M, lay.k
    Kb, Kcg, Kgg = inv.pairs, inv.cam_global, inv.global_global
    Yt = np.ascontiguousarray(nrm.Y.transpose(0, 2, 1))  # (Nm, 6, 3)
    Kbt = np.ascontiguousarray(Kb.transpose(0, 2, 1))
    Kcg_m = np.take(Kcg, lay.jm, axis=0)
    C = -(Kcg_m @ np.take(nrm.Z, lay.ps, axis=0).transpose(0, 2, 1))
    for c in _chunks(len(lay.by_q1)):  # C_{q1} −= K⁻¹_{j(q1) j(q2)} Y_{q2}ᵀ over all pairs …
        pairs = lay.by_q1[c]
        B = np.take(Kb, lay.pid[pairs], axis=0)
        _subtract_sorted(C, lay.q1[pairs], B @ np.take(Yt, lay.q2[pairs], axis=0))
    for c in _chunks(len(lay.by_q2)):  # … and C_{q2} −= (K⁻¹_{j(q1) j(q2)})ᵀ Y_{q1}ᵀ, q1 ≠ q2
        pairs = lay.by_q2[c]
        Bt = np.take(Kbt, lay.pid[pairs], axis=0)
        _subtract_sorted(C, lay.q2[pairs], Bt @ np.take(Yt, lay.q1[pairs], axis=0))
    Qgp = -(_group_sum(lay.by_point, Kcg_m.transpose(0, 2, 1) @ Yt)
            + Kgg @ nrm.Z.transpose(0, 2, 1))  # (Pf, e, 3)
    Qpp = nrm.Ninv - _group_sum(lay.by_point, nrm.Y @ C) - nrm.Z @ Qgp
    Qcam = Kb[lay.diag_pair]
    Qsub = np.empty((M, 6 + k, 6 + k))  # image a's own unknowns and the interior parameters
    Qsub[:, :6, :6] = Qcam
    Qsub[:, :6, 6:] = Kcg[:, :, :k]
    Qsub[:, 6:, :6] = Kcg[:, :, :k].transpose(0, 2, 1)
    Qsub[:, 6:, 6:] = Kgg[:k, :k]
    qhat = np.sum((A @ np.take(Qsub, j, axis=0)) * A, axis=2)
    mo = lay.mo
    Qyp = np.concatenate([C, np.take(Qgp[:, :k], lay.ps, axis=0)], axis=1)  # (Nm, 6 + k, 3)
    Am, Apm = A[mo], Ap[mo]
    qhat[mo] += np.sum((2.0 * (Am @ Qyp) + Apm @ np.take(Qpp, lay.ps, axis=0)) * Apm, axis=2)
    return Covariances(Qcam, Kgg[:k, :k].copy(), Qpp, C, qhat)
