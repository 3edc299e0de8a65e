"""How many plausible wrong answers get a specific hint: the answer-audit harness of issue 14.

For every exercise of every chapter and a few students, :func:`wrong_answers` builds the
wrong answers a student plausibly gives (one *family* each: a unit prefix off by 10^±3 or
10^±6, the sign flipped, a matrix transposed, degrees for radians and back, the result
rounded to 2 significant digits, a direction vector not normalised, the inverse, a factor
2 or 1/2); :func:`coverage` judges each as the grader does
(:func:`tests.grading.chapter_checks.judge_as_grader`) and counts those judged wrong that
name a specific mistake (a tag other than ``None`` and ``"other"``). A family whose answer the
grader accepts (rounding to 2 digits where the tolerance allows it) is not a wrong answer and
is left out of the count.

Run ``python -m tests.grading.hint_coverage`` from the repository root for the figure and the
share per family.
"""

from __future__ import annotations

import math

import numpy as np

from photolib.grading.notebook import parameters_for

from .chapter_checks import judge_as_grader

#: the families of plausible wrong answers, in the order they are reported
FAMILIES = ("x1000", "x0.001", "x1e6", "x1e-6", "sign", "transposed", "degrees",
            "radians", "2-digits", "unnormalised", "inverse", "x2", "x0.5")

STUDENTS = ("cov0001", "cov0002", "cov0003")

#: what does not count as a specific hint
UNSPECIFIC = (None, "other")


def _round_sig(values, digits=2):
    values = np.asarray(values, float)
    out = np.zeros_like(values)
    nonzero = values != 0
    exponent = np.floor(np.log10(np.abs(values[nonzero])))
    scale = 10.0 ** (exponent - digits + 1)
    out[nonzero] = np.round(values[nonzero] / scale) * scale
    return out


def _transform(family, value):
    """The family's wrong version of a numeric answer (ndarray), or None if it does not apply."""
    v = np.asarray(value, float)
    factors = {"x1000": 1e3, "x0.001": 1e-3, "x1e6": 1e6, "x1e-6": 1e-6, "sign": -1.0,
               "degrees": 180 / math.pi, "radians": math.pi / 180, "x2": 2.0, "x0.5": 0.5}
    if family in factors:
        return v * factors[family]
    if family == "transposed":
        return v.T if v.ndim == 2 and v.shape[0] == v.shape[1] else None
    if family == "2-digits":
        return _round_sig(v, 2)
    if family == "unnormalised":
        norm = np.linalg.norm(v)
        return v * 3.7 if v.ndim == 1 and v.size > 1 and abs(norm - 1) < 1e-6 else None
    if family == "inverse":
        if v.ndim == 0:
            return 1 / v if v != 0 else None
        if v.ndim == 2 and v.shape[0] == v.shape[1] and abs(np.linalg.det(v)) > 1e-12:
            return np.linalg.inv(v)
        return None
    raise ValueError(f"unknown family {family!r}")


def wrong_answers(ex, params):
    """``(family, answer)`` for every family that applies to this variant of ``ex``."""
    out = []
    if ex.kind in ("number", "array", "rotation"):
        ref = ex.reference(params)
        for family in FAMILIES:
            wrong = _transform(family, ref)
            if wrong is not None:
                out.append((family, float(wrong) if ex.kind == "number" else wrong))
    elif ex.kind == "function":
        f = ex.reference(params)
        for family in FAMILIES:
            def g(*args, f=f, family=family):
                wrong = _transform(family, f(*args))
                if wrong is None:
                    raise NotImplementedError(family)
                return wrong
            out.append((family, g))
    elif ex.kind == "expression":
        ref = ex.reference(params)
        out.append(("sign", -ref))
        out.append(("x2", 2 * ref))
        if getattr(ref, "is_Matrix", False):
            out.append(("transposed", ref.T))
    return out


def coverage(exercises, students=STUDENTS):
    """``(hinted, wrong, per_family)``: answers judged wrong, how many with a specific hint,
    and per family ``[hinted, wrong]``."""
    hinted = wrong = 0
    per_family: dict = {}
    for ex in exercises:
        for sid in students:
            params = parameters_for(ex, sid)
            for family, answer in wrong_answers(ex, params):
                try:
                    verdict = judge_as_grader(ex, sid, answer)
                except Exception:  # noqa: BLE001 - a family that does not apply here
                    continue
                if verdict.status != "wrong":
                    continue
                if verdict.mistake == "raised" and ex.kind == "function":
                    continue            # the family does not apply to this output (raised)
                counts = per_family.setdefault(family, [0, 0])
                counts[1] += 1
                wrong += 1
                if verdict.mistake not in UNSPECIFIC:
                    counts[0] += 1
                    hinted += 1
    return hinted, wrong, per_family


def all_exercises():
    from photolib.grading.exercises import chapters
    return [ex for exs in chapters().values() for ex in exs]


def main():
    hinted, wrong, per_family = coverage(all_exercises())
    print(f"specific hints: {hinted} of {wrong} wrong answers = {hinted / wrong:.1%}")
    for family in FAMILIES:
        if family in per_family:
            h, w = per_family[family]
            print(f"  {family:13s} {h:4d} / {w:4d} = {h / w:6.1%}")
    return hinted, wrong


if __name__ == "__main__":
    main()
