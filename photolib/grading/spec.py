"""How an exercise is declared: :class:`Exercise`, :class:`Mistake` and :class:`Params`.

An exercise is data plus small functions, kept in a chapter module under
:mod:`photolib.grading.exercises` so that the grader's own process has the parameters, the
reference solution, the hidden tests and the hint rules without trusting the notebook.

>>> ex = Exercise(
...     id="demo.double", points=1, title="Double it", kind="number", answer="doubled",
...     statement="Double a = {a}.", parameters=lambda rng: {"a": 2.5},
...     reference=lambda p: 2 * p["a"])
>>> ex.reference(ex.parameters(None))
5.0
"""

from __future__ import annotations

import keyword
import re
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any

__all__ = ["KINDS", "MIN_VARIANTS", "PRINTED", "RESERVED_NAMES", "Exercise", "Mistake", "Params"]

#: answer kinds and what the answer variable holds
KINDS = {
    "number": "a real number",
    "array": "an array of numbers of a fixed shape",
    "rotation": "a rotation matrix (orthonormal, det +1)",
    "expression": "a SymPy expression or Matrix, or a formula string",
    "function": "a Python function, called on test inputs",
    "choice": "the key of one option of a multiple choice, e.g. 'b'",
}

#: notebook names a task's parameters may not take (the setup cell and the id cell own them)
RESERVED_NAMES = frozenset({"STUDENT_ID", "check", "task"})

#: ``Exercise(tolerance=PRINTED)``: the tolerance follows the rounding of the printed inputs
#: (:func:`photolib.grading.judge.printed_tolerance`)
PRINTED = "printed"

#: distinct variants (what the student sees and the correct answer) an exercise must draw,
#: unless its ``few_variants`` says why it cannot
MIN_VARIANTS = 50

_ID = re.compile(r"^[a-z0-9]+(?:[.-][a-z0-9]+)*$")
_NAME = re.compile(r"^[A-Za-z_][A-Za-z0-9_]*$")


class Params(dict):
    """The parameters of one student's variant; keys also read as attributes.

    >>> p = Params(c_mm=153.2)
    >>> p.c_mm
    153.2
    """

    def __getattr__(self, name):
        try:
            return self[name]
        except KeyError:
            raise AttributeError(f"no parameter {name!r}; parameters are {sorted(self)}") from None


@dataclass(frozen=True)
class Mistake:
    """A recognisable mistake: the answer it produces, and the hint to give.

    Parameters
    ----------
    tag : str
        Short name counted in the gradebook summary, e.g. ``"transposed"``.
    message : str
        The hint shown to the student.
    wrong : callable
        ``wrong(params)`` returns the value (for function exercises: the function) that this
        mistake produces. It may return ``None`` when the mistake does not apply.
    shapes_tolerance : bool
        Whether a ``PRINTED`` tolerance is kept off this mistake's value (the default). The
        near-miss hints added for issue 14 (a factor 2, the reciprocal, degrees for radians)
        are hints only: they never narrow the tolerance, so an answer within the rounding of
        the printed inputs stays correct.
    """

    tag: str
    message: str
    wrong: Callable[[Params], Any]
    shapes_tolerance: bool = True


@dataclass(frozen=True)
class Exercise:
    """One graded exercise.

    Parameters
    ----------
    id : str
        Globally unique, lower case, dotted: ``"rot.opk-matrix"``. Appears in the answer cell's
        tag ``answer:ID``, in ``check("ID")`` and as a gradebook column.
    points : float
        Points for a correct answer.
    title, statement : str
        Heading and task text (Markdown). ``{name}`` fields are filled from the student's
        parameters when :func:`photolib.grading.task` prints the statement.
    kind : str
        One of :data:`KINDS`.
    answer : str
        Name of the notebook variable (or function) that holds the answer.
    params_name : str
        Name of the notebook variable that holds the task's parameters: the master's task
        cell is ``params_name = task("ID")`` (``assign`` refuses any other), and
        :func:`~photolib.grading.task` prints "Your numbers are in params_name: …". Unique
        within the chapter (:func:`photolib.grading.exercises.chapters` checks), so that
        every task keeps its own numbers whatever order the cells run in. Default:
        ``p_`` and the id's last part (``"t.dlt-vector"`` -> ``p_dlt_vector``).
    parameters : callable
        ``parameters(rng)`` draws the variant from a ``numpy.random.Generator``; values should
        be rounded as printed, so student and reference compute with the same numbers.
    reference : callable
        ``reference(params)`` returns the correct answer (for ``kind="function"``: a function).
    rtol, atol : float
        Tolerances of numbers and arrays; ``atol`` is also the tolerance of matrix entries.
    tolerance : callable or ``PRINTED``, optional
        ``tolerance(params) -> (rtol, atol)`` for tolerances that depend on the variant, e.g.
        from error propagation (:func:`photolib.grading.judge.propagated_atol`).
        :data:`PRINTED` derives it from the statement as printed: every float input is
        rounded to its last printed digit, so the answer may differ by what half a unit of
        each digit changes (propagated, per entry and, for functions, per test input), plus
        float32 (rtol 1e-6), but never so much that a declared or generic mistake comes
        within reach (:func:`photolib.grading.judge.printed_tolerance`).
    mistakes : tuple of Mistake
        Exercise-specific mistakes, tried before the generic ones of the answer kind.
    cases : callable, optional
        For functions: ``cases(rng, params)`` returns a list of argument tuples. The public
        check and the grader call it with different generators; the grader's inputs stay hidden.
    symbols : tuple of str
        Symbol names allowed in formula strings (``kind="expression"``).
    positive : tuple of str
        ``expression`` only: symbols that are positive in the exercise (lengths, f-numbers);
        they are compared over positive values, every other symbol over all real values
        (angles are signed), so ``Abs(sin(omega))`` does not pass for ``sin(omega)``.
    choices : dict, optional
        For multiple choice: option key -> option text.
    exact : tuple of str
        Float parameters that are exact as printed, not measurements rounded to their last
        digit (a significance level α = 0.05, a stated requirement): the rounding of the
        printed inputs (``tolerance=PRINTED`` and the policy's tests) leaves them alone.
    scenario : str
        Multi-step exercises: the id of the scenario this exercise is one step of (by
        convention the id of its first step). Every step of a scenario draws its parameters
        from the same seed (:func:`photolib.grading.variants.rng_for` with the scenario id),
        so the steps share the student's numbers; each step is graded on its own (its own id,
        answer and gradebook column), and a later step's parameters carry the correct result
        of the earlier steps it builds on, so that a wrong first step does not hide a right
        method. Empty for a single-step exercise. :func:`photolib.grading.exercises.chapters`
        checks that a scenario's steps are in one chapter and titled "Step k of n".
    precision : str
        The precision asked, in the words of a statement (``"to 0.01 mm"``, ``"to 3
        significant digits"``), where the one derived from the tolerance
        (:func:`photolib.grading.precision.derived`) does not fit. A statement that states its
        precision in words needs neither: :func:`~photolib.grading.task` then adds no line.
    unit : str
        The answer's length unit (``"mm"``, ``"µm"``, ``"m"``) where the statement does not
        name it as "in mm": the unit hints speak of it (µm for mm where the answer is in mm).
    few_variants : str
        Why this exercise cannot draw :data:`MIN_VARIANTS` distinct variants (a multiple
        choice has as many correct answers as options); empty when it does. The tests count
        the distinct variants of every exercise and hold it to this.
    """

    id: str
    points: float
    title: str
    statement: str
    kind: str
    answer: str
    parameters: Callable[[Any], dict]
    reference: Callable[[Params], Any]
    params_name: str = ""
    rtol: float = 1e-6
    atol: float = 1e-9
    tolerance: Callable[[Params], tuple] | None = None
    mistakes: tuple = ()
    cases: Callable[[Any, Params], list] | None = None
    symbols: tuple = ()
    positive: tuple = ()
    choices: dict = field(default_factory=dict)
    exact: tuple = ()
    scenario: str = ""
    few_variants: str = ""
    precision: str = ""
    unit: str = ""

    def __post_init__(self):
        if not _ID.match(self.id):
            raise ValueError(f"exercise id {self.id!r} must be lower case words joined by . or -")
        if self.kind not in KINDS:
            raise ValueError(f"exercise {self.id}: kind {self.kind!r} is not one of {list(KINDS)}")
        if not _NAME.match(self.answer):
            raise ValueError(f"exercise {self.id}: answer {self.answer!r} is not a Python name")
        if not self.params_name:
            object.__setattr__(self, "params_name",
                               "p_" + re.sub(r"\W", "_", self.id.rsplit(".", 1)[-1]))
        if (not _NAME.match(self.params_name) or keyword.iskeyword(self.params_name)
                or self.params_name in RESERVED_NAMES):
            raise ValueError(f"exercise {self.id}: params_name {self.params_name!r} is not a "
                             f"Python name free for a task's parameters")
        if self.params_name == self.answer:
            raise ValueError(f"exercise {self.id}: params_name and answer are both "
                             f"{self.answer!r}")
        if not self.points > 0:
            raise ValueError(f"exercise {self.id}: points must be positive, got {self.points!r}")
        if self.kind == "function" and self.cases is None:
            raise ValueError(f"exercise {self.id}: a function exercise needs cases")
        if self.kind == "choice" and not self.choices:
            raise ValueError(f"exercise {self.id}: a multiple choice needs choices")
        if self.scenario and not _ID.match(self.scenario):
            raise ValueError(f"exercise {self.id}: scenario {self.scenario!r} must be an "
                             f"exercise id")
        if isinstance(self.tolerance, str) and self.tolerance != PRINTED:
            raise ValueError(f"exercise {self.id}: tolerance {self.tolerance!r} is neither a "
                             f"function nor {PRINTED!r}")

    @property
    def seed_id(self) -> str:
        """The id the variant's generator is seeded with: the scenario's, else the exercise's."""
        return self.scenario or self.id

    def tolerances(self, params: Params) -> tuple[float, float]:
        """``(rtol, atol)`` for this variant (``atol`` may be an array, one per entry).

        For a function exercise with ``tolerance=PRINTED`` this is ``(rtol, floor)``: the
        absolute tolerance depends on the test inputs, and
        :func:`photolib.grading.judge.judge` widens it per input.
        """
        if self.tolerance == PRINTED:
            from photolib.grading.judge import printed_tolerance
            return printed_tolerance(self)(params)
        return self.tolerance(params) if self.tolerance else (self.rtol, self.atol)
