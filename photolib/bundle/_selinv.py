r"""The blocks of K⁻¹ the statistics need, without the dense inverse: a selected inverse of
the reduced camera system by a block-tridiagonal Cholesky factorisation.

The cameras are put in reverse Cuthill–McKee order of the graph "two images share a point"
(an aerial block: strip by strip); with b the largest distance in that order between two
images that share a point, groups of b consecutive images make the camera part ``Kc`` of K
block tridiagonal (groups I and I + 1 coupled, no others), with blocks of s = 6b unknowns.
Its Cholesky factor ``L`` is block bidiagonal,

.. math::
    L_{II} L_{II}^T = K_{II} - L_{I,I-1} L_{I,I-1}^T,\qquad
    L_{I+1,I} = K_{I+1,I} L_{II}^{-T},

and ``Z = Kc⁻¹ = L⁻ᵀL⁻¹`` restricted to the same block pattern follows backwards from
``Z L = L⁻ᵀ`` (upper triangular; Takahashi's recursion) with ``X_I = L_{I+1,I} L_{II}^{-1}``:

.. math::
    Z_{I+1,I} = -Z_{I+1,I+1} X_I,\qquad
    Z_{II} = (L_{II} L_{II}^T)^{-1} + X_I^T Z_{I+1,I+1} X_I .

Every image pair that shares a point lies in one group or two neighbouring ones, so these
blocks hold all of K⁻¹ the statistics use. The e global columns (interior parameters) border
Kc: with ``Xg = Kc⁻¹ K_cg`` and the Schur complement ``S = K_gg − K_cgᵀ Xg``,

.. math::
    (K^{-1})_{gg} = S^{-1},\quad (K^{-1})_{cg} = -X_g S^{-1},\quad
    (K^{-1})_{cc} = Z + X_g S^{-1} X_g^T .

Work O(M·s²) and memory O(M·s) instead of O((6M)³) and O((6M)²).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.linalg as sla
import scipy.sparse as sps
from scipy.sparse.csgraph import reverse_cuthill_mckee


@dataclass(frozen=True)
class CameraGroups:
    """The cameras in reverse Cuthill–McKee order, cut into ``G`` groups of ``g``:
    camera a is number ``local[a]`` of group ``group[a]``."""

    g: int
    G: int
    group: np.ndarray
    local: np.ndarray


def camera_groups(M: int, pair_a: np.ndarray, pair_b: np.ndarray) -> CameraGroups:
    """The :class:`CameraGroups` of M cameras coupled in the pairs (pair_a, pair_b)."""
    off = pair_a != pair_b
    adj = sps.csr_matrix((np.ones(2 * int(off.sum())), (np.r_[pair_a[off], pair_b[off]],
                                                        np.r_[pair_b[off], pair_a[off]])),
                         shape=(M, M))
    order = reverse_cuthill_mckee(adj, symmetric_mode=True)
    pos = np.empty(M, dtype=int)
    pos[order] = np.arange(M)
    g = max(int(np.max(np.abs(pos[pair_a] - pos[pair_b]), initial=0)), 1)
    return CameraGroups(g=g, G=-(-M // g), group=pos // g, local=pos % g)


@dataclass(frozen=True)
class InverseBlocks:
    """The blocks of K⁻¹ the statistics use: ``pairs`` (pairs, 6, 6) = (K⁻¹)_{ab} of every
    image pair (a, b) of the layout, ``cam_global`` (M, 6, e), ``global_global`` (e, e)."""

    pairs: np.ndarray
    cam_global: np.ndarray
    global_global: np.ndarray


class BlockTridiagonal:
    """Cholesky factor of the camera part of K (Jacobi-scaled, SPD) in the block-tridiagonal
    form of :func:`camera_groups`; ``np.linalg.LinAlgError`` if it is not positive definite.

    ``Kc`` (pairs, 6, 6) are the blocks K_{ab} (a ≤ b) of the pairs (pair_a, pair_b)."""

    def __init__(self, cg: CameraGroups, Kc, pair_a, pair_b):
        self.cg = cg
        s, G = 6 * cg.g, cg.G
        D = np.zeros((G, s, s))
        B = np.zeros((max(G - 1, 0), s, s))  # B[I] = K_{I+1, I}
        ga, gb = cg.group[pair_a], cg.group[pair_b]
        r6 = np.arange(6)
        ra = 6 * cg.local[pair_a][:, None] + r6  # (pairs, 6) rows of a within its group
        rb = 6 * cg.local[pair_b][:, None] + r6
        same, up, down = ga == gb, gb == ga + 1, ga == gb + 1
        D[ga[same][:, None, None], ra[same][:, :, None], rb[same][:, None, :]] = Kc[same]
        D[ga[same][:, None, None], rb[same][:, :, None], ra[same][:, None, :]] = \
            Kc[same].transpose(0, 2, 1)
        B[ga[up][:, None, None], rb[up][:, :, None], ra[up][:, None, :]] = \
            Kc[up].transpose(0, 2, 1)
        B[gb[down][:, None, None], ra[down][:, :, None], rb[down][:, None, :]] = Kc[down]
        pad = G * cg.g - len(cg.group)  # unused places of the last group: identity
        if pad:
            idx = np.arange(s - 6 * pad, s)
            D[-1, idx, idx] = 1.0
        self.L = np.empty_like(D)
        self.C = np.empty_like(B)  # C[I] = L_{I+1, I}
        for i in range(G):
            A = D[i] - self.C[i - 1] @ self.C[i - 1].T if i else D[i]
            self.L[i] = sla.cholesky(A, lower=True, check_finite=False)
            if i < G - 1:
                self.C[i] = sla.solve_triangular(self.L[i], B[i].T, lower=True,
                                                 check_finite=False).T

    def _rows(self, x):
        """(M·6, m) in camera order → (G, s, m) in group order (padding rows 0)."""
        cg = self.cg
        out = np.zeros((cg.G * cg.g, 6, x.shape[1]))
        out[cg.group * cg.g + cg.local] = x.reshape(-1, 6, x.shape[1])
        return out.reshape(cg.G, 6 * cg.g, x.shape[1])

    def _unrows(self, y):
        cg = self.cg
        flat = y.reshape(cg.G * cg.g, 6, y.shape[2])
        return flat[cg.group * cg.g + cg.local].reshape(-1, y.shape[2])

    def solve(self, x):
        """``Kc⁻¹ x`` for x (6M, m), by the block forward and back substitutions."""
        b = self._rows(x)
        for i in range(self.cg.G):
            rhs = b[i] - self.C[i - 1] @ b[i - 1] if i else b[i]
            b[i] = sla.solve_triangular(self.L[i], rhs, lower=True, check_finite=False)
        for i in reversed(range(self.cg.G)):
            rhs = b[i] - self.C[i].T @ b[i + 1] if i < self.cg.G - 1 else b[i]
            b[i] = sla.solve_triangular(self.L[i], rhs, lower=True, trans="T",
                                        check_finite=False)
        return self._unrows(b)

    def selected_inverse(self):
        """``(Zd, Zs)``: the diagonal blocks Z_II (G, s, s) and Z_{I+1,I} (G − 1, s, s) of
        Kc⁻¹ (the module's recursion)."""
        G = self.cg.G
        Zd, Zs = np.empty_like(self.L), np.empty_like(self.C)
        eye = np.eye(self.L.shape[1])
        for i in reversed(range(G)):
            Linv = sla.solve_triangular(self.L[i], eye, lower=True, check_finite=False)
            Zd[i] = Linv.T @ Linv
            if i < G - 1:
                X = self.C[i] @ Linv
                Zs[i] = -Zd[i + 1] @ X
                Zd[i] -= X.T @ Zs[i]
            Zd[i] = 0.5 * (Zd[i] + Zd[i].T)
        return Zd, Zs

    def pair_blocks(self, Zd, Zs, pair_a, pair_b):
        """The 6 × 6 blocks Z_{ab} (pairs, 6, 6) of the pairs, gathered from Zd and Zs."""
        cg = self.cg
        ga, gb = cg.group[pair_a], cg.group[pair_b]
        r6 = np.arange(6)
        ra = 6 * cg.local[pair_a][:, None] + r6
        rb = 6 * cg.local[pair_b][:, None] + r6
        out = np.empty((len(pair_a), 6, 6))
        same, up, down = ga == gb, gb == ga + 1, ga == gb + 1
        out[same] = Zd[ga[same][:, None, None], ra[same][:, :, None], rb[same][:, None, :]]
        out[up] = Zs[ga[up][:, None, None], rb[up][:, :, None], ra[up][:, None, :]] \
            .transpose(0, 2, 1)
        out[down] = Zs[gb[down][:, None, None], ra[down][:, :, None], rb[down][:, None, :]]
        return out


class BorderedCholesky:
    """Cholesky factorisation of the SPD K = [[Kc, Kg], [Kgᵀ, Kgg]] with the camera part
    ``Kc`` block tridiagonal (:class:`BlockTridiagonal`) and the e global columns as a Schur
    border: ``Xg = Kc⁻¹ Kg``, ``S = Kgg − Kgᵀ Xg`` (e × e, Cholesky). Solves K x = b and gives
    the :class:`InverseBlocks` (the module's formulas). All inputs Jacobi-scaled: ``Kc``
    (pairs, 6, 6), ``Kg`` (M, 6, e), ``Kgg`` (e, e). ``np.linalg.LinAlgError`` if K is not
    positive definite."""

    def __init__(self, cg: CameraGroups, Kc, Kg, Kgg, pair_a, pair_b):
        self.tri = BlockTridiagonal(cg, Kc, pair_a, pair_b)
        self.pair_a, self.pair_b = pair_a, pair_b
        M, e = Kg.shape[0], Kg.shape[2]
        self.M, self.e = M, e
        self.Kg = Kg.reshape(6 * M, e)
        self.Xg = self.tri.solve(self.Kg) if e else np.zeros((6 * M, 0))
        S = Kgg - self.Kg.T @ self.Xg
        self.S = sla.cho_factor(S, lower=True, check_finite=False) if e else None

    def solve(self, b):
        """``K⁻¹ b`` for b (6M + e,) or (6M + e, m)."""
        b2 = b.reshape(len(b), -1)
        n = 6 * self.M
        xc = self.tri.solve(b2[:n])
        if self.e:
            xg = sla.cho_solve(self.S, b2[n:] - self.Kg.T @ xc, check_finite=False)
            xc = xc - self.Xg @ xg
            out = np.vstack([xc, xg])
        else:
            out = xc
        return out.reshape(b.shape)

    def inverse_blocks(self) -> InverseBlocks:
        """The blocks of K⁻¹ of every image pair, image–global and global–global."""
        Zd, Zs = self.tri.selected_inverse()
        pairs = self.tri.pair_blocks(Zd, Zs, self.pair_a, self.pair_b)
        M, e = self.M, self.e
        if e == 0:
            return InverseBlocks(pairs, np.zeros((M, 6, 0)), np.zeros((0, 0)))
        Sinv = sla.cho_solve(self.S, np.eye(e), check_finite=False)
        XS = (self.Xg @ Sinv).reshape(M, 6, e)
        Xr = self.Xg.reshape(M, 6, e)
        pairs = pairs + XS[self.pair_a] @ Xr[self.pair_b].transpose(0, 2, 1)
        return InverseBlocks(pairs, -XS, Sinv)
