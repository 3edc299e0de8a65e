"""Immediate feedback in the student's notebook: :func:`task` and :func:`check`.

Both read ``STUDENT_ID`` and the answer variables from the notebook's namespace. ``check``
judges exactly as the grader does (same decoding, same judge, same hints), but in the
student's own kernel, so it is feedback, not a grade: the grader re-runs the notebook in a
sandbox and judges in its own process. The public test inputs of function exercises differ
from the grader's hidden ones, and no message shows test inputs.
"""

from __future__ import annotations

import ast
import re
import string
import sys

import numpy as np

from photolib.grading.encode import (NOT_ANSWERED, Raised, Unsupported, decode_value,
                                      decoded_or_unsupported, encode_value)
from photolib.grading.exercises import exercise as _exercise
from photolib.grading.judge import FunctionOutputs, judge
from photolib.grading.spec import Params
from photolib.grading.variants import rng_for

__all__ = ["CellLog", "IssuedParams", "cell_log", "check", "function_outputs",
           "parameters_for", "reference_outputs", "task"]


def _shell():
    """The IPython shell running the current cell, or None outside IPython."""
    try:
        return get_ipython()        # IPython puts it into builtins while a cell runs
    except NameError:
        return None


def _namespace() -> dict:
    ip = _shell()
    return ip.user_ns if ip is not None else vars(sys.modules["__main__"])


def _student_id(ns: dict) -> str:
    sid = ns.get("STUDENT_ID", "")
    return sid if isinstance(sid, str) else str(sid)


#: what task() and check() say, instead of numbers, while STUDENT_ID is empty
NO_STUDENT_ID = ("STUDENT_ID is empty: set it in the first cell to your student id, then run "
                 "the notebook again (your numbers depend on it; no numbers are issued without it).")


class StudentIdMissing(RuntimeError):
    """Raised by the parameters of a task read while ``STUDENT_ID`` is empty."""


class NoParameters:
    """What :func:`task` returns while ``STUDENT_ID`` is empty: any parameter read raises.

    >>> NoParameters().c_mm
    Traceback (most recent call last):
    ...
    photolib.grading.notebook.StudentIdMissing: STUDENT_ID is empty: ...
    """

    def __init__(self, exercise_id: str = ""):
        self._photolib_issued = (exercise_id, "")

    def __getattr__(self, name):
        if name.startswith("__"):
            raise AttributeError(name)
        raise StudentIdMissing(NO_STUDENT_ID)

    __getitem__ = __getattr__

    def __repr__(self):
        return "NoParameters(STUDENT_ID is empty)"


class IssuedParams(Params):
    """What :func:`task` returns: the parameters, and for which exercise and id it issued them.

    >>> p = IssuedParams({"c_mm": 153.2}, "demo.image-scale", "s1")
    >>> p.c_mm, issued_for(p)
    (153.2, ('demo.image-scale', 's1'))
    """

    def __init__(self, params, exercise_id: str, student_id: str):
        super().__init__(params)
        self._photolib_issued = (exercise_id, student_id)


def issued_for(value):
    """``(exercise id, STUDENT_ID)`` that :func:`task` issued ``value`` for, else None."""
    if type(value) in (IssuedParams, NoParameters):     # not isinstance: no user __class__
        return vars(value).get("_photolib_issued")
    return None


def parameters_for(exercise, student_id: str) -> Params:
    """The variant of ``exercise`` for ``student_id``."""
    return Params(exercise.parameters(rng_for(student_id, exercise.seed_id)))


def _where_line(ex, params) -> str:
    """The line under the statement saying where the numbers are: ``p_opk.omega_gon`` …"""
    name = ex.params_name
    if not params:
        return f"This task has no numbers of its own ({name} is empty)."
    shown = []
    for _, field, _, _ in string.Formatter().parse(ex.statement):
        key = field and re.match(r"\w+", field).group()
        value = params.get(key) if key else None
        if (key not in shown and not isinstance(value, bool)
                and isinstance(value, (int, float, list))):
            shown.append(key)
    if re.search(rf"\b{name}\.\w", ex.statement):
        return f"Your numbers are in {name}."
    if not shown:
        return f"This task's values are in {name}."
    return f"Your numbers are in {name}: " + ", ".join(f"{name}.{k}" for k in shown) + "."


def task(exercise_id: str) -> Params | NoParameters:
    """Print the exercise with this student's numbers and return them.

    While ``STUDENT_ID`` is empty it prints one line saying so and issues no numbers: the
    statement is not printed and the returned :class:`NoParameters` raises on any read, so no
    one works on the numbers of the empty id (which are nobody's and graded as nobody's).

    Returns
    -------
    IssuedParams
        The parameters, readable as attributes (``p_opk.omega_gon``); assign them to the
        exercise's ``params_name``, which the printed text names.
    """
    cell_log()
    ex = _exercise(exercise_id)
    sid = _student_id(_namespace())
    if not sid.strip():
        print(f"✋ {ex.id}: {NO_STUDENT_ID}")
        return NoParameters(ex.id)
    params = parameters_for(ex, sid)
    _show_statement(ex, params)
    return IssuedParams(params, ex.id, sid)


def precision_line(ex, params) -> str:
    """The line stating the precision asked, or ``""`` where the statement states it in
    words (or there is no number to round: a formula, an option)."""
    from photolib.grading.precision import for_variant
    text = ex.statement.format(**params)
    precision, in_words = for_variant(ex, params, text)
    if in_words:
        return ""
    if ex.kind == "function":
        rtol, atol = ex.tolerances(params)
        if rtol > 0:
            digits = max(1, round(-np.log10(rtol)))
            within = f"to about {digits} significant digits"
        else:
            within = f"to within {float(np.min(atol)):.3g} (absolute)"
        return (f"Your function's results are compared with the reference {within}: return "
                f"them unrounded.")
    if precision is None or not precision.value:
        return ""
    if precision.kind == "whole":
        return f"Give {ex.answer} as a whole number."
    return f"Give {ex.answer} {precision.text()} (or more precisely)."


def statement_texts(ex, params) -> tuple[str, str]:
    """``(markdown, plain)``: what :func:`task` shows in a notebook and elsewhere."""
    from photolib.grading.statement import render
    unit = "point" if ex.points == 1 else "points"
    where = _where_line(ex, params)
    precision = precision_line(ex, params)
    plain = (f"{ex.id} ({ex.points:g} {unit}) {ex.title}\n{ex.statement.format(**params)}\n"
             + (f"{precision}\n" if precision else "") + where)
    markdown = (f"**{ex.title}** &nbsp;({ex.points:g} {unit}, `{ex.id}`)\n\n"
                f"{render(ex.statement, params)}\n\n"
                + (f"{precision}  \n" if precision else "")
                + re.sub(r"\b(p_\w+(?:\.\w+)?)", r"`\1`", where))
    return markdown, plain


def _show_statement(ex, params) -> None:
    """Display the statement as Markdown in IPython (plain text as the fallback), else print."""
    markdown, plain = statement_texts(ex, params)
    if _shell() is None:
        print(plain)
        return
    from IPython.display import display
    display({"text/markdown": markdown, "text/plain": plain}, raw=True)


def function_outputs(func, cases) -> FunctionOutputs:
    """Call ``func`` on each argument tuple; outputs as data (encoded then decoded)."""
    outputs = []
    for args in cases:
        try:
            value = func(*args)
        except NotImplementedError:
            value = ...                 # untouched, as the grader's extraction reports it
        except TimeoutError as exc:
            return FunctionOutputs((), f"your function raised {type(exc).__name__}: {exc}")
        except Exception as exc:  # noqa: BLE001 - the student's function may raise anything
            outputs.append(Raised.of(exc))  # judged: right only where the reference raises
            continue
        outputs.append(decode_value(encode_value(value)))
    return FunctionOutputs(tuple(outputs))


def reference_outputs(cases):
    """``outputs_of`` for :func:`~photolib.grading.judge.judge`: any function on ``cases``.

    Where the function raises ``ValueError`` (the reference on a degenerate input, or a
    mistaken implementation) the output is :class:`~photolib.grading.encode.Raised`.
    """
    def one(func, args):
        try:
            return decode_value(encode_value(func(*args)))
        except ValueError as exc:
            return Raised.of(exc)

    def outputs_of(func):
        return tuple(one(func, args) for args in cases)
    return outputs_of


def _read(value):
    """``value`` as the grader reads it, including what it makes of an unreadable one.

    The grader turns an answer its encoder or decoder rejects (``sympy.nan``, ``Max(a, b)``,
    an int of 400 digits) into :class:`~photolib.grading.encode.Unsupported` with the reason
    (:func:`photolib.grading.extract.decode_item`), which the judge then calls wrong; ``check``
    says the same, with the same words.
    """
    try:
        data = encode_value(value)
    except Exception as exc:  # noqa: BLE001 - the grader's kernel reports the type only
        return Unsupported(f"unreadable answer (encoding failed with {type(exc).__name__})")
    return decoded_or_unsupported(lambda: decode_value(data))


def check(exercise_id: str) -> None:
    """Judge the current answer of ``exercise_id`` and print one line of feedback.

    While ``STUDENT_ID`` is empty an answer is not judged (it would be judged against the
    numbers of the empty id, which are nobody's): check says so instead. Nor is an answer
    that the notebook did not just compute (in IPython, see :class:`CellLog`): the cell that
    sets it raised, it was computed from a value whose cell raised or from numbers issued for
    another ``STUDENT_ID``, or the task's numbers are for another ``STUDENT_ID``; check says
    which cell to run again.
    """
    try:
        ex = _exercise(exercise_id)
    except KeyError as exc:
        print(f"check: {exc.args[0]}")
        return
    ns = _namespace()
    sid = _student_id(ns)
    stale = _stale(ex, ns, sid) if sid.strip() else None
    if stale:
        print(f"✋ {ex.id}: {stale}")
        return
    params = parameters_for(ex, sid)
    value = ns.get(ex.answer, None)
    outputs_of = None
    if ex.kind == "function":
        if not callable(value):
            answer = NOT_ANSWERED
        else:
            cases = ex.cases(rng_for(sid, ex.id, "public"), params)
            answer = function_outputs(value, cases)
            outputs_of = reference_outputs(cases)
    else:
        answer = _read(value)
    verdict = judge(ex, params, answer, outputs_of)
    if not sid.strip() and verdict.status != "not-answered":    # judged against nobody's numbers
        print(f"✋ {ex.id}: {NO_STUDENT_ID}")
        return
    mark = {"correct": "✔", "not-answered": "…"}.get(verdict.status, "✘")
    print(f"{mark} {ex.id}: {verdict.message}")


# -- what ran: names assigned by cells that raised, and what an answer was computed from ------
_LATE = (ast.FunctionDef, ast.AsyncFunctionDef, ast.ClassDef, ast.Lambda)
#: cell magics whose body runs in the user's namespace (``%%time``), line magics likewise
_CELL_MAGICS, _LINE_MAGICS = {"time", "capture"}, {"time"}
_ASSIGNED_LINE = re.compile(r"^((?:[A-Za-z_]\w*\s*,\s*)*[A-Za-z_]\w*)\s*"
                            r"(?::[^=]*)?(?:[-+*/%&|^@]|//|\*\*|<<|>>)?=(?!=)")
_DEF_LINE = re.compile(r"^(?:async\s+)?(?:def|class)\s+([A-Za-z_]\w*)")


class _Cell:
    """The names one cell assigns and reads, from its source (:func:`_analyse`)."""

    def __init__(self):
        self.assigned: set[str] = set()     # module-level names the cell binds
        self.reads: set[str] = set()        # names read while the cell runs
        self.late: dict[str, set] = {}      # function or class -> names its body reads when called

    def walk(self, node):
        if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef, ast.ClassDef)):
            self.assigned.add(node.name)
            eager = node.decorator_list + (node.bases + [k.value for k in node.keywords]
                                           if isinstance(node, ast.ClassDef) else
                                           node.args.defaults
                                           + [d for d in node.args.kw_defaults if d])
            for child in eager:
                self.walk(child)
            self.late[node.name] = _late_reads(node)
            return
        if isinstance(node, ast.Lambda):
            return                          # its body runs when called
        if (isinstance(node, ast.Assign) and isinstance(node.value, ast.Lambda)
                and all(isinstance(t, ast.Name) for t in node.targets)):
            for target in node.targets:
                self.assigned.add(target.id)
                self.late[target.id] = _late_reads(node.value)
            return
        if isinstance(node, (ast.ListComp, ast.SetComp, ast.DictComp, ast.GeneratorExp)):
            local = {n.id for g in node.generators for n in ast.walk(g.target)
                     if isinstance(n, ast.Name)}
            self.reads |= _loads([node]) - local
            return
        if isinstance(node, ast.Name):
            (self.assigned if isinstance(node.ctx, ast.Store) else self.reads).add(node.id)
        elif isinstance(node, (ast.Import, ast.ImportFrom)):
            for alias in node.names:
                if alias.name != "*":
                    self.assigned.add(alias.asname or alias.name.split(".")[0])
        elif isinstance(node, ast.ExceptHandler) and node.name:
            self.assigned.add(node.name)
        elif isinstance(node, (ast.MatchAs, ast.MatchStar)) and node.name:
            self.assigned.add(node.name)
        elif isinstance(node, ast.AugAssign) and isinstance(node.target, ast.Name):
            self.reads.add(node.target.id)
        elif isinstance(node, ast.Call):
            self._magic(node)
        for child in ast.iter_child_nodes(node):
            self.walk(child)

    def _magic(self, call):
        """``get_ipython().run_cell_magic('time', '', body)``: the body's names count too."""
        func = call.func
        if not (isinstance(func, ast.Attribute) and func.attr in ("run_cell_magic",
                                                                  "run_line_magic")):
            return
        args = [a.value if isinstance(a, ast.Constant) else None for a in call.args]
        if func.attr == "run_cell_magic" and len(args) == 3 and args[0] in _CELL_MAGICS:
            body = args[2]
        elif func.attr == "run_line_magic" and len(args) == 2 and args[0] in _LINE_MAGICS:
            body = args[1]
        else:
            return
        if isinstance(body, str):
            inner = _analyse(body)
            self.assigned |= inner.assigned
            self.reads |= inner.reads
            self.late.update(inner.late)


def _loads(nodes) -> set:
    return {n.id for node in nodes for n in ast.walk(node)
            if isinstance(n, ast.Name) and isinstance(n.ctx, ast.Load)}


def _late_reads(node) -> set:
    """The global names a function, lambda or class body reads: its loads less its locals."""
    body = [node.body] if isinstance(node, ast.Lambda) else node.body
    local, declared = set(), set()
    if not isinstance(node, ast.ClassDef):
        a = node.args
        local |= {x.arg for x in a.posonlyargs + a.args + a.kwonlyargs}
        local |= {x.arg for x in (a.vararg, a.kwarg) if x is not None}
    for sub in (n for part in body for n in ast.walk(part)):
        if isinstance(sub, ast.Name) and not isinstance(sub.ctx, ast.Load):
            local.add(sub.id)
        elif isinstance(sub, (ast.FunctionDef, ast.AsyncFunctionDef, ast.ClassDef)):
            local.add(sub.name)
        elif isinstance(sub, (ast.Import, ast.ImportFrom)):
            local |= {a.asname or a.name.split(".")[0] for a in sub.names}
        elif isinstance(sub, (ast.Global, ast.Nonlocal)):
            declared |= set(sub.names)
    return _loads(body) - (local - declared)


def _analyse(source: str) -> _Cell:
    """What a cell's (transformed) source assigns and reads.

    A cell that is not valid Python ran no line: its assignments are read from the lines
    that start in column 0 (``name = ...``, ``a, b = ...``, ``def name``).
    """
    cell = _Cell()
    try:
        tree = ast.parse(source)
    except (SyntaxError, ValueError):
        for line in source.splitlines():
            match = _DEF_LINE.match(line) or _ASSIGNED_LINE.match(line)
            if match:
                cell.assigned.update(n.strip() for n in match.group(1).split(","))
        return cell
    for node in tree.body:
        cell.walk(node)
    return cell


class CellLog:
    """What :func:`check` knows about the cells run in this kernel (IPython only).

    Registered as a ``post_run_cell`` callback, once per shell (:func:`cell_log`). For each
    cell that ran it parses the source with :mod:`ast` and notes, per module-level name the
    cell assigns (assignments, ``def``, ``import``, ``for`` targets …):

    - ``failed[name] = (root, error)``: the cell raised (``root`` is ``name``), or it ran but
      read a name whose cell had raised (``root`` is that name, so ``x = f(y)`` after a
      failing ``y = ...`` is not trusted either). A later successful cell assigning ``name``
      clears it;
    - ``basis[name]``: for each parameter object (:class:`IssuedParams`) the value was
      computed from, directly or through other names, which exercise and ``STUDENT_ID``
      :func:`task` issued it for;
    - ``late[name]``: for a function (or lambda, class), the names its body reads: they are
      read when it is called, so they are judged as they are when ``check`` runs.

    Nothing here changes the notebook's namespace or a grade: the grader reads the answers
    after running the notebook top to bottom and judges them in its own process.
    """

    photolib_cell_log = 1       # the marker by which an earlier registration is recognised

    def __init__(self, shell):
        self.shell = shell
        self.failed: dict[str, tuple] = {}
        self.basis: dict[str, dict] = {}
        self.late: dict[str, set] = {}

    def post_run_cell(self, result) -> None:
        try:
            self.record(result)
        except Exception:  # noqa: BLE001, S110 - feedback bookkeeping never disturbs a cell
            pass

    def record(self, result) -> None:
        info = result.info
        source = getattr(info, "transformed_cell", None) or getattr(info, "raw_cell", "") or ""
        cell = _analyse(source)
        error = result.error_in_exec or result.error_before_exec
        if error is not None:
            for name in cell.assigned:
                self.failed[name] = (name, type(error).__name__)
            return
        ns = self.shell.user_ns
        inputs = cell.reads - cell.assigned
        root = next((self.failed[n] for n in sorted(inputs) if n in self.failed), None)
        basis = {}
        for name in inputs:
            basis.update(self.basis_of(name, ns))
        for name in cell.assigned:
            if root is None:
                self.failed.pop(name, None)
            else:
                self.failed[name] = root
            if name in cell.late:
                self.late[name] = cell.late[name]
                self.basis.pop(name, None)
            else:
                self.late.pop(name, None)
                self.basis[name] = basis

    def basis_of(self, name: str, ns: dict, seen=None) -> dict:
        """The parameter objects the current value of ``name`` was computed from."""
        record = issued_for(ns.get(name))
        if record is not None:
            return {name: record}
        if name in self.late:
            seen = set() if seen is None else seen
            if name in seen:
                return {}
            seen.add(name)
            out = {}
            for read in self.late[name]:
                out.update(self.basis_of(read, ns, seen))
            return out
        return dict(self.basis.get(name, {}))

    def problem(self, name: str, ns: dict, seen=None) -> str | None:
        """Why the value of ``name`` is not what the notebook computes now, or None."""
        seen = set() if seen is None else seen
        if name in seen:
            return None
        seen.add(name)
        if name in self.failed:
            root, error = self.failed[name]
            if root == name:
                return f"the cell that sets {name} raised an error ({error}); run it again"
            return (f"{name} was computed from {root} after the cell that sets {root} had "
                    f"raised an error ({error}); run that cell again, then the cells that "
                    f"compute {name} from it")
        if name in self.late:                   # a function reads these when it is called
            for read in sorted(self.late[name]):
                issue = self.problem(read, ns, seen)
                if issue:
                    return f"{name} uses {read}: {issue}"
            return None
        for pname, record in sorted(self.basis.get(name, {}).items()):
            if issued_for(ns.get(pname)) != record:
                return (f"{name} was computed from the numbers {pname} held before (issued by "
                        f"task({record[0]!r}) for STUDENT_ID {record[1]!r}); run the cell that "
                        f"sets {name} again")
        return None


def cell_log():
    """The :class:`CellLog` of the running IPython shell, registered once; None outside IPython.

    Idempotent: a log already registered (also by an earlier import of this module, e.g.
    after a reload) is found by its marker among the ``post_run_cell`` callbacks and reused.
    """
    ip = _shell()
    events = getattr(ip, "events", None)
    if events is None:
        return None
    for callback in events.callbacks.get("post_run_cell", []):
        owner = getattr(callback, "__self__", None)
        if getattr(owner, "photolib_cell_log", None) == CellLog.photolib_cell_log:
            return owner
    log = CellLog(ip)
    events.register("post_run_cell", log.post_run_cell)
    return log


def _stale(ex, ns: dict, sid: str) -> str | None:
    """Why ``check`` should not judge the answer of ``ex`` now, or None."""
    log = cell_log()
    if log is None:
        return None
    pname = ex.params_name
    record = issued_for(ns.get(pname))
    if record is not None and record[0] == ex.id and record[1] != sid:
        when = ("while STUDENT_ID was empty" if not record[1]
                else f"for STUDENT_ID {record[1]!r}")
        return (f"{pname} holds the numbers issued {when}: run the task cell "
                f"({pname} = task({ex.id!r})) again, then the cell that sets {ex.answer}")
    return log.problem(ex.answer, ns)


cell_log()      # a kernel that imports photolib.grading notes every cell from here on
