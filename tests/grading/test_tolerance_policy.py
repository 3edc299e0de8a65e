"""The tolerance policy of docs/instructors.md, enforced on every numeric exercise part.

For each exercise of kind number, array, rotation and function and each of
:data:`VARIANTS` student ids, :mod:`tolerance_audit` builds the answers a careful student may
give (float32 work; the reference recomputed from each printed input moved by half a unit of
its last printed digit) and the grader must accept every one. A failure names the exercise,
the variant, which input was moved and the answer.

Each failure this scan found before (col.project answered to 0.1 µm and rejected float32
work; 39 exercises in all) was fixed at its cause: those exercises take
``tolerance=PRINTED``, which derives the tolerance from the statement as printed.
"""

from __future__ import annotations

import pytest

from photolib.grading.exercises import exercise

from .tolerance_audit import audit, half_unit, numeric_exercises, printed_inputs

VARIANTS = tuple(f"tol{i:04d}" for i in range(24))

#: exercises where the printed rounding of some variant reaches a declared mistake, so that
#: PRINTED cuts the tolerance to keep the hint and the moved-input answer is rejected (or,
#: for functions, a per-input tolerance cut the same way): they need their inputs printed to
#: more digits (a fixed format such as {c_mm:.2f}: repr drops trailing zeros, "99.5" reads
#: as good to 0.05 only) or variants drawn away from the mistake. Strict, so a fix shows up
#: as an unexpected pass; the 14 of issue 13 are all fixed that way, none is left
KNOWN_CONFLICTS: set = set()


def _marked(ex):
    if ex.id in KNOWN_CONFLICTS:
        return pytest.param(ex, marks=pytest.mark.xfail(
            strict=True, reason="printed rounding reaches a mistake; more digits needed"))
    return ex


def _ids(ex):
    return ex.id


@pytest.mark.slow
@pytest.mark.parametrize("ex", [_marked(ex) for ex in numeric_exercises()], ids=_ids)
def test_float32_work_and_the_printed_inputs_rounding_are_accepted(ex):
    failures = audit(ex, VARIANTS)
    assert not failures, f"{len(failures)} answers rejected, e.g.\n" + "\n".join(failures[:8])


def test_the_scan_reads_the_printed_digits():
    assert half_unit("12.30") == pytest.approx(0.005)
    assert half_unit("-1.744e-06") == pytest.approx(5e-10)
    assert half_unit("45") == 0.5
    # col.project prints X0 with repr (a trailing zero dropped) and the ground point to 1 mm
    ex = exercise("col.project")
    from photolib.grading.notebook import parameters_for
    p = parameters_for(ex, "s1")
    found = {name: half for name, _, half, _ in printed_inputs(ex, p)}
    assert set(found) == {"c_mm", "X0", "Y0", "Z0", "omega_deg", "phi_deg", "kappa_deg",
                          "X", "Y", "Z"}
    assert found["X"] == pytest.approx(0.0005)
    # a matrix printed as text: every entry found, to its nine printed decimals
    ex = exercise("rot.angles-from-matrix")
    entries = printed_inputs(ex, parameters_for(ex, "s1"))
    assert len(entries) == 9 and all(h == pytest.approx(5e-10) for _, _, h, _ in entries)


def test_the_scan_catches_a_tolerance_tighter_than_the_print():
    # the scan can fail: col.project with its old fixed tolerance (rtol 0, atol 1e-6 mm)
    import dataclasses
    old = dataclasses.replace(exercise("col.project"), tolerance=None, rtol=0.0, atol=1e-6)
    failures = audit(old, VARIANTS[:2])
    assert any("float32" in f for f in failures)
    assert any("X0 = " in f for f in failures)
    assert all(f.startswith("col.project, variant tol000") for f in failures)
