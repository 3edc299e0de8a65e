"""Per-student variants: parameters derived deterministically from the student id.

``sha256(purpose, student id, exercise id)`` seeds a :class:`numpy.random.Generator`, so the
notebook and the grader derive the same numbers, and a neighbour's numbers differ. The hidden
test inputs of function exercises also mix in ``PHOTOLIB_GRADING_SECRET`` (an environment
variable of the grader), so they cannot be computed in advance from the course package.

>>> a = rng_for("s123", "demo.scale").uniform()
>>> b = rng_for("s123", "demo.scale").uniform()
>>> c = rng_for("s124", "demo.scale").uniform()
>>> a == b, a == c
(True, False)
"""

from __future__ import annotations

import hashlib
import os

import numpy as np

__all__ = ["CHOICE_KEYS", "PURPOSES", "aerial_camera", "close_range_camera", "permuted_options",
           "printed_letter", "rng_for"]

PURPOSES = ("params", "public", "hidden")
#: the letters of a multiple choice, in printed order
CHOICE_KEYS = "abcd"


def rng_for(student_id: str, exercise_id: str, purpose: str = "params") -> np.random.Generator:
    """Generator for one student, exercise and purpose.

    Parameters
    ----------
    student_id, exercise_id : str
    purpose : {"params", "public", "hidden"}
        ``"params"``: the variant; ``"public"``: test inputs of the notebook's ``check``;
        ``"hidden"``: the grader's test inputs (mixes in ``PHOTOLIB_GRADING_SECRET``).
    """
    if purpose not in PURPOSES:
        raise ValueError(f"purpose {purpose!r} is not one of {PURPOSES}")
    secret = os.environ.get("PHOTOLIB_GRADING_SECRET", "") if purpose == "hidden" else ""
    text = "\0".join([purpose, str(student_id), str(exercise_id), secret])
    seed = int.from_bytes(hashlib.sha256(text.encode()).digest()[:16], "little")
    return np.random.default_rng(seed)


def aerial_camera(rng: np.random.Generator) -> dict:
    """An aerial survey camera and flight: camera constant (mm) and flying height (m).

    Camera constants of film and digital aerial cameras (88, 100, 120, 153, 210, 305 mm
    nominal, calibrated to 0.01 mm); flying heights 300–6000 m above ground, to 1 m.

    >>> cam = aerial_camera(np.random.default_rng(1))
    >>> 80 < cam["c_mm"] < 310 and 300 <= cam["h_m"] <= 6000
    True
    """
    nominal = rng.choice([88.0, 100.0, 120.0, 153.0, 210.0, 305.0])
    return {"c_mm": round(float(nominal + rng.uniform(-0.5, 0.5)), 2),
            "h_m": float(round(rng.uniform(300, 6000)))}


def close_range_camera(rng: np.random.Generator) -> dict:
    """A close-range camera: camera constant 8–50 mm (to 0.001 mm), object distance 1–60 m.

    >>> cam = close_range_camera(np.random.default_rng(1))
    >>> 8 <= cam["c_mm"] <= 50 and 1 <= cam["h_m"] <= 60
    True
    """
    return {"c_mm": round(float(rng.uniform(8, 50)), 3),
            "h_m": round(float(rng.uniform(1, 60)), 2)}


# -- multiple choice --------------------------------------------------------------------------------

def permuted_options(rng: np.random.Generator, options) -> tuple[str, list[int]]:
    """The options in a per-student order, as printed, and that order.

    Returns ``("(a) …; (b) …", order)``: letter ``CHOICE_KEYS[i]`` is printed before
    ``options[order[i]]``; so the letter of ``options[k]`` is ``CHOICE_KEYS[order.index(k)]``.

    >>> permuted_options(np.random.default_rng(0), ["x", "y", "z"])
    ('(a) z; (b) x; (c) y', [2, 0, 1])
    """
    options = [str(o) for o in options]
    if not 2 <= len(options) <= len(CHOICE_KEYS):
        raise ValueError(f"a choice needs 2 … {len(CHOICE_KEYS)} options, got {len(options)}")
    order = [int(i) for i in rng.permutation(len(options))]
    return "; ".join(f"({CHOICE_KEYS[i]}) {options[j]}" for i, j in enumerate(order)), order


def printed_letter(options, index: int, field: str = "options"):
    """``letter(p)``: the letter printed before ``options[index]`` in the text ``p[field]``
    (read from the text, so the parameters hold no answer).

    >>> text, _ = permuted_options(np.random.default_rng(0), ["x", "y", "z"])
    >>> printed_letter(["x", "y", "z"], 1)({"options": text})
    'c'
    """
    wanted = str(options[index])

    def letter(p):
        for item in p[field].split("; "):
            if item[4:] == wanted:
                return item[1]
        raise LookupError(f"option {wanted!r} is not in the printed options {p[field]!r}")
    return letter
