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
import re

import numpy as np

from photolib.grading.spec import Mistake, Params

__all__ = [
    "ERRATUM_RULES",
    "MESSAGES",
    "check_erratum_rules",
    "degrees_for_radians",
    "erratum_version",
    "generic_mistakes",
    "gon_for_radians",
    "reversed_sense",
    "scaled_parameter",
    "scaled_result",
    "sign_of",
    "transposed",
    "answer_unit",
    "unit_message",
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
    "units-um-m": "off by a factor of 10⁶: are µm and m mixed up?",
    "radians": "it looks as if the answer is in radians where degrees are asked "
               "(convert with numpy.degrees)",
    "factor-2": "off by a factor of 2: a half or a double (a radius for a diameter, a "
                "half-angle, ½ forgotten)?",
    "reciprocal": "your answer is the reciprocal of the expected one (a ratio or a scale "
                  "inverted)",
    "inverse": "your matrix is the inverse of the expected one (the transformation the "
               "other way round)",
    "digits": "close, but not to the precision asked",
    "unnormalised": "the direction is right but the vector is not normalised: divide it "
                    "by its length (a unit vector, length 1)",
    "weight-inverted": "the weight is inverted: p = σ0²/σ² (divide by σ²), not σ²/σ0²",
}

#: how a unit prefix mix-up reads for an answer in a given unit: factor -> words
_UNIT_WORDS = {
    "mm": {1e3: "the answer looks as if it is in µm where mm are asked",
           1e-3: "the answer looks as if it is in m where mm are asked",
           1e6: "the answer looks as if it is in nm where mm are asked",
           1e-6: "the answer looks as if it is in km where mm are asked"},
    "µm": {1e3: "the answer looks as if it is in nm where µm are asked",
           1e-3: "the answer looks as if it is in mm where µm are asked",
           1e-6: "the answer looks as if it is in m where µm are asked"},
    "m": {1e3: "the answer looks as if it is in mm where m are asked",
          1e-3: "the answer looks as if it is in km where m are asked",
          1e6: "the answer looks as if it is in µm where m are asked"},
}

#: the unit of an answer as statements name it ("… in mm", "(in µm)")
_UNIT_IN = re.compile(r"\bin \**(µm|μm|um|mm|m|metres|millimetres|micrometres)\**(?![\w²³])"
                      r"|\((µm|μm|mm|m)\)")
_UNIT_ALIASES = {"μm": "µm", "um": "µm", "micrometres": "µm", "millimetres": "mm",
                 "metres": "m"}


def answer_unit(exercise) -> str:
    """The length unit the answer is asked in: ``exercise.unit``, else the last
    "in mm" / "in µm" / "in m" of the statement; ``""`` when there is none.

    >>> from photolib.grading.spec import Exercise
    >>> answer_unit(Exercise(id="d.u", points=1, title="", kind="number", answer="x",
    ...     statement="What is the image distance, in mm?", parameters=None, reference=None))
    'mm'
    """
    unit = getattr(exercise, "unit", "")
    if unit:
        return _UNIT_ALIASES.get(unit, unit)
    found = [a or b for a, b in _UNIT_IN.findall(exercise.statement)]
    return _UNIT_ALIASES.get(found[-1], found[-1]) if found else ""


def unit_message(exercise, factor: float) -> str:
    """The hint for an answer ``factor`` times the reference (a unit prefix mixed up), in
    the words of the exercise's unit: µm for mm where the answer is in mm, mm for m where it
    is in m; without a known unit the factor and the usual suspects."""
    words = _UNIT_WORDS.get(answer_unit(exercise), {}).get(factor)
    power = round(math.log10(factor))
    shown = {3: "1000", -3: "1/1000", 6: "10⁶", -6: "1/10⁶"}[power]
    if words:
        return f"off by a factor of {shown}: {words}"
    if abs(power) == 3:
        return f"off by a factor of {shown}: are units mixed up (µm and mm, or mm and m)?"
    return f"off by a factor of {shown}: are µm and m mixed up?"


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

    Without :mod:`photolib.errata` (a grader installed without the catalogue) the rule does
    not apply. An unknown record or version is an error (``KeyError`` naming it), not a
    silently missing hint: every rule is listed in :data:`ERRATUM_RULES`, and
    :func:`check_erratum_rules` (run by the tests) looks each one up.
    """
    ERRATUM_RULES.append((record_id, version))

    def wrong(params):
        try:
            # import_module honours sys.modules (a package attribute left by an earlier
            # import would not), so a missing catalogue really means no hint
            errata = importlib.import_module("photolib.errata")
        except ImportError:
            return None
        return evaluate(_erratum_expression(errata, record_id, version), params)
    return Mistake("erratum", f"{MESSAGES['erratum']} ({record_id})", wrong)


#: (record id, version) of every :func:`erratum_version` rule built so far
ERRATUM_RULES: list = []


def _erratum_expression(errata, record_id: str, version: str):
    record = errata.get(record_id)                       # KeyError: "no errata record '…'"
    if version not in record.versions:
        raise KeyError(f"errata record {record_id!r} has no version {version!r}; it has "
                       f"{sorted(record.versions)}")
    return record.versions[version]


def check_erratum_rules() -> int:
    """Look up the record and version of every erratum rule built so far (import the exercise
    modules first); raises ``KeyError`` naming the first that does not exist. Returns how many
    rules were checked."""
    errata = importlib.import_module("photolib.errata")
    for record_id, version in ERRATUM_RULES:
        _erratum_expression(errata, record_id, version)
    return len(ERRATUM_RULES)


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


#: a generic mistake whose value lies within this relative distance of the reference does
#: not apply to the variant (1/x of x ≈ 1, Mᵀ of a nearly symmetric M): it would tell
#: nothing and cut a ``PRINTED`` tolerance down to the gap
APART = 0.05


def _apart(reference, wrong):
    """``wrong`` where its value lies clearly apart from the reference, else None."""
    def rule(params):
        value = wrong(params)
        if value is None:
            return None
        ref = np.asarray(reference(params), float)
        got = np.asarray(value, float)
        if got.shape != ref.shape or not np.all(np.isfinite(got)):
            return None
        if np.max(np.abs(got - ref)) <= APART * max(float(np.max(np.abs(ref))), 1e-300):
            return None
        return value
    return rule


def _reciprocal(reference):
    def wrong(params):
        value = np.asarray(reference(params), float)
        if value.ndim == 0:
            return None if value == 0 else 1.0 / value
        if value.ndim == 2 and value.shape[0] == value.shape[1]:
            return None if abs(np.linalg.det(value)) < 1e-12 else np.linalg.inv(value)
        return None
    return wrong


def _square_transposed(reference):
    def wrong(params):
        value = np.asarray(reference(params), float)
        return value.T if value.ndim == 2 and value.shape[0] == value.shape[1] else None
    return wrong


def _times(reference, factor):
    def wrong(params):
        return np.asarray(reference(params), float) * factor
    return wrong


def _hint(tag, message, wrong):
    """A near-miss rule that gives its hint but does not narrow a ``PRINTED`` tolerance."""
    return Mistake(tag, message, wrong, shapes_tolerance=False)


def generic_mistakes(exercise) -> tuple:
    """The mistakes tried for every exercise of a kind, after the exercise's own.

    Numbers and arrays: a unit prefix mixed up (10^±3 and 10^±6, in the words of the
    exercise's unit, :func:`unit_message`), the sign, degrees for radians and radians for
    degrees, a factor 2 or ½, the reciprocal (of a number) or inverse (of a square matrix)
    and a square matrix transposed; each applies only where its value is clearly apart
    from the reference (:data:`APART`). Functions: the same prefixes and the sign.
    """
    ref = exercise.reference
    if exercise.kind in ("number", "array"):
        units = tuple(Mistake("units-mm-m" if abs(f) in (1e3, 1e-3) else "units-um-m",
                              unit_message(exercise, f), _times(ref, f))
                      for f in (1e3, 1e-3))
        more = (_hint("units-um-m", unit_message(exercise, 1e6), _times(ref, 1e6)),
                _hint("units-um-m", unit_message(exercise, 1e-6), _times(ref, 1e-6)),
                _hint("degrees", "it looks as if the answer is in degrees where radians "
                      "are asked (convert with numpy.radians)", _times(ref, 180 / math.pi)),
                _hint("radians", MESSAGES["radians"], _times(ref, math.pi / 180)),
                _hint("factor-2", MESSAGES["factor-2"], _apart(ref, _times(ref, 2.0))),
                _hint("factor-2", MESSAGES["factor-2"], _apart(ref, _times(ref, 0.5))))
        matrix = ((_hint("transposed", MESSAGES["transposed"],
                         _apart(ref, _square_transposed(ref))),)
                  if exercise.kind == "array" else ())
        reciprocal = _hint("reciprocal" if exercise.kind == "number" else "inverse",
                           MESSAGES["reciprocal" if exercise.kind == "number" else "inverse"],
                           _apart(ref, _reciprocal(ref)))
        return (units + (scaled_result(ref, -1.0, "sign", MESSAGES["sign"]),)
                + more + matrix + (reciprocal,))
    if exercise.kind == "rotation":
        return (transposed(ref),)
    if exercise.kind == "expression":
        def wrong_t(params):
            value = ref(params)
            return value.T if hasattr(value, "T") and getattr(value, "is_Matrix", False) else None
        return (Mistake("transposed", MESSAGES["transposed"], wrong_t),)
    if exercise.kind == "function":
        return (Mistake("units-mm-m", unit_message(exercise, 1e3), _scaled_function(ref, 1e3)),
                Mistake("units-mm-m", unit_message(exercise, 1e-3),
                        _scaled_function(ref, 1e-3)),
                Mistake("sign", MESSAGES["sign"], _negated_function(ref)),
                _hint("units-um-m", unit_message(exercise, 1e6), _scaled_function(ref, 1e6)),
                _hint("units-um-m", unit_message(exercise, 1e-6), _scaled_function(ref, 1e-6)),
                _hint("factor-2", MESSAGES["factor-2"], _scaled_function(ref, 2.0)),
                _hint("factor-2", MESSAGES["factor-2"], _scaled_function(ref, 0.5)))
    return ()
