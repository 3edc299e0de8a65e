"""Every verdict of the errata catalogue, re-evaluated from its evidence."""

import math
from pathlib import Path

import numpy as np
import pytest
import sympy as sp

from photolib import errata
from photolib.errata import luhmann_dlt
from photolib.errata._record import CLAIMS, VersionSpec, figure

CAT = errata.catalogue()
PAIRS = [(r.id, name) for r in CAT for name in r.specs]
DOCS = Path(__file__).resolve().parents[2] / "docs" / "errata.md"


def test_catalogue_size_and_ids():
    ids = [r.id for r in CAT]
    assert len(ids) > 40 and len(set(ids)) == len(ids)
    for prefix in ("luhmann:", "de-summary:", "hu-wiki:", "pl-notes:"):
        assert any(i.startswith(prefix) for i in ids), prefix
    for need in ("luhmann:2.19", "luhmann:2.20", "luhmann:2.21", "luhmann:2.86", "luhmann:2.88",
                 "luhmann:2.136", "luhmann:p90-t-distribution", "luhmann:example-3.7",
                 "luhmann:table-3.3", "luhmann:4.13", "luhmann:example-4.1-x0",
                 "luhmann:example-4.5-x0", "luhmann:4.18b", "luhmann:4.26",
                 "luhmann:example-4.3", "luhmann:4.76", "luhmann:example-4.8",
                 "luhmann:table-4.1", "luhmann:5.42", "luhmann:5.50-p1", "luhmann:5.72",
                 "luhmann:5.73", "de-summary:tangential-distortion", "hu-wiki:rotation-matrix",
                 "pl-notes:bilinear", "pl-notes:helmert", "pl-notes:bundle-unknowns"):
        assert errata.get(need).id == need
    with pytest.raises(KeyError, match="no errata record"):
        errata.get("luhmann:9.99")


@pytest.mark.parametrize("rid, name", PAIRS)
def test_verdict_recomputed_equals_stated(rid, name):
    rec = errata.get(rid)
    ev = rec.evaluate(name)
    assert ev.verdict == rec.specs[name].verdict
    spec = rec.specs[name]
    expr = spec.expr() if callable(spec.expr) else spec.expr
    # re-evaluate counterexamples of formula comparisons at 50 digits
    if ev.counterexample and spec.check is None and expr is not None:
        given = rec.given_substitution()
        printed = sp.Matrix([expr]) if not isinstance(expr, sp.MatrixBase) else expr
        printed = printed.subs(given) if given else printed
        derived = rec.derived() if spec.target is None else (
            spec.target() if callable(spec.target) else spec.target)
        derived = sp.Matrix([derived]) if not isinstance(derived, sp.MatrixBase) else derived
        pa = [sp.N(e.subs(ev.counterexample), 40) for e in printed]
        pb = [sp.N(e.subs(ev.counterexample), 40) for e in derived]
        assert any(abs(complex(a) - complex(b)) > 1e-12 for a, b in zip(pa, pb))
        if ev.verdict.startswith("right-under-condition"):
            cond = spec.condition() if callable(spec.condition) else spec.condition
            ca = [sp.N(e.subs(cond).subs(ev.counterexample), 40) for e in printed]
            cb = [sp.N(e.subs(cond).subs(ev.counterexample), 40) for e in derived]
            assert all(abs(complex(a) - complex(b)) < 1e-20 for a, b in zip(ca, cb))
    for row in ev.table:
        name_, printed_, recomputed, tol, agrees = row
        if tol is not None and printed_ is not None:
            assert agrees == (abs(printed_ - recomputed) <= tol), row
    if ev.verdict == "wrong":
        assert ev.counterexample or any(not r[4] for r in ev.table) or ev.detail


def test_versions_are_sympy():
    for r in CAT:
        for name, e in r.versions.items():
            assert name in ("printed", "old", "corrected")
            assert isinstance(e, (sp.Basic, sp.MatrixBase)), (r.id, name)


# ---- independent numeric cross-checks (NumPy/SciPy, not SymPy) ----------------------------


def test_219_inverse_roundtrip_numpy():
    rng = np.random.default_rng(1)
    a0, a1, a2, b0, b1, b2, c1, c2 = rng.uniform(-1, 1, 8) + np.array([0, 2, 0, 0, 0, 2, 0, 0])
    xi, yi = 0.3, -0.4
    den = 1 + c1 * xi + c2 * yi
    X, Y = (a0 + a1 * xi + a2 * yi) / den, (b0 + b1 * xi + b2 * yi) / den
    rec = errata.get("luhmann:2.19")
    syms = {str(s): s for s in rec.versions["corrected"].free_symbols}
    vals = dict(a0=a0, a1=a1, a2=a2, b0=b0, b1=b1, b2=b2, c1=c1, c2=c2, X=X, Y=Y)
    got = [float(e.subs({syms[k]: v for k, v in vals.items() if k in syms}))
           for e in rec.versions["corrected"]]
    assert np.allclose(got, [xi, yi], atol=1e-12)


def test_542_log_by_finite_differences():
    s, r = 1.3, 0.7
    def G(x, y):
        return math.exp(-(x * x + y * y) / (2 * s * s)) / (2 * math.pi * s * s)
    h = 1e-3
    lap = (G(r + h, 0) + G(r - h, 0) + G(r, h) + G(r, -h) - 4 * G(r, 0)) / h**2
    rec = errata.get("luhmann:5.42")
    sym = {str(v): v for v in rec.versions["corrected"].free_symbols}
    val = float(rec.versions["corrected"].subs({sym["r"]: r, sym["sigma"]: s}))
    old = float(rec.versions["old"].subs({sym["r"]: r, sym["sigma"]: s}))
    assert val == pytest.approx(lap, rel=1e-5)
    assert old != pytest.approx(lap, rel=1e-2)


def test_550_p1_moments_preserved_numerically():
    rng = np.random.default_rng(3)
    g = np.concatenate([rng.normal(50, 5, 700), rng.normal(150, 10, 300)])
    m1, m2, m3 = (np.mean(g**k) for k in (1, 2, 3))
    s2 = m2 - m1**2
    sk = (m3 + 2 * m1**3 - 3 * m1 * m2) / s2**1.5
    for p1, good in ((0.5 * (1 + sk / math.sqrt(4 + sk * sk)), True),
                     (0.5 * (1 + sk * math.sqrt(4 + sk * sk)), False)):
        p2 = 1 - p1
        if not 0 < p1 < 1:
            assert not good
            continue
        h1, h2 = m1 - math.sqrt(s2 * p2 / p1), m1 + math.sqrt(s2 * p1 / p2)
        m3_two = p1 * h1**3 + p2 * h2**3
        assert (abs(m3_two - m3) < 1e-6 * abs(m3)) == good


def test_t_distribution_against_scipy():
    from scipy import stats

    from photolib.derive.adjustment import t_tail
    for k, nu in ((2, 5), (1, 3), (3, 30)):
        assert float(t_tail(k, nu)) == pytest.approx(2 * stats.t.sf(k, nu), rel=1e-10)
    assert 2 * stats.t.sf(2, 5) > 2 * stats.t.sf(2, 30) > 2 * stats.norm.sf(2)


def test_example_43_principal_point_sign_numpy():
    L = np.array(luhmann_dlt.L_PRINTED)
    Lsq = 1 / (L[8] ** 2 + L[9] ** 2 + L[10] ** 2)
    x0 = (L[0] * L[8] + L[1] * L[9] + L[2] * L[10]) * Lsq
    y0 = (L[4] * L[8] + L[5] * L[9] + L[6] * L[10]) * Lsq
    assert x0 > 3.7 and y0 < -3.9          # printed: x'0 = −3.7708, y'0 = +3.8404
    A = L[[0, 1, 2, 4, 5, 6, 8, 9, 10]].reshape(3, 3)
    X0 = np.linalg.solve(A, -np.array([L[3], L[7], 1]))
    assert np.allclose(X0, [-471.12, 318.14, 1604.96], atol=2.0)


def test_hu_matrix_not_orthogonal_but_fixable():
    from photolib.derive.rotation import kappa, omega, phi, wolf_m
    from photolib.errata.hu_wiki import printed_matrix
    vals = {omega: 0.5, phi: 0.2, kappa: -0.3}
    M = np.array(printed_matrix().subs(vals).evalf(), dtype=float)
    assert not np.allclose(M.T @ M, np.eye(3), atol=1e-3)
    fixed = M.copy()
    fixed[0, 0] = math.cos(0.2) * math.cos(-0.3)
    assert np.allclose(fixed, np.array(wolf_m().subs(vals).evalf(), dtype=float), atol=1e-12)


def test_depth_of_field_thin_lens_simulation():
    f, k, up, a = 0.05, 4.0, 2e-5, 3.0          # m
    img = lambda d: d * f / (d - f)
    blur = lambda d: (f / k) * abs(img(d) - img(a)) / img(d)
    from scipy.optimize import brentq
    av = brentq(lambda d: blur(d) - up, f * 1.01, a)
    ah = brentq(lambda d: blur(d) - up, a, 1e4)
    mb = (a - f) / f
    t_true = ah - av
    t_printed = 2 * up * k * (1 + mb) / (mb**2 - (up * k / f) ** 2)
    beta = 1 / mb
    t_beta = 2 * up * k * (1 + beta) / (beta**2 - (up * k / f) ** 2)
    assert t_beta == pytest.approx(t_true, rel=1e-6)
    assert abs(t_printed - t_true) > 0.5 * t_true
    u_printed = (ah - av) / (ah + av) * f**2 / (k * (a - f))
    assert u_printed == pytest.approx(up, rel=1e-6)


def test_bilinear_printed_has_seven_parameters():
    ev = errata.get("pl-notes:bilinear").evaluate("printed")
    assert ev.verdict == "wrong" and "7 independent" in ev.detail


def test_example_48_same_parallaxes():
    b = 1.2
    px_old = [64.0 * b / z for z in (3.88, 58.49)]
    px_new = [-60.2 * b / z for z in (-3.65, -55.02)]
    assert np.allclose(px_old, px_new, rtol=2e-3)


def test_differs_from_source_listed():
    diffs = {r.id: r.differs_from_source() for r in CAT if r.differs_from_source()}
    assert "luhmann:5.50-p1" in diffs and "luhmann:example-4.3" in diffs
    assert "luhmann:2.21" in diffs


# ---- claims of the sources and the table of docs/errata.md ---------------------------------


def test_every_version_has_a_claim():
    for r in CAT:
        for name, spec in r.specs.items():
            assert spec.claim in CLAIMS, (r.id, name, spec.claim)
            if r.id.startswith(("de-summary:", "hu-wiki:", "pl-notes:")):
                assert spec.claim == "right", (r.id, name)      # they claim what they print
            elif name == "old":
                assert spec.claim == "wrong", (r.id, name)      # "alte Fassung"
            elif name == "corrected":
                assert spec.claim == "right", (r.id, name)      # "richtig"


def test_missing_claim_is_an_error_at_construction():
    with pytest.raises(ValueError, match="claim"):
        VersionSpec("right")
    with pytest.raises(ValueError, match="claim"):
        VersionSpec("wrong", claim="richtig")
    with pytest.raises(TypeError):
        figure("x:fig", "src", "item", "figure only")          # the claim is keyword-only
    assert VersionSpec("wrong", claim="right").claim == "right"


def _docs_table():
    """``{(record id, version): (claim, verdict, reason)}`` from docs/errata.md."""
    rows = {}
    for line in DOCS.read_text(encoding="utf-8").splitlines():
        if not line.startswith("| `"):
            continue
        cells = [c.strip() for c in line.strip().strip("|").split(" | ")]
        assert len(cells) == 5, line
        rid, version, claim, verdict, reason = cells
        key = (rid.strip("`"), version)
        assert key not in rows, f"row listed twice: {key}"
        rows[key] = (claim, verdict, reason)
    return rows


def test_docs_table_is_exactly_differs_from_source():
    """The table of docs/errata.md lists every (record, version) whose verdict differs from the
    source's claim, and nothing else, with the claim and the full verdict string (the stated
    verdict, which ``test_verdict_recomputed_equals_stated`` ties to what the CLI prints)."""
    table = _docs_table()
    expected = {(r.id, name): cv for r in CAT for name, cv in r.differs_from_source().items()}
    assert sorted(set(expected) - set(table)) == [], "missing from docs/errata.md"
    assert sorted(set(table) - set(expected)) == [], "in docs/errata.md but not differing"
    for key, (claim, verdict) in expected.items():
        assert table[key][:2] == (claim, verdict), key
        assert table[key][2], f"no reason for {key}"
    # same order as the catalogue, so the page reads source by source
    assert list(table) == list(expected)
