"""Answers as data: encode a value into JSON inside the kernel, decode it in the grader.

:func:`encode_value` runs in the student's kernel (its source is injected by the grader, so
it does not depend on anything the notebook may have patched; the transport of the record
back to the grader does run in the student's process: see docs/instructors.md, "What is and
is not protected") and turns numbers, arrays,
strings and SymPy expressions into JSON. :func:`decode_value` runs in the grader and accepts
only a whitelist: SymPy trees are rebuilt from known node names, numbers from strings; there is
no ``eval`` anywhere.

>>> import sympy as sp
>>> x = sp.Symbol("x")
>>> decode_value(encode_value(sp.sin(x) ** 2 + sp.Rational(1, 3)))
sin(x)**2 + 1/3
>>> decode_value(encode_value([[1, 2], [3, 4]])).shape
(2, 2)
"""

from __future__ import annotations

import math

import numpy as np

__all__ = ["MAX_ELEMENTS", "NONE", "NOT_ANSWERED", "DecodeError", "Raised", "decode_value",
           "decoded_or_unsupported", "encode_value", "unanswered"]

MAX_ELEMENTS = 100_000
MAX_NODES = 20_000
#: deepest nesting of an expression tree (or of lists)
MAX_DEPTH = 100
#: largest |numeric exponent| of one power, integer, rational or float
MAX_EXPONENT = 64
#: largest product of the |numeric exponents| along one path from the root (nested powers)
MAX_POWER = 256
#: deepest nesting of exponentials (exp, sinh, cosh, powers with a symbolic exponent)
MAX_EXP_HEIGHT = 2


class _NotAnswered:
    def __init__(self, name="NOT_ANSWERED"):
        self._name = name

    def __repr__(self):
        return self._name


#: decoded value of an untouched answer (``...``, missing variable)
NOT_ANSWERED = _NotAnswered()
#: decoded ``None``: an answer variable set to None counts as not answered, but a function
#: that returns None (a forgotten ``return``) is told so, not "not answered yet"
NONE = _NotAnswered("NONE")


def unanswered(value) -> bool:
    """Is a decoded value :data:`NOT_ANSWERED` or :data:`NONE`?"""
    return value is NOT_ANSWERED or value is NONE


class DecodeError(ValueError):
    """An encoded answer that is malformed or outside the whitelist."""


def encode_value(value, _depth=0):
    """JSON-ready description of ``value`` (runs in the kernel; standard library only)."""
    import sys
    sp = sys.modules.get("sympy")
    if value is None:
        return {"t": "none", "v": "None"}
    if value is Ellipsis or value is NotImplemented:
        return {"t": "none"}
    if isinstance(value, bool):
        return {"t": "bool", "v": bool(value)}
    if isinstance(value, str):
        return {"t": "str", "v": value[:20000]}
    if isinstance(value, (int, float)) and not isinstance(value, bool):
        return {"t": "num", "v": repr(float(value))}
    if isinstance(value, complex):
        if value.imag != 0:
            return {"t": "other", "type": "complex number (nonzero imaginary part)"}
        return {"t": "num", "v": repr(float(value.real))}
    if sp is not None and isinstance(value, sp.MatrixBase):
        if value.rows * value.cols > 400:
            return {"t": "other", "type": "large Matrix"}
        return {"t": "matrix", "shape": [value.rows, value.cols],
                "v": [_tree(e, sp, [0]) for e in value]}
    if sp is not None and isinstance(value, sp.Basic):
        if value.is_number and not value.free_symbols and isinstance(value, sp.Float):
            return {"t": "num", "v": repr(float(value))}
        return {"t": "sympy", "v": _tree(value, sp, [0])}
    np_ = sys.modules.get("numpy")
    if np_ is not None and isinstance(value, np_.generic) and value.ndim == 0:
        if np_.iscomplexobj(value):
            if value.imag != 0:
                return {"t": "other", "type": "complex number (nonzero imaginary part)"}
            value = value.real
        try:
            return {"t": "num", "v": repr(float(value))}
        except (TypeError, ValueError):
            return {"t": "other", "type": type(value).__name__}
    if np_ is not None and isinstance(value, (list, tuple, np_.ndarray)):
        try:
            arr = np_.asarray(value)
            if arr.dtype.kind == "c":
                if np_.any(arr.imag != 0):
                    return {"t": "other",
                            "type": "complex array (nonzero imaginary part)"}
                arr = arr.real
            arr = np_.asarray(arr, dtype=float)
        except (TypeError, ValueError):
            arr = None
        if arr is not None:
            if arr.size > 100_000:
                return {"t": "other", "type": f"array of {arr.size} elements"}
            return {"t": "array", "shape": list(arr.shape), "v": [repr(float(v)) for v in arr.ravel()]}
    if isinstance(value, (list, tuple)) and _depth < 3 and len(value) <= 1000:
        return {"t": "list", "v": [encode_value(v, _depth + 1) for v in value]}
    return {"t": "other", "type": type(value).__name__}


def _tree(expr, sp, count):
    count[0] += 1
    if count[0] > 20_000:
        raise ValueError("expression too large")
    if isinstance(expr, sp.Symbol):
        return {"s": expr.name}
    if isinstance(expr, sp.Integer):
        return {"i": str(int(expr))}
    if isinstance(expr, sp.Rational):
        return {"r": [str(expr.p), str(expr.q)]}
    if isinstance(expr, sp.Float):
        return {"F": repr(float(expr))}
    if expr in (sp.pi, sp.E, sp.I):
        return {"c": str(expr)}
    return {"f": type(expr).__name__, "a": [_tree(a, sp, count) for a in expr.args]}


# ---------------------------------------------------------------------------------- decoding
_FUNCTIONS = ("Add", "Mul", "Pow", "sin", "cos", "tan", "cot", "sec", "csc", "asin", "acos",
              "atan", "atan2", "sinh", "cosh", "tanh", "exp", "log", "Abs", "sign")


def _number(text: str) -> float:
    if not isinstance(text, str) or len(text) > 40:
        raise DecodeError(f"bad number {text!r}")
    try:
        return float(text)
    except ValueError:
        raise DecodeError(f"bad number {text!r}") from None


def _integer(text) -> int:
    if not isinstance(text, str) or len(text) > 200 or not text.lstrip("-").isdigit():
        raise DecodeError(f"bad integer {str(text)[:50]!r}")
    return int(text)


def _limits(node, depth=0, count=None):
    """Check an encoded tree before SymPy sees it; returns ``(exp_height, power)``.

    ``power`` is the product of ``max(1, |exponent|)`` of the numeric powers on the deepest
    path (what nested ``Pow(…, 64)`` multiply to), ``exp_height`` the nesting of
    exponentials. Both are bounded, so that building, expanding or sampling an answer in the
    grader stays cheap.
    """
    count = [0] if count is None else count
    count[0] += 1
    if count[0] > MAX_NODES:
        raise DecodeError(f"expression too large (more than {MAX_NODES} nodes)")
    if depth > MAX_DEPTH:
        raise DecodeError(f"expression nested deeper than {MAX_DEPTH} levels")
    if not isinstance(node, dict) or "f" not in node:
        return 0, 1.0
    args = node.get("a")
    if not isinstance(args, list):
        raise DecodeError("bad expression node")
    stats = [_limits(a, depth + 1, count) for a in args]
    name = node["f"]
    if name == "Pow" and len(args) == 2:
        (hb, pb), (he, pe) = stats
        exponent = _literal(args[1])
        if exponent is None:  # symbolic exponent: an exponential
            height, power = 1 + max(hb, he), max(pb, pe)
        else:
            if abs(exponent) > MAX_EXPONENT:
                raise DecodeError(f"exponent {exponent:g} larger than {MAX_EXPONENT}")
            height, power = hb, pb * max(1.0, abs(exponent))
    elif name in ("exp", "sinh", "cosh"):
        height = 1 + max((h for h, _ in stats), default=0)
        power = max((p for _, p in stats), default=1.0)
    else:
        height = max((h for h, _ in stats), default=0)
        power = max((p for _, p in stats), default=1.0)
    if height > MAX_EXP_HEIGHT:
        raise DecodeError(f"exponentials nested deeper than {MAX_EXP_HEIGHT}")
    if power > MAX_POWER:
        raise DecodeError(f"nested powers multiply to more than {MAX_POWER}")
    return height, power


def _literal(node):
    """The value of a numeric leaf (integer, rational, float), else None."""
    if not isinstance(node, dict):
        return None
    try:
        if "i" in node:
            return float(_integer(node["i"]))
        if "r" in node:
            p, q = node["r"]
            return _integer(p) / _integer(q) if _integer(q) else None
        if "F" in node:
            return _number(node["F"])
    except (ValueError, TypeError, OverflowError):
        raise DecodeError("bad number in an exponent") from None
    return None


def _decode_tree(node, sp, count):
    count[0] += 1
    if count[0] > MAX_NODES:
        raise DecodeError("expression too large")
    if not isinstance(node, dict) or len(node) not in (1, 2):
        raise DecodeError(f"bad expression node {str(node)[:80]!r}")
    if "s" in node:
        name = node["s"]
        if not isinstance(name, str) or not name.isidentifier() or name.startswith("_"):
            raise DecodeError(f"bad symbol name {str(name)[:50]!r}")
        return sp.Symbol(name)
    if "i" in node:
        return sp.Integer(_integer(node["i"]))
    if "r" in node:
        if not isinstance(node["r"], list) or len(node["r"]) != 2:
            raise DecodeError("bad rational")
        p, q = node["r"]
        if _integer(q) == 0:
            raise DecodeError("rational with zero denominator")
        return sp.Rational(_integer(p), _integer(q))
    if "F" in node:
        return sp.Float(_number(node["F"]))
    if "c" in node:
        consts = {"pi": sp.pi, "E": sp.E, "I": sp.I}
        if node["c"] not in consts:
            raise DecodeError(f"unknown constant {str(node['c'])[:30]!r}")
        return consts[node["c"]]
    name, args = node.get("f"), node.get("a")
    if name not in _FUNCTIONS or not isinstance(args, list):
        raise DecodeError(f"{str(name)[:40]!r} is not an allowed function")
    args = [_decode_tree(a, sp, count) for a in args]
    if name == "Pow":
        if len(args) != 2:
            raise DecodeError("Pow needs two arguments")
        if args[1].is_number and args[1].is_real and abs(float(args[1])) > MAX_EXPONENT:
            raise DecodeError(f"exponent larger than {MAX_EXPONENT}")
    func = getattr(sp, name)
    try:
        return func(*args)
    except (TypeError, ValueError, ArithmeticError) as exc:  # e.g. sin with two arguments
        raise DecodeError(f"{name} cannot take these arguments "
                          f"({type(exc).__name__}: {str(exc)[:80]})") from None


def _sympy_tree(node, sp, count):
    _limits(node)
    return _decode_tree(node, sp, count)


def decode_value(data, _depth=0):
    """Rebuild an answer from :func:`encode_value`'s output; whitelisted, never ``eval``.

    Returns
    -------
    object
        :data:`NOT_ANSWERED`, :data:`NONE`, bool, float, str, ``numpy.ndarray``, SymPy expression or
        ``sympy.Matrix``, or a list of these.

    Raises
    ------
    DecodeError
        For anything malformed or not on the whitelist.
    """
    if not isinstance(data, dict) or "t" not in data:
        raise DecodeError(f"bad answer record {str(data)[:80]!r}")
    kind = data["t"]
    if kind == "none":
        return NONE if data.get("v") == "None" else NOT_ANSWERED
    if kind == "bool":
        return bool(data.get("v"))
    if kind == "str":
        if not isinstance(data.get("v"), str):
            raise DecodeError("string answer is not a string")
        return data["v"]
    if kind == "num":
        return _number(data.get("v"))
    if kind == "array":
        shape, values = data.get("shape"), data.get("v")
        if (not isinstance(shape, list) or not all(isinstance(n, int) and n >= 0 for n in shape)
                or not isinstance(values, list) or len(values) > MAX_ELEMENTS
                or math.prod(shape) != len(values)):
            raise DecodeError("array answer with inconsistent shape")
        return np.array([_number(v) for v in values], dtype=float).reshape(shape)
    if kind in ("sympy", "matrix"):
        import sympy as sp
        count = [0]
        if kind == "sympy":
            return _sympy_tree(data.get("v"), sp, count)
        shape, values = data.get("shape"), data.get("v")
        if (not isinstance(shape, list) or len(shape) != 2 or not isinstance(values, list)
                or not all(isinstance(n, int) and n > 0 for n in shape)
                or shape[0] * shape[1] != len(values) or len(values) > 400):  # as encoded
            raise DecodeError("matrix answer with inconsistent shape")
        return sp.Matrix(shape[0], shape[1], [_sympy_tree(v, sp, count) for v in values])
    if kind == "list":
        values = data.get("v")
        if not isinstance(values, list) or len(values) > 1000:
            raise DecodeError("bad list answer")
        if _depth >= 3:
            raise DecodeError("lists nested deeper than 3 levels")
        return [decode_value(v, _depth + 1) for v in values]
    if kind == "other":
        return Unsupported(str(data.get("type", "?"))[:80])
    if kind == "raised":
        return Raised(str(data.get("type", "?"))[:80], bool(data.get("ve")),
                      str(data.get("m", ""))[:200])
    raise DecodeError(f"unknown answer type {str(kind)[:30]!r}")


class Raised:
    """A function's outcome on one test input when it raised instead of returning.

    A degenerate test input (collinear points, zero parallax) has no answer: the reference
    raises ``ValueError`` naming the problem, and a student's function is right there when
    it raises ``ValueError`` (or a subclass) too; the message is not judged.
    """

    def __init__(self, type_name: str, value_error: bool, message: str = ""):
        self.type_name, self.value_error, self.message = type_name, value_error, message

    @classmethod
    def of(cls, exc: BaseException) -> Raised:
        return cls(type(exc).__name__, isinstance(exc, ValueError), str(exc)[:200])

    def record(self) -> dict:
        """As the grader's extraction emits it (``decode_value`` reads it back)."""
        return {"t": "raised", "type": self.type_name, "ve": self.value_error, "m": self.message}

    def __repr__(self):
        return f"Raised({self.type_name!r}, {self.message!r})"


class Unsupported:
    """An answer of a type the grader cannot judge (its type name only)."""

    def __init__(self, type_name: str):
        self.type_name = type_name

    def __repr__(self):
        return f"Unsupported({self.type_name!r})"


def decoded_or_unsupported(decode):
    """``decode()``, or :class:`Unsupported` with the reason when it fails.

    One bad answer costs its own exercise only; the grader's extraction
    (:func:`photolib.grading.extract.decode_item`) and ``check()`` in the notebook both read
    answers through here, so they say the same words.
    """
    try:
        return decode()
    except RecursionError:
        return Unsupported("answer nested too deeply")
    except Exception as exc:  # noqa: BLE001 - any failure is the answer's, not the grader's
        reason = str(exc) if isinstance(exc, DecodeError) else f"{type(exc).__name__}: {exc}"
        return Unsupported(f"unreadable answer ({reason[:200]})")
