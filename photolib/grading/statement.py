"""A task statement as the student reads it: Markdown with LaTeX maths (issue 14 point 2).

:func:`render` fills the statement's ``{name}`` fields from the variant and returns the
Markdown that :func:`photolib.grading.task` displays (with the plain text of
:func:`plain` as the fallback outside a notebook):

* a field inside ``$…$`` is written as LaTeX (a list as a ``bmatrix``, ``-`` stays the
  LaTeX minus);
* a number outside maths is written with a proper minus sign (U+2212, after which no browser
  breaks a line) in a ``<span style="white-space:nowrap">``, so a value never breaks inside;
* a list of numbers (or of points) outside maths becomes a small LaTeX array
  ``$\\begin{bmatrix}…\\end{bmatrix}$``, one row per point;
* a text field with a printed matrix (``[[…], […]]``) becomes a ``bmatrix`` too; other text
  fields keep their words, with their numbers kept whole as above and their line breaks.

>>> render("Rotate by $\\\\kappa = {k}$ gon, then by {a} gon.", {"k": -1.5, "a": -2.25})
'Rotate by $\\\\kappa = -1.5$ gon, then by <span style="white-space:nowrap">−2.25</span> gon.'
>>> render("v = {v} mm", {"v": [-1.5, 2.0]})
'v = $\\\\begin{bmatrix} -1.5 & 2.0 \\\\end{bmatrix}$ mm'
"""

from __future__ import annotations

import re
import string

import numpy as np

__all__ = ["number_html", "plain", "render"]

#: a number in text: sign, digits, decimals, exponent
_NUMBER = re.compile(r"(?<![\w.])([-−+]?)(\d+(?:[.,]\d+)*(?:[eE][-+]?\d+)?)(?![\w])")
_NOWRAP = '<span style="white-space:nowrap">{}</span>'


def number_html(text: str) -> str:
    """Numbers in ``text`` with a proper minus (U+2212), each kept on one line."""
    def one(match):
        sign = "−" if match.group(1) in "-−" and match.group(1) else match.group(1)
        return _NOWRAP.format(sign + match.group(2))
    return _NUMBER.sub(one, text)


def _is_numeric_list(value) -> bool:
    if not isinstance(value, (list, tuple, np.ndarray)) or isinstance(value, str):
        return False
    try:
        array = np.asarray(value, dtype=float)
    except (TypeError, ValueError):
        return False
    return array.ndim in (1, 2) and array.size > 0


def _latex_number(text: str) -> str:
    text = text.replace("−", "-")
    mantissa, e, exponent = text.partition("e")
    if e and re.fullmatch(r"[-+]?\d+", exponent):
        return rf"{mantissa} \cdot 10^{{{int(exponent)}}}"
    return text


def _bmatrix(rows) -> str:
    body = r" \\ ".join(" & ".join(_latex_number(x) for x in row) for row in rows)
    return rf"\begin{{bmatrix}} {body} \end{{bmatrix}}"


def _list_rows(value, spec: str):
    array = np.asarray(value, dtype=object)
    rows = [array] if array.ndim == 1 else list(array)
    return [[format(x, spec) for x in row] for row in rows]


_MATRIX_TEXT = re.compile(r"\[\s*\[.*\]\s*\]", re.S)


def _matrix_text(text: str):
    """``(before, rows, after)`` of a text holding a printed matrix ``[[…], […]]``, or None."""
    match = _MATRIX_TEXT.search(text)
    if not match:
        return None
    rows = [[m.group() for m in _NUMBER.finditer(line)]
            for line in re.findall(r"\[([^\[\]]*)\]", match.group())]
    if not rows or len({len(r) for r in rows}) != 1 or not rows[0]:
        return None
    return text[:match.start()], rows, text[match.end():]


def _text_field(text: str) -> str:
    """A text field outside maths: matrices as ``bmatrix``, numbers whole, lines kept."""
    found = _matrix_text(text)
    if found is not None:
        before, rows, after = found
        return (_text_field(before) + "$$" + _bmatrix(rows) + "$$" + _text_field(after))
    lines = text.split("\n")
    return "  \n".join(number_html(_markdown_safe(line)) for line in lines)


def _field_markdown(value, spec: str, in_math: bool) -> str:
    if isinstance(value, bool) or value is None:
        return str(value)
    if _is_numeric_list(value):
        latex = _bmatrix(_list_rows(value, spec))
        return latex if in_math else f"${latex}$"
    if isinstance(value, (int, float, np.integer, np.floating)):
        text = format(value, spec)
        return _latex_number(text) if in_math else number_html(text)
    text = format(value, spec) if spec else str(value)
    if in_math:
        return text
    return _text_field(text)


_PROTECTED = re.compile(r"(\$\$|(?<!\\)\$|`[^`]*`|<[^>]*>)")
_HYPHEN_MINUS = re.compile(r"(?<=[\s(\[=,;:])-(?=\d)|^-(?=\d)")


#: a word that ends in a hyphen right before a field: one name with the field's number
_WORD_HYPHEN = re.compile(r"[\w.]*\w-$|(?:(?<=[\s(\[=,;:])|^)-$")

_INTRAWORD_STAR = re.compile(r"(?<=\w)\*(?=\w)")


def _markdown_safe(text: str) -> str:
    """An asterisk inside a word (``x*1``, an image vector) is text, not emphasis."""
    return _INTRAWORD_STAR.sub(r"\*", text)


def _literal(text: str, in_math: bool) -> tuple[str, bool]:
    """The statement's own text: a hyphen before a digit outside maths, code and tags becomes
    a minus sign (no line break after it); returns the text and whether maths is open after."""
    out = []
    for part in _PROTECTED.split(text):
        if part in ("$", "$$"):
            in_math = not in_math
            out.append(part)
        elif in_math or part.startswith(("`", "<")):
            out.append(part)
        else:
            out.append(_markdown_safe(_HYPHEN_MINUS.sub("−", part)))
    return "".join(out), in_math


def render(statement: str, params) -> str:
    """The statement's Markdown for this variant (see the module)."""
    out = []
    in_math = False
    formatter = string.Formatter()
    for literal, name, spec, conversion in formatter.parse(statement):
        text, in_math = _literal(literal, in_math)
        out.append(text)
        if name is None:
            continue
        value, _ = formatter.get_field(name, (), params)
        if conversion:
            value = formatter.convert_field(value, conversion)
        field = _field_markdown(value, spec or "", in_math)
        glued = None if in_math or not out else _WORD_HYPHEN.search(out[-1])
        if glued and field.startswith(_NOWRAP.split("{")[0]):
            # a name such as aerial2-{j:03d}: the browser would break at the hyphen
            # and a minus typed before a field ("x = -{k}") keeps to its number as a minus sign
            name = glued.group()
            out[-1] = out[-1][:glued.start()]
            field = _NOWRAP.format((name if name != "-" else "−") + field)
        out.append(field)
    return "".join(out)


def plain(statement: str, params) -> str:
    """The statement as plain text (outside a notebook): fields filled with ``format``."""
    return statement.format(**params)
