"""The block statistics of photolib.bundle against the dense computation, and the structure.

At the adjusted block the full design matrix over all unknowns (images, interior parameters,
unknown point coordinates; the control observations as rows with their weights) is formed
here densely, the normal matrix (bordered by the inner constraints for a free network)
inverted with NumPy, and σ0, every covariance block, the redundancy numbers of the image and
control observations and the w-test values compared to 1e-10 with the result of
``bundle_adjustment``, whose statistics come from the Schur structure only. The sparse
solver of the reduced system (forced by ``DENSE_LIMIT = 0``) must give the same numbers.
The self-calibration case estimates x0, y0 and A1 but not c: over 30 m of relief from 500 m,
c and Z0 are correlated so closely that any two float64 inverses of N (this dense one
included) agree only to about 1e-9.
"""

from __future__ import annotations

import numpy as np
import pytest

from photolib import bundle as bd
from photolib.bundle import _blocks, _selinv
from photolib.bundle._adjustment import _prepare, linearise
from photolib.bundle._blocks import make_layout
from photolib.errors import PointBehindCameraError
from tests.test_bundle import C, _block, _corners, _start

TOL = 1e-10


def _dense(res, xy, ji, pi, ext0, P0, control=None, control_sigma=None, sigma_image=None,
           calibrate=(), datum="control"):
    """σ0², Q_xx over (images, interior, unknown point coordinates), Q_vv diagonals, from the
    full dense design matrix at the result (the Jacobian blocks of ``linearise``)."""
    prob = _prepare(xy, ji, pi, ext0, P0, C, 0.0, 0.0, None, control, datum, control_sigma,
                    sigma_image, calibrate, 1e-10, 30)
    lay = make_layout(prob.j, prob.i, len(prob.ext), prob.pts, prob.sig, prob.weighted,
                      prob.calib, prob.datum, prob.sigma_image)
    interior = dict(prob.interior) | res.interior()
    v, A, Ap = linearise(prob, lay, res.exterior, res.points, interior)
    M, P, k, n = len(res.exterior), len(res.points), len(prob.calib), len(xy)
    unknown = np.argwhere(prob.sig != 0)  # (point, coordinate) with an unknown
    unknown = unknown[np.isin(unknown[:, 0], lay.free)]
    col = {(int(p), int(e)): 6 * M + k + q for q, (p, e) in enumerate(unknown)}
    u = 6 * M + k + len(unknown)
    weighted = np.argwhere(prob.weighted & np.isin(np.arange(P), lay.free)[:, None])
    Afull = np.zeros((2 * n + len(weighted), u))
    for o in range(n):
        Afull[2 * o:2 * o + 2, 6 * ji[o]:6 * ji[o] + 6] = A[o, :, :6]
        Afull[2 * o:2 * o + 2, 6 * M:6 * M + k] = A[o, :, 6:]
        for e in range(3):
            if (pi[o], e) in col:
                Afull[2 * o:2 * o + 2, col[(pi[o], e)]] = Ap[o, :, e]
    p_c = (prob.sigma_image / prob.sig[weighted[:, 0], weighted[:, 1]]) ** 2 \
        if len(weighted) else np.zeros(0)
    v_c = res.points[weighted[:, 0], weighted[:, 1]] - P0[weighted[:, 0], weighted[:, 1]]
    for q, (p, e) in enumerate(weighted):
        Afull[2 * n + q, col[(int(p), int(e))]] = 1.0
    Pw = np.r_[np.ones(2 * n), p_c]
    N = Afull.T @ (Pw[:, None] * Afull)
    d = 0
    if datum == "free":
        B = bd.inner_constraints(res.points)
        G = np.zeros((u, 7))
        G[6 * M + k:] = B
        N = np.block([[N, G], [G.T, np.zeros((7, 7))]])
        d = 7
    # Jacobi-scaled before the inverse: self-calibration makes N ill-conditioned (c with Z0)
    D = 1.0 / np.sqrt(np.where(np.abs(np.diag(N)) > 0, np.abs(np.diag(N)), 1.0))
    Q = (D[:, None] * np.linalg.inv(D[:, None] * N * D[None, :]) * D[None, :])[:u, :u]
    r = len(Pw) - u + d
    s2 = (v.ravel() @ v.ravel() + p_c @ v_c**2) / r
    rn = 1.0 - np.einsum("ij,jk,ik->i", Afull, Q, Afull) * Pw
    return dict(s2=s2, Q=Q, M=M, k=k, col=col, rn=rn[:2 * n].reshape(n, 2),
                crn=(weighted, rn[2 * n:]), v=v, r=r)


def _compare(res, dense):
    s2, Q, M, k, col = dense["s2"], dense["Q"], dense["M"], dense["k"], dense["col"]
    assert res.redundancy == dense["r"]
    assert abs(res.sigma0**2 - s2) <= TOL * s2
    for a in range(M):
        ref = s2 * Q[6 * a:6 * a + 6, 6 * a:6 * a + 6]
        np.testing.assert_allclose(res.exterior_covariance[a], ref, rtol=0,
                                   atol=TOL * np.abs(ref).max())
    if k:
        ref = s2 * Q[6 * M:6 * M + k, 6 * M:6 * M + k]
        np.testing.assert_allclose(res.interior_covariance, ref, rtol=0,
                                   atol=TOL * np.abs(ref).max())
    pcov = np.zeros_like(res.point_covariance)
    for (p, e), c in col.items():
        for (p2, e2), c2 in col.items():
            if p2 == p:
                pcov[p, e, e2] = s2 * Q[c, c2]
    fixed_or_control = [p for p in range(len(pcov)) if not np.any(pcov[p])]
    pcov[fixed_or_control] = res.point_covariance[fixed_or_control]  # not adjusted: as given
    np.testing.assert_allclose(res.point_covariance, pcov, rtol=0,
                               atol=TOL * np.abs(pcov).max())
    np.testing.assert_allclose(res.redundancy_numbers, dense["rn"], rtol=0, atol=TOL)
    np.testing.assert_allclose(res.qvv, dense["rn"], rtol=0, atol=TOL)
    weighted, crn = dense["crn"]
    if len(weighted):
        np.testing.assert_allclose(res.control_redundancy_numbers[weighted[:, 0], weighted[:, 1]],
                                   crn, rtol=0, atol=TOL)
    total = res.redundancy_numbers.sum() + (res.control_redundancy_numbers.sum()
                                            if res.control_redundancy_numbers is not None else 0)
    assert abs(total - res.redundancy) < 1e-8
    sigma = 0.003
    w = bd.data_snooping(res, sigma=sigma).statistic
    w_ref = dense["v"] / (sigma * np.sqrt(dense["rn"]))
    np.testing.assert_allclose(w, w_ref, rtol=1e-9, atol=0)


def _cases():
    xy, ji, pi, ext, P = _block(strips=2, per=3, A1=2e-6)
    control = _corners(P)
    ext0, P0 = _start(ext, P, control)
    sig = np.full((len(P), 3), np.inf)
    sig[control[:2]] = 0.0
    sig[control[2:]] = 0.05
    sig[7] = (np.inf, np.inf, 0.0)   # a height control point: a partially fixed point
    sig[11] = (0.02, 0.02, np.inf)   # a plan point observed in X, Y
    return {
        "control": (xy, ji, pi, ext0, P0, dict(control=control)),
        "self-calibration, weighted and partial control": (
            xy, ji, pi, ext0, P0, dict(control_sigma=sig, sigma_image=0.003,
                                       calibrate=("x0", "y0", "A1"))),
        "free network": (xy, ji, pi, ext0, P0, dict(datum="free")),
    }


CASES = _cases()


@pytest.mark.parametrize("case", list(CASES))
@pytest.mark.parametrize("limit", [_blocks.DENSE_LIMIT, 0, "banded", "banded-solve"],
                         ids=["dense", "sparse", "banded", "banded-solve"])
def test_statistics_agree_with_the_dense_inverse_of_the_full_normal_matrix(case, limit,
                                                                           monkeypatch):
    if limit == "banded":  # the block-tridiagonal selected inverse (fixed datum) at any size
        monkeypatch.setattr(_blocks, "BANDED_LIMIT", 0)
        monkeypatch.setattr(_blocks, "MIN_GROUPS", 1)
    elif limit == "banded-solve":  # ... and its Cholesky as the solver of every iteration
        monkeypatch.setattr(_blocks, "DENSE_LIMIT", 0)
        monkeypatch.setattr(_blocks, "MIN_GROUPS", 1)
    else:
        monkeypatch.setattr(_blocks, "DENSE_LIMIT", limit)
    xy, ji, pi, ext0, P0, kw = CASES[case]
    res = bd.bundle_adjustment(xy, ji, pi, ext0, P0, C, **kw)
    assert res.converged
    _compare(res, _dense(res, xy, ji, pi, ext0, P0, **kw))


def test_sparse_and_dense_reduced_solvers_give_the_same_adjustment(monkeypatch):
    xy, ji, pi, ext0, P0, kw = CASES["self-calibration, weighted and partial control"]
    dense = bd.bundle_adjustment(xy, ji, pi, ext0, P0, C, **kw)
    monkeypatch.setattr(_blocks, "DENSE_LIMIT", 0)
    sparse = bd.bundle_adjustment(xy, ji, pi, ext0, P0, C, **kw)
    np.testing.assert_allclose(sparse.exterior, dense.exterior, rtol=0, atol=1e-9)
    np.testing.assert_allclose(sparse.points, dense.points, rtol=0, atol=1e-9)
    assert sparse.iterations == dense.iterations
    monkeypatch.setattr(_blocks, "MIN_GROUPS", 1)  # the block-tridiagonal Cholesky instead
    banded = bd.bundle_adjustment(xy, ji, pi, ext0, P0, C, **kw)
    np.testing.assert_allclose(banded.exterior, dense.exterior, rtol=0, atol=1e-9)
    np.testing.assert_allclose(banded.points, dense.points, rtol=0, atol=1e-9)
    assert banded.iterations == dense.iterations


def test_pairs_of_the_layout_cover_every_two_rays_of_a_point_once():
    xy, ji, pi, ext0, P0, kw = CASES["control"]
    prob = _prepare(xy, ji, pi, ext0, P0, C, 0.0, 0.0, None, kw["control"], "control", None,
                    None, (), 1e-10, 30)
    lay = make_layout(prob.j, prob.i, len(prob.ext), prob.pts, prob.sig, prob.weighted,
                      prob.calib, prob.datum, prob.sigma_image)
    rays = np.bincount(lay.ps, minlength=len(lay.free))
    assert len(lay.q1) == int(np.sum(rays * (rays + 1) // 2))
    assert np.all(lay.ps[lay.q1] == lay.ps[lay.q2]) and np.all(lay.q1 <= lay.q2)
    a, b = lay.jm[lay.q1], lay.jm[lay.q2]
    assert np.all(lay.pair_a[lay.pid] == a) and np.all(lay.pair_b[lay.pid] == b)
    assert np.all(lay.pair_a[lay.diag_pair] == np.arange(lay.M))
    assert np.all(lay.pair_b[lay.diag_pair] == np.arange(lay.M))


@pytest.mark.parametrize("calibrate", [(), ("c", "x0", "y0")], ids=["plain", "self-calibration"])
def test_banded_selected_inverse_equals_the_dense_inverse(calibrate):
    """The blocks of K⁻¹ by the block-tridiagonal recursion (:mod:`photolib.bundle._selinv`)
    against the dense LAPACK inverse of the same reduced system, on a block long enough for
    several camera groups (two strips of twenty images)."""
    xy, ji, pi, ext, P = _block(strips=2, per=20, A1=0.0)
    control = _corners(P)
    ext0, P0 = _start(ext, P, control)
    res = bd.bundle_adjustment(xy, ji, pi, ext0, P0, C, control=control, calibrate=calibrate)
    prob = _prepare(xy, ji, pi, ext0, P0, C, 0.0, 0.0, None, control, "control", None, None,
                    calibrate, 1e-10, 30)
    lay = make_layout(prob.j, prob.i, len(prob.ext), prob.pts, prob.sig, prob.weighted,
                      prob.calib, prob.datum, prob.sigma_image)
    interior = dict(prob.interior) | res.interior()
    v, A, Ap = linearise(prob, lay, res.exterior, res.points, interior)
    system = _blocks.ReducedSystem(lay, _blocks.normals(lay, v, A, Ap, res.points))
    groups = _selinv.camera_groups(lay.M, lay.pair_a, lay.pair_b)
    assert groups.G >= 3  # the recursion runs over more than two groups
    banded, dense = system.inverse_blocks("banded"), system.inverse_blocks("dense")
    # the same factorisation solves K_s x = b (the solver of the iterations above
    # DENSE_LIMIT): backward error at rounding level (c and Z0 make K ill-conditioned, so
    # the forward error of any two solvers is larger)
    rhs = np.random.default_rng(1).standard_normal((lay.ny, 3))
    x = system._banded(groups).solve(rhs)
    backward = np.linalg.norm(system.Ks @ x - rhs, axis=0) / (
        np.linalg.norm(system.Ks) * np.linalg.norm(x, axis=0))
    assert np.all(backward < 1e-14)
    for name in ("pairs", "cam_global", "global_global"):
        got, ref = getattr(banded, name), getattr(dense, name)
        assert got.shape == ref.shape
        if ref.size:
            np.testing.assert_allclose(got, ref, rtol=0, atol=TOL * np.abs(ref).max())
    # every image pair that shares a point lies within one group or two neighbouring ones
    gap = np.abs(groups.group[lay.pair_a] - groups.group[lay.pair_b])
    assert gap.max() <= 1


def test_banded_route_refuses_a_free_network_and_falls_back_when_not_definite(monkeypatch):
    xy, ji, pi, ext0, P0, kw = CASES["free network"]
    res = bd.bundle_adjustment(xy, ji, pi, ext0, P0, C, **kw)
    prob = _prepare(xy, ji, pi, ext0, P0, C, 0.0, 0.0, None, None, "free", None, None, (),
                    1e-10, 30)
    lay = make_layout(prob.j, prob.i, len(prob.ext), prob.pts, prob.sig, prob.weighted,
                      prob.calib, prob.datum, prob.sigma_image)
    v, A, Ap = linearise(prob, lay, res.exterior, res.points, dict(prob.interior))
    system = _blocks.ReducedSystem(lay, _blocks.normals(lay, v, A, Ap, res.points))
    with pytest.raises(ValueError, match="needs a fixed datum"):
        system.inverse_blocks("banded")
    # the automatic choice takes the dense route for a free network at any size
    monkeypatch.setattr(_blocks, "BANDED_LIMIT", 0)
    monkeypatch.setattr(_blocks, "MIN_GROUPS", 1)
    auto, dense = system.inverse_blocks(), system.inverse_blocks("dense")
    np.testing.assert_array_equal(auto.pairs, dense.pairs)


@pytest.mark.parametrize("calibrate", [(), ("c", "x0", "y0", "A1")], ids=["plain", "self-calibration"])
def test_linearisation_in_chunks_equals_one_pass_and_names_the_point_behind(calibrate,
                                                                            monkeypatch):
    """``linearise`` runs the generated code on LIN_CHUNK observations at a time: with chunks
    of 7 (boundaries inside images and points) the residuals and Jacobian blocks are those of
    one pass over all observations, and a point behind a camera in a later chunk is named
    with its own indices."""
    from photolib.bundle import _adjustment as ad

    xy, ji, pi, ext, P = _block()
    control = _corners(P)
    ext0, P0 = _start(ext, P, control)
    prob = _prepare(xy, ji, pi, ext0, P0, C, 0.0, 0.0, None, control, "control", None, None,
                    calibrate, 1e-10, 30)
    lay = make_layout(prob.j, prob.i, len(prob.ext), prob.pts, prob.sig, prob.weighted,
                      prob.calib, prob.datum, prob.sigma_image)
    interior = dict(prob.interior) | {"A1": 1e-6}
    monkeypatch.setattr(ad, "LIN_CHUNK", len(xy) + 1)
    whole = linearise(prob, lay, prob.ext, prob.pts, interior)
    monkeypatch.setattr(ad, "LIN_CHUNK", 7)
    chunked = linearise(prob, lay, prob.ext, prob.pts, interior)
    for a, b in zip(whole, chunked):
        np.testing.assert_array_equal(a, b)
    first = np.full(len(P0), len(xy))
    np.minimum.at(first, pi, np.arange(len(xy)))
    p = int(np.argmax(np.where(np.isin(np.arange(len(P0)), control), -1, first)))
    q = int(first[p])
    assert q > 7  # its first observation lies beyond the first chunk
    pts = prob.pts.copy()
    pts[p, 2] = ext0[:, 2].max() + 50.0  # above every (nadir) camera: behind all of them
    with pytest.raises(PointBehindCameraError,
                       match=rf"object point {p} is not in front of image {ji[q]}: N = "):
        linearise(prob, lay, prob.ext, pts, interior)
