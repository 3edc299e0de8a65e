"""Records of the errata catalogue and how their verdicts are computed.

A :class:`Record` holds the printed versions of one formula, example, text or figure, and
a derivation from :mod:`photolib.derive`. Each printed version has a :class:`VersionSpec`
with the verdict the catalogue states for it; :meth:`Record.evaluate` recomputes that
verdict from the evidence every time (never from the printed "richtig" version):

* formula versions are compared with the derivation by :func:`photolib.symcheck.equivalent`:
  ``equal`` → ``right``; equal only after the version's ``condition`` substitution →
  ``right-under-condition: <text>``; otherwise ``wrong`` with the counterexample;
* examples and text statements have a ``check`` function that recomputes the numbers
  from the printed inputs and returns an :class:`Evidence`;
* figures and items without printed data are ``not-checkable: <why>``.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any

import sympy as sp

from photolib.symcheck import equivalent

VERDICT_PREFIXES = ("right", "wrong", "right-under-condition: ", "not-checkable: ")
#: what a source can claim of a printed version; every :class:`VersionSpec` must state one
CLAIMS = ("right", "wrong", "right-under-condition")


@dataclass
class Evidence:
    """What a check found: the verdict string and the numbers behind it.

    Attributes
    ----------
    verdict : str
        ``right``, ``wrong``, ``right-under-condition: <condition>`` or ``not-checkable: <why>``.
    detail : str
        One line of reason.
    counterexample : dict or None
        Symbol → value where a wrong version differs from the derivation.
    values : tuple or None
        (printed value, derived value) at the counterexample.
    table : list of tuple
        For examples: rows ``(quantity, printed, recomputed, tolerance, agrees)``.
    """

    verdict: str
    detail: str = ""
    counterexample: dict | None = None
    values: tuple | None = None
    table: list = field(default_factory=list)


@dataclass
class VersionSpec:
    """One printed version ("printed", "old" or "corrected") and its stated verdict.

    ``expr`` is the transcription (SymPy, or a callable returning it); ``condition`` a
    substitution under which it equals the derivation, described by ``condition_text``;
    ``check`` replaces the formula comparison for examples and text; ``claim`` is what the
    source says of the version (``reading=True``: the source prints a sentence and ``expr`` is
    the catalogue's reading of it, not a transcription): ``right``/``wrong`` (the errata list's "richtig"/"alte
    Fassung"; the other sources claim everything they print right), or
    ``right-under-condition`` where the source itself adds the condition. It is required:
    a spec without a claim raises ``ValueError``, so :meth:`Record.differs_from_source`
    sees every version.

    >>> VersionSpec("right")
    Traceback (most recent call last):
    ...
    ValueError: missing or bad claim ''; must be one of ('right', 'wrong', 'right-under-condition')
    """

    verdict: str
    expr: Any = None
    condition: Any = None
    condition_text: str = ""
    check: Callable[[], Evidence] | None = None
    claim: str = ""
    target: Any = None              # overrides the record's derivation for this version
    reading: bool = False           # expr is the catalogue's reading of a sentence, not a print

    def __post_init__(self):
        if not any(self.verdict == p or (p.endswith(": ") and self.verdict.startswith(p))
                   for p in VERDICT_PREFIXES):
            raise ValueError(f"bad verdict {self.verdict!r}; must start with one of "
                             f"{VERDICT_PREFIXES}")
        if self.claim not in CLAIMS:
            raise ValueError(f"missing or bad claim {self.claim!r}; must be one of {CLAIMS}")


def _resolve(v):
    return v() if callable(v) else v


@dataclass
class Record:
    """One catalogue entry. See the module docstring."""

    id: str
    source: str
    item: str
    kind: str                       # "formula", "example", "text" or "figure"
    specs: dict
    derivation: Any = None          # SymPy object or callable returning it
    given: Any = None               # substitution (or callable) giving printed symbols a meaning
    steps: tuple = ()
    note: str = ""
    domain: Any = None              # symbols_domain for the sampling (or callable)
    symbols: Any = None             # name -> Symbol for check-formula (or callable)
    _cache: dict = field(default_factory=dict, repr=False)

    @property
    def versions(self) -> dict:
        """``{"printed" | "old" | "corrected": SymPy expression}`` of the formula versions."""
        out = {}
        for name, spec in self.specs.items():
            e = _resolve(spec.expr)
            if e is not None:
                out[name] = e
        return out

    def derived(self):
        """The derivation (SymPy), computed once per process."""
        if "derived" not in self._cache:
            self._cache["derived"] = _resolve(self.derivation)
        return self._cache["derived"]

    def given_substitution(self) -> dict:
        if "given" not in self._cache:
            self._cache["given"] = dict(_resolve(self.given) or {})
        return self._cache["given"]

    def symbol_table(self) -> dict:
        """Names usable in ``check-formula`` for this record."""
        table = dict(_resolve(self.symbols) or {})
        for e in list(self.versions.values()) + [self.derived()]:
            if isinstance(e, (sp.Basic, sp.MatrixBase)):
                for s in e.free_symbols:
                    table.setdefault(s.name, s)
        return table

    def compare(self, expr, condition=None, target=None):
        """``equivalent(expr with the given meanings, derivation)``."""
        given = self.given_substitution()
        if isinstance(expr, (sp.Basic, sp.MatrixBase)) and given:
            expr = expr.subs(given)
        target = self.derived() if target is None else target
        return equivalent(expr, target, symbols_domain=_resolve(self.domain),
                          assumptions=condition, time_budget=3.0, samples=8)

    def evaluate(self, name: str) -> Evidence:
        """Recompute the verdict of version ``name`` from the evidence."""
        key = ("eval", name)
        if key in self._cache:
            return self._cache[key]
        spec = self.specs[name]
        if spec.check is not None:
            ev = spec.check()
        elif spec.verdict.startswith("not-checkable"):
            ev = Evidence(spec.verdict, "no printed data to recompute")
        else:
            ev = self._formula_evidence(spec)
        self._cache[key] = ev
        return ev

    def _formula_evidence(self, spec: VersionSpec) -> Evidence:
        expr = _resolve(spec.expr)
        cond = _resolve(spec.condition)
        v = self.compare(expr, cond, _resolve(spec.target))
        if v.kind == "equal":
            return Evidence("right", f"equal to the derivation ({v.method})")
        if v.kind == "equal-under-condition":
            text = spec.condition_text or str(v.condition)
            return Evidence(f"right-under-condition: {text}",
                            f"differs in general, equal under the condition ({v.method})",
                            v.counterexample, v.values)
        if v.kind == "not-equal":
            return Evidence("wrong", f"differs from the derivation ({v.method})",
                            v.counterexample, v.values)
        return Evidence(f"not-checkable: comparison undecided ({v.detail})", v.detail)

    @property
    def verdicts(self) -> dict:
        """``{version: verdict string}``, recomputed."""
        return {name: self.evaluate(name).verdict for name in self.specs}

    @property
    def stated(self) -> dict:
        """``{version: verdict string}`` as stated in the catalogue (tests compare)."""
        return {name: spec.verdict for name, spec in self.specs.items()}

    def differs_from_source(self) -> dict:
        """``{version: (claim, verdict)}`` of the versions whose verdict kind differs from the
        source's claim (every version has a claim, see :class:`VersionSpec`)."""
        out = {}
        for name, spec in self.specs.items():
            kind = spec.verdict.split(":")[0]
            if kind != spec.claim:
                out[name] = (spec.claim, spec.verdict)
        return out


def formula(id, source, item, specs, derivation, **kw) -> Record:
    return Record(id=id, source=source, item=item, kind="formula", specs=specs,
                  derivation=derivation, **kw)


def figure(id, source, item, why, *, claim) -> Record:
    """A figure or text item that cannot be checked by computation (``claim`` required)."""
    return Record(id=id, source=source, item=item, kind="figure",
                  specs={"corrected": VersionSpec(f"not-checkable: {why}", claim=claim)},
                  note=why)


def numbers_evidence(rows, reason_ok="", reason_bad="", condition="") -> Evidence:
    """Evidence for an example from rows ``(name, printed, recomputed, tolerance)``."""
    table = []
    bad = []
    for name, printed, recomputed, tol in rows:
        agrees = abs(float(printed) - float(recomputed)) <= float(tol)
        table.append((name, float(printed), float(recomputed), float(tol), agrees))
        if not agrees:
            bad.append(f"{name}: printed {float(printed):g}, recomputed {float(recomputed):.6g}")
    if bad:
        return Evidence("wrong", reason_bad or "; ".join(bad), table=table)
    if condition:
        return Evidence(f"right-under-condition: {condition}", reason_ok, table=table)
    return Evidence("right", reason_ok or "all printed numbers recomputed", table=table)
