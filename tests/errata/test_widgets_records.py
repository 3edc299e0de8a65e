"""The errata widget over every record, and the records 5.73 (LSM gradients) and 2.21 (cross
ratio) as the widget shows them."""

import math

import pytest
import sympy as sp

from photolib import errata
from photolib.derive import image_processing as ip
from photolib.errata import evaluate as widgets
from photolib.nb import errata as nb_errata
from photolib.errata.cli import describe

CAT = errata.catalogue()
IDS = [r.id for r in CAT]


def _defaults(rec):
    return {s.name: round(0.3 + 0.1 * i, 2) for i, s in enumerate(widgets._free_symbols(rec))}


@pytest.mark.parametrize("rid", IDS)
def test_every_record_evaluates_or_says_why(rid):
    """Each record either evaluates (every version and the derivation, finite numbers) or
    raises the ValueError naming the record and the reason; the widget builds either way."""
    rec = errata.get(rid)
    reason = widgets.not_evaluable_reason(rec)
    box = nb_errata.build_widget(rid)
    texts = [c.value for c in box.children if not hasattr(c, "continuous_update")]
    sliders = [c for c in box.children if hasattr(c, "continuous_update")]
    assert texts[0].startswith(f"<b>{rid}</b>")
    if reason is not None:
        with pytest.raises(ValueError, match=rf"^{rid} cannot be evaluated at numbers: "):
            widgets.evaluate_versions(rid, {})
        assert not sliders and "cannot be evaluated at numbers" in texts[-1]
        assert reason in texts[-1] and f"--id {rid}" in texts[-1]
        return
    try:
        vals = widgets.evaluate_versions(rid, _defaults(rec))
    except (ArithmeticError, TypeError, ValueError) as exc:     # a pole at the slider defaults
        assert f"cannot evaluate here: {exc}" == texts[-1]
        return
    assert set(rec.versions) | {"derived"} <= set(vals)
    for v in vals.values():
        assert all(math.isfinite(x) for x in (v if isinstance(v, list) else [v]))
    assert "<b>derived</b>" in texts[-1]
    assert len(sliders) == len(widgets._free_symbols(rec))


@pytest.mark.parametrize("rid", ["luhmann:4.76", "de-summary:refraction-snell",
                                 "de-summary:reflection", "de-summary:aperture-angle"])
def test_reported_records_give_the_clear_message(rid):
    with pytest.raises(ValueError, match=rf"{rid} cannot be evaluated at numbers: no derivation"):
        widgets.evaluate_versions(rid, {})
    box = nb_errata.build_widget(rid)
    assert "cannot be evaluated at numbers: no derivation" in box.children[-1].value


def test_missing_value_still_named():
    with pytest.raises(ValueError, match=r"luhmann:5.73: no value for \['g_yp'\]"):
        widgets.evaluate_versions("luhmann:5.73", {"a1": 1, "a2": 0, "b1": 0, "b2": 1,
                                                   "g_xp": 1})


def test_own_target_shown():
    rec = errata.get("luhmann:2.19")
    vals = widgets.evaluate_versions("luhmann:2.19", _defaults(rec))
    assert "target (old)" in vals
    assert vals["corrected"] == pytest.approx(vals["derived"], rel=1e-12)
    assert "target" in nb_errata.build_widget("luhmann:2.19").children[1].value


# ---- luhmann:5.73 ------------------------------------------------------------------------

G_XP, G_YP = sp.symbols("g_xp g_yp", real=True)
G_X, G_Y = sp.symbols("g_x g_y", real=True)
A1, A2 = sp.symbols("a1 a2", real=True)
B1, B2 = sp.symbols("b1 b2", real=True)


def _image(u, v):
    """A smooth search image g(x', y') for finite differences."""
    return math.sin(1.3 * u) * math.cos(0.7 * v) + 0.2 * u * v * v


def _image_grad(u, v):
    return (1.3 * math.cos(1.3 * u) * math.cos(0.7 * v) + 0.2 * v * v,
            -0.7 * math.sin(1.3 * u) * math.sin(0.7 * v) + 0.4 * u * v)


def test_573_versions_are_distinct_symbols_as_printed():
    rec = errata.get("luhmann:5.73")
    old, new = rec.versions["old"], rec.versions["corrected"]
    assert old == sp.Matrix([G_X, G_Y])                   # g_x = ∂g⁰(x, y)/∂x  (alte Fassung)
    assert new == sp.Matrix([G_XP, G_YP])                 # g_x' = ∂g(x', y')/∂x'  (richtig)
    assert old != new and not (old.free_symbols & new.free_symbols)
    assert rec.derived() == sp.Matrix([G_XP, G_YP])


def test_573_derivation_is_the_572_linearisation():
    lin = ip.lsm_linearised()
    da0, db0 = sp.symbols("da0 db0", real=True)
    r1 = sp.Symbol("r1", real=True)
    rec = errata.get("luhmann:5.73")
    grad = sp.Matrix([lin.coeff(da0) / r1, lin.coeff(db0) / r1]).xreplace({G_X: G_XP,
                                                                          G_Y: G_YP})
    assert sp.simplify(grad - rec.derived()) == sp.zeros(2, 1)
    # independent: ∂/∂da0 of r0 + r1·g(x' + da0, y') by central differences is r1·∂g/∂x'
    r0v, r1v, xp, yp, h = 0.2, 1.3, 0.4, -0.9, 1e-6
    fd = [(r0v + r1v * _image(xp + h * e0, yp + h * e1)
           - (r0v + r1v * _image(xp - h * e0, yp - h * e1))) / (2 * h)
          for e0, e1 in ((1, 0), (0, 1))]
    gx, gy = _image_grad(xp, yp)
    at = {G_XP: gx, G_YP: gy}
    assert [r1v * float(e.subs(at)) for e in rec.derived()] == pytest.approx(fd, rel=1e-8)


def test_573_old_meaning_is_the_template_gradient_by_finite_differences():
    """Old g_x = ∂g⁰(x, y)/∂x with g⁰(x, y) = g(x'(x, y), y'(x, y)): re-evaluated numerically."""
    rec = errata.get("luhmann:5.73")
    a0, a1, a2, b0, b1, b2 = 0.1, 1.2, -0.3, -0.2, 0.25, 0.9
    x, y, h = 0.3, 0.5, 1e-6

    def g0(x, y):
        return _image(a0 + a1 * x + a2 * y, b0 + b1 * x + b2 * y)

    fd = [(g0(x + h, y) - g0(x - h, y)) / (2 * h), (g0(x, y + h) - g0(x, y - h)) / (2 * h)]
    gx, gy = _image_grad(a0 + a1 * x + a2 * y, b0 + b1 * x + b2 * y)
    at = {A1: a1, A2: a2, B1: b1, B2: b2, G_XP: gx, G_YP: gy}
    old = rec.versions["old"].subs(rec.given_substitution())
    assert [float(e.subs(at)) for e in old] == pytest.approx(fd, rel=1e-8)
    # ... and that is not the gradient 5.72 needs (∂g/∂x', ∂g/∂y') for this sheared patch
    assert [float(e.subs(at)) for e in rec.derived()] != pytest.approx(fd, rel=1e-3)


def test_573_verdicts_and_their_evidence():
    rec = errata.get("luhmann:5.73")
    old, new = rec.evaluate("old"), rec.evaluate("corrected")
    assert old.verdict.startswith("right-under-condition: a1 = b2 = 1, a2 = b1 = 0")
    assert new.verdict == "right"
    given = rec.given_substitution()
    printed = rec.versions["old"].subs(given)
    # the counterexample re-evaluated: the old gradient differs from the derivation there ...
    ce = old.counterexample
    assert set(map(str, ce)) == {"a1", "a2", "b1", "b2", "g_xp", "g_yp"}
    diff = (printed - rec.derived()).subs(ce)
    assert max(abs(sp.N(d, 40)) for d in diff) > 1e-6
    # ... and is equal under the condition (pure shift), identically
    cond = rec.specs["old"].condition
    assert sp.simplify(printed.subs(cond) - rec.derived()) == sp.zeros(2, 1)
    # corrected: identical to the derivation
    assert sp.simplify(rec.versions["corrected"] - rec.derived()) == sp.zeros(2, 1)
    text = describe(rec)
    assert "derivation: Matrix([[g_xp], [g_yp]])" in text
    assert "printed (old): Matrix([[g_x], [g_y]])" in text
    assert "printed (corrected): Matrix([[g_xp], [g_yp]])" in text


def test_573_widget_consistent_with_verdicts():
    rec = errata.get("luhmann:5.73")
    vals = widgets.evaluate_versions("luhmann:5.73", _defaults(rec))
    assert vals["corrected"] == pytest.approx([0.7, 0.8])
    assert vals["derived"] == pytest.approx([0.7, 0.8])
    assert vals["old"] == pytest.approx([0.3 * 0.7 + 0.5 * 0.8, 0.4 * 0.7 + 0.6 * 0.8])
    shift = widgets.evaluate_versions("luhmann:5.73", {"a1": 1, "b2": 1, "a2": 0, "b1": 0,
                                                       "g_xp": 0.7, "g_yp": -0.2})
    assert shift["old"] == pytest.approx(shift["derived"])
    assert shift["corrected"] == pytest.approx(shift["derived"])


# ---- luhmann:2.21 ------------------------------------------------------------------------


def test_221_widget_compares_residuals_with_the_derivation():
    from photolib.transforms import cross_ratio
    rec = errata.get("luhmann:2.21")
    assert rec.derived() == 0
    pts = {"t_A": 0.3, "t_B": 0.4, "t_C": 0.5, "t_D": 0.6}
    vals = widgets.evaluate_versions("luhmann:2.21", pts)
    assert vals["derived"] == 0.0
    assert vals["old"] == pytest.approx(0.0, abs=1e-12)
    assert vals["corrected"] == pytest.approx(0.0, abs=1e-12)
    assert vals["λ as printed (old)"] == pytest.approx(0.75)
    assert vals["λ as printed (corrected)"] == pytest.approx(1 / 3)
    assert vals["λ course"] == pytest.approx(cross_ratio(0.3, 0.4, 0.5, 0.6)) \
        == pytest.approx(vals["λ as printed (corrected)"])
    for p in ({"t_A": -1.0, "t_B": 0.2, "t_C": 1.7, "t_D": 1.9},):
        v = widgets.evaluate_versions("luhmann:2.21", p)
        assert abs(v["old"]) < 1e-12 and abs(v["corrected"]) < 1e-12


def test_221_projectivity_is_not_affine_so_the_residual_tests_something():
    """A non-invariant ratio (AB/BC, affine-invariant only) has a non-zero residual under the
    widget's map: the zero residuals of 2.21 are evidence, not an artefact of the map."""
    tA, tB, tC, tD = sp.symbols("t_A t_B t_C t_D", real=True)
    simple = (tB - tA) / (tC - tB)
    res = (widgets._projected(simple) - simple).subs({tA: 0.3, tB: 0.4, tC: 0.5, tD: 0.6})
    assert abs(float(res)) > 1e-3
    p, q, r, s = (widgets.PROJECTIVITY[k] for k in sp.symbols("p q r s_", real=True))
    assert r != 0 and p * s - q * r != 0


def test_221_widget_text_explains_the_comparison():
    box = nb_errata.build_widget("luhmann:2.21", 0.1, 3.0)
    note = box.children[1].value
    assert "residual" in note and "λ course" in note and "t ↦" in note
    out = box.children[-1].value
    assert "<b>λ as printed (old)</b>: 0.75" in out and "<b>derived</b>: 0" in out
