"""Recognisable mistakes: builders of :class:`~photolib.grading.spec.Mistake` rules.

A mistake rule recomputes the answer the way a student who made that mistake would; when the
student's answer matches it, the hint is shown. Generic rules per answer kind are always tried
(:func:`generic_mistakes`); exercises add their own with the builders below.

>>> from photolib.grading.spec import Params
>>> rule = scaled_parameter(lambda p: 2 * p["a"], "a", 1000.0, "units-mm-m", "mm and m?")
>>> rule.wrong(Params(a=1.5))
3000.0
"""

from __future__ import annotations

import importlib

import math

import numpy as np

from photolib.grading.spec import Mistake, Params

__all__ = [
    "MESSAGES",
    "degrees_for_radians",
    "erratum_version",
    "generic_mistakes",
    "gon_for_radians",
    "reversed_sense",
    "scaled_parameter",
    "scaled_result",
    "sign_of",
    "transposed",
]

#: the standard hint of each mistake tag
MESSAGES = {
    "transposed": "your matrix is the transpose of the expected one (Rᵀ instead of R, or the "
                  "sense of rotation reversed)",
    "degrees": "it looks as if an angle in degrees was used where radians are needed "
               "(convert with numpy.radians)",
    "gon": "it looks as if an angle in gon was used where radians are needed "
           "(400 gon = 2π rad: multiply by π/200)",
    "sign-c": "check the sign of the camera constant c (c > 0, the image vector has z = −c)",
    "units-mm-m": "off by a factor of 1000: are mm and m mixed up?",
    "sign": "the sign is wrong",
    "sense": "the sense of rotation of an angle is reversed",
    "erratum": "this is the formula as printed before the erratum; see the errata chapter",
    "distortion-point": "the distortion was evaluated at the wrong point (measured versus ideal)",
}


def scaled_parameter(reference, name: str, factor: float, tag: str, message: str | None = None):
    """Mistake: parameter ``name`` used ``factor`` times too large (units, sign, sense)."""
    def wrong(params):
        changed = Params(params)
        changed[name] = params[name] * factor
        return reference(changed)
    return Mistake(tag, message or MESSAGES[tag], wrong)


def degrees_for_radians(reference, name: str):
    """Mistake: the angle parameter ``name`` (radians) was given in degrees."""
    return scaled_parameter(reference, name, 180.0 / math.pi, "degrees")


def gon_for_radians(reference, name: str):
    """Mistake: the angle parameter ``name`` (radians) was given in gon."""
    return scaled_parameter(reference, name, 200.0 / math.pi, "gon")


def reversed_sense(reference, *names: str):
    """Mistake: the angles ``names`` turned the other way (φ or κ sense reversed)."""
    def wrong(params):
        changed = Params(params)
        for name in names:
            changed[name] = -params[name]
        return reference(changed)
    return Mistake("sense", f"{MESSAGES['sense']} ({', '.join(names)})", wrong)


def sign_of(reference, name: str, tag: str = "sign-c"):
    """Mistake: the parameter ``name`` with the wrong sign (by default: the camera constant)."""
    return scaled_parameter(reference, name, -1.0, tag)


def scaled_result(reference, factor: float, tag: str = "units-mm-m", message: str | None = None):
    """Mistake: the result ``factor`` times the reference (mm versus m: 1000 or 1/1000)."""
    def wrong(params):
        value = reference(params)
        return None if callable(value) else np.asarray(value, float) * factor
    return Mistake(tag, message or MESSAGES[tag], wrong)


def transposed(reference):
    """Mistake: the transposed matrix."""
    def wrong(params):
        value = reference(params)
        return value.T
    return Mistake("transposed", MESSAGES["transposed"], wrong)


def erratum_version(record_id: str, evaluate, version: str = "old"):
    """Mistake: the formula as printed before an erratum (from :mod:`photolib.errata`).

    Parameters
    ----------
    record_id : str
        Catalogue id, e.g. ``"luhmann:4.18b"``.
    evaluate : callable
        ``evaluate(expr, params)`` turns the SymPy expression of that version into the answer
        (for numeric exercises: substitute the parameters); return the expression itself for
        symbolic exercises.
    version : str
        Key of ``record.versions``; ``"old"`` is the print before the erratum.

    When :mod:`photolib.errata` or the record is missing the rule quietly does not apply.
    """
    def wrong(params):
        try:
            # import_module honours sys.modules (a package attribute left by an earlier
            # import would not), so a missing catalogue really means no hint
            errata = importlib.import_module("photolib.errata")
            expr = errata.get(record_id).versions[version]
        except Exception:  # noqa: BLE001 - no catalogue, no hint
            return None
        return evaluate(expr, params)
    return Mistake("erratum", f"{MESSAGES['erratum']} ({record_id})", wrong)


def _negated_function(reference):
    def wrong(params):
        f = reference(params)
        return lambda *args: -np.asarray(f(*args), float)
    return wrong


def _scaled_function(reference, factor):
    def wrong(params):
        f = reference(params)
        return lambda *args: np.asarray(f(*args), float) * factor
    return wrong


def generic_mistakes(exercise) -> tuple:
    """The mistakes tried for every exercise of a kind, after the exercise's own."""
    ref = exercise.reference
    if exercise.kind in ("number", "array"):
        return (scaled_result(ref, 1000.0), scaled_result(ref, 1e-3),
                scaled_result(ref, -1.0, "sign", MESSAGES["sign"]))
    if exercise.kind == "rotation":
        return (transposed(ref),)
    if exercise.kind == "expression":
        def wrong_t(params):
            value = ref(params)
            return value.T if hasattr(value, "T") and getattr(value, "is_Matrix", False) else None
        return (Mistake("transposed", MESSAGES["transposed"], wrong_t),)
    if exercise.kind == "function":
        return (Mistake("units-mm-m", MESSAGES["units-mm-m"], _scaled_function(ref, 1000.0)),
                Mistake("units-mm-m", MESSAGES["units-mm-m"], _scaled_function(ref, 1e-3)),
                Mistake("sign", MESSAGES["sign"], _negated_function(ref)))
    return ()
