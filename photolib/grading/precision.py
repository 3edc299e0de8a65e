"""The precision a task asks for, and that the judge's tolerance grants (issue 14 point 2).

Every statement says to what precision the answer is wanted. Where the statement says so in
its own words ("to 0.01 mm", "to 3 significant digits", "to 4 decimals"), that is read from
it (:func:`stated_in_words`); else :attr:`Exercise.precision
<photolib.grading.spec.Exercise.precision>` gives it; else it is derived for the variant from
the judge's tolerance (:func:`derived`): the coarsest decimal step ``d`` (a power of ten)
whose rounding error ``d/2`` stays within 0.8 of the smallest tolerance of any entry, so an
answer rounded as asked is always accepted:

    d = 10^⌊log10(1.6 · min_i (atol_i + rtol·|ref_i|))⌋

>>> Precision("decimal", 0.001, "mm").text()
'to 0.001 mm'
>>> Precision("significant", 4).text()
'to 4 significant digits'
>>> Precision("decimal", 0.001).round(12.34567)
12.346
>>> stated_in_words("Give x in mm to 0.01 mm.")
Precision(kind='decimal', value=0.01, unit='mm')
>>> stated_in_words("to 3 significant digits").value
3
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass

import numpy as np

__all__ = ["Precision", "derived", "for_variant", "stated_in_words"]

#: kinds whose answers are numbers that can be rounded
ROUNDED_KINDS = ("number", "array", "rotation")

#: the coarsest step a rotation matrix's entries may be rounded to (orthonormality 1e-6)
ROTATION_STEP = 1e-7

#: share of the tolerance the rounding of a stated precision may use
MARGIN = 0.8

_UNIT = r"(µm|μm|mm|cm|m|km|px|pixels?|°|gon|rad|mrad|%|s|lp/mm|1/mm)"
_WORDS = (
    (re.compile(r"\bto (\d+) significant (?:digits|figures)", re.I), "significant"),
    (re.compile(r"\bto (\d+) (?:decimals|decimal places|decimal digits)\b", re.I), "decimals"),
    (re.compile(r"\bto (?:within )?(0\.0*1|0\.0*5|1e-\d+|10\^-?\d+|1|10|100)\s?"
                + _UNIT + r"(?![\w²³])"), "decimal"),
)


@dataclass(frozen=True)
class Precision:
    """A stated precision: ``kind`` ``"decimal"`` (a step ``value``, e.g. 0.001, in ``unit``)
    or ``"significant"`` (``value`` significant digits)."""

    kind: str
    value: float
    unit: str = ""

    def text(self) -> str:
        """The words of the statement: ``"to 0.001 mm"``, ``"to 4 significant digits"``."""
        if self.kind == "significant":
            return f"to {int(self.value)} significant digits"
        if self.kind == "whole":
            return "exactly (a whole number)"
        if self.value < 1e-3:
            shown = {"°": "degrees", "%": "percent"}.get(self.unit, self.unit)
            return f"to {-round(math.log10(self.value))} decimals" + (
                f" (in {shown})" if shown else "")
        if self.value >= 1:
            return f"to the nearest {self.value:.0f}" + (f" {self.unit}" if self.unit else "")
        step = _step_text(self.value)
        return f"to {step} {self.unit}".rstrip() if self.unit not in ("°", "%") else \
            f"to {step}{self.unit}"

    def half(self, reference) -> np.ndarray:
        """Largest rounding error of an answer rounded as stated, per entry of ``reference``."""
        ref = np.abs(np.asarray(reference, float))
        if self.kind == "whole":
            return np.zeros(ref.shape)
        if self.kind == "significant":
            with np.errstate(divide="ignore"):
                exponent = np.where(ref > 0, np.floor(np.log10(np.where(ref > 0, ref, 1.0))), 0)
            return 0.5 * 10.0 ** (exponent - int(self.value) + 1)
        return np.full(ref.shape, 0.5 * self.value)

    def round(self, value):
        """``value`` rounded as stated (what a careful student answers)."""
        v = np.asarray(value, float)
        if self.kind == "whole":
            out = np.round(v)
        elif self.kind == "significant":
            out = np.zeros_like(v)
            nz = v != 0
            exponent = np.floor(np.log10(np.abs(v[nz])))
            scale = 10.0 ** (exponent - int(self.value) + 1)
            out[nz] = np.round(v[nz] / scale) * scale
        else:
            decimals = -int(round(math.log10(self.value)))
            out = np.round(v, decimals) if self.value < 10 else np.round(v / self.value) * self.value
        return float(out) if v.ndim == 0 else out


def _step_text(step: float) -> str:
    decimals = -int(round(math.log10(step)))
    if 0 <= decimals <= 6:
        return f"{step:.{decimals}f}"
    if decimals < 0 and decimals >= -4:
        return f"{step:.0f}"
    return f"1e{-decimals}"


def stated_in_words(text: str) -> Precision | None:
    """The precision a statement (as the student reads it) states in words, else None."""
    for pattern, kind in _WORDS:
        match = pattern.search(text)
        if not match:
            continue
        if kind == "significant":
            return Precision("significant", int(match.group(1)))
        if kind == "decimals":
            return Precision("decimal", 10.0 ** -int(match.group(1)))
        number = match.group(1).replace("10^", "1e")
        unit = match.group(2).replace("μm", "µm")
        return Precision("decimal", float(number), unit)
    return None


_ASKED_IN = re.compile(r"\bin \**(µm|μm|mm|cm|m|km|px|pixels|degrees|gon|radians|rad|e⁻|dB|DN)"
                       r"\**(?![\w²³⁻])|\((µm|mm|cm|m|px|gon|rad)\)")
_UNIT_NAMES = {"μm": "µm", "degrees": "°", "radians": "rad"}


def answer_unit_words(exercise) -> str:
    """The unit the answer is asked in, as the precision line names it: ``exercise.unit``,
    else the last "in mm", "in **cm**", "in degrees", "(µm)" of the statement; else ``""``.

    >>> from photolib.grading.spec import Exercise
    >>> answer_unit_words(Exercise(id="d.u", points=1, title="", kind="number", answer="x",
    ...     statement="Give the angle in degrees.", parameters=None, reference=None))
    '°'
    """
    if getattr(exercise, "unit", ""):
        return exercise.unit
    found = [a or b for a, b in _ASKED_IN.findall(exercise.statement)]
    return _UNIT_NAMES.get(found[-1], found[-1]) if found else ""


def derived(exercise, params) -> Precision | None:
    """The coarsest decimal step the judge's tolerance grants this variant (see the module),
    in the exercise's unit; None for kinds that are not rounded numbers."""
    if exercise.kind not in ROUNDED_KINDS:
        return None
    ref = np.asarray(exercise.reference(params), float)
    rtol, atol = exercise.tolerances(params)
    tol = np.broadcast_to(np.asarray(atol, float), ref.shape) + rtol * np.abs(ref)
    smallest = float(np.min(tol)) if tol.size else 0.0
    if np.all(ref == np.round(ref)) and smallest < 0.5 and exercise.kind == "number":
        return Precision("whole", 1)
    if not smallest > 0:
        return None
    step = 10.0 ** math.floor(math.log10(2 * MARGIN * smallest))
    if exercise.kind == "rotation":
        # the judge also asks |RᵀR − I| ≤ 1e-6 of a rotation: entries rounded to 1e-7 keep it
        step = min(step, ROTATION_STEP)
    unit = answer_unit_words(exercise)
    if step < 1e-6 and exercise.kind == "number" and float(ref) != 0:
        # a step this fine reads better as significant digits
        exponent = math.floor(math.log10(abs(float(ref))))
        return Precision("significant", exponent - round(math.log10(step)) + 1)
    return Precision("decimal", step, unit)


#: metres per unit, for a precision stated in another length unit than the answer's
_LENGTHS = {"µm": 1e-6, "mm": 1e-3, "cm": 1e-2, "m": 1.0, "km": 1e3}


def _in_answer_unit(precision: Precision, unit: str) -> Precision:
    """"in m, to 1 mm" is a step of 0.001 in the answer's unit m.

    >>> _in_answer_unit(Precision("decimal", 1.0, "mm"), "m")
    Precision(kind='decimal', value=0.001, unit='m')
    """
    if (precision.kind == "decimal" and precision.unit in _LENGTHS and unit in _LENGTHS
            and precision.unit != unit):
        step = precision.value * _LENGTHS[precision.unit] / _LENGTHS[unit]
        return Precision("decimal", float(f"{step:.12g}"), unit)
    return precision


def for_variant(exercise, params, statement: str | None = None) -> tuple[Precision | None, bool]:
    """``(precision, in_words)``: what the statement states in words (``in_words`` True),
    else the exercise's ``precision`` override, else :func:`derived`."""
    text = statement if statement is not None else exercise.statement
    words = stated_in_words(text)
    if words is not None:
        return _in_answer_unit(words, answer_unit_words(exercise)), True
    override = getattr(exercise, "precision", "")
    if override:
        return stated_in_words(override) or Precision("significant", 0), False
    return derived(exercise, params), False
