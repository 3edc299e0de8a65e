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

``python -m photolib check-formula`` binds the names a reader types to the record's symbols
with :meth:`Record.accepted_names`: the catalogue's own names (``k_x``, ``z_p``, ``kappa``) and
the textbook's spellings of them (``kx``, ``zp``, ``κ``; see :func:`spellings`), plus the
aliases a record lists itself (``Record.aliases``).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field
import re
import unicodedata
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


#: Greek letter names as SymPy prints them → the letters (Python accepts both in a formula)
GREEK = {
    "alpha": "α", "beta": "β", "gamma": "γ", "delta": "δ", "epsilon": "ε", "zeta": "ζ",
    "eta": "η", "theta": "θ", "iota": "ι", "kappa": "κ", "lamda": "λ", "mu": "μ", "nu": "ν",
    "xi": "ξ", "omicron": "ο", "rho": "ρ", "sigma": "σ", "tau": "τ", "upsilon": "υ",
    "phi": "φ", "chi": "χ", "psi": "ψ", "omega": "ω",
    "Gamma": "Γ", "Delta": "Δ", "Theta": "Θ", "Lambda": "Λ", "Xi": "Ξ", "Sigma": "Σ",
    "Phi": "Φ", "Psi": "Ψ", "Omega": "Ω",
}
_LETTER_NAME = {v: k for k, v in GREEK.items()}
_MACRON = "\u0304"      # combining macron: s̄ for s_bar


def _token_variants(token: str) -> set:
    """Spellings of one ``_``-separated part of a name: as is, Greek letter ↔ name."""
    out = {token}
    m = re.fullmatch(r"([A-Za-z]+)(\d*)", token)
    if m and m.group(1) in GREEK:                       # kappa → κ, xi0 → ξ0
        out.add(GREEK[m.group(1)] + m.group(2))
    m = re.fullmatch(r"(\w)(\d*)", token)
    if m and m.group(1) in _LETTER_NAME:                # κ → kappa
        out.add(_LETTER_NAME[m.group(1)] + m.group(2))
    return out


def spellings(name: str) -> set:
    """The textbook spellings of a catalogue symbol name (the name itself included).

    Why: the catalogue names symbols so that SymPy prints them unambiguously (``k_x``,
    ``z_p`` for z', ``kappa``, ``s_bar``); a reader types them as the book prints them:
    ``kx``, ``zp`` (or ``z'``, which the parser reads as ``z_p``), ``κ``, ``s̄``, ``r_11``.
    The rules: the ``_`` between parts may be left out; a Greek part may be typed as the
    letter or as its name; ``_bar`` may be a macron over the letter; digits after letters
    may follow a ``_`` (``X_0`` for ``X0``). All spellings are NFKC-normalised, as Python
    normalises the identifiers of a typed formula (so ``ϕ`` is read as ``φ``).

    >>> sorted(spellings("k_x"))
    ['k_x', 'kx']
    >>> sorted(spellings("kappa"))
    ['kappa', 'κ']
    >>> sorted(spellings("Delta_xi"))
    ['Delta_xi', 'Delta_ξ', 'Deltaxi', 'Deltaξ', 'Δ_xi', 'Δ_ξ', 'Δxi', 'Δξ']
    >>> sorted(spellings("r11"))
    ['r11', 'r_11']
    """
    parts = name.split("_")
    variants = [""]
    for i, part in enumerate(parts):
        if part == "bar" and i > 0:                     # s_bar → s̄, sbar, s_bar
            variants = [v + sep + alt for v in variants for sep, alt in
                        (("", _MACRON), ("_", "bar"), ("", "bar"))
                        if not (alt == _MACRON and len(re.split(r"_", v)[-1]) != 1)]
            continue
        seps = ("",) if i == 0 else ("_", "")
        variants = [v + sep + t for v in variants for sep in seps
                    for t in sorted(_token_variants(part))]
    out = set(variants)
    m = re.fullmatch(r"([A-Za-z]+)(\d+)", name)
    if m:                                               # r11 → r_11, X0 → X_0
        out.add(f"{m.group(1)}_{m.group(2)}")
    return {unicodedata.normalize("NFKC", v) for v in out if v.isidentifier()}


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
    aliases: Any = None             # textbook spelling -> symbol name, beside spellings()
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

    def accepted_names(self) -> dict:
        """``{spelling: Symbol}``: every name ``check-formula`` binds for this record.

        The names of :meth:`symbol_table`, each symbol's textbook :func:`spellings`, and
        the record's own ``aliases`` (``{"X0_star": "X0s"}``: a spelling the rules do not
        give). A spelling that two symbols share is ambiguous and left out, and a symbol's
        own name always means that symbol.

        Raises
        ------
        ValueError
            If an alias names no symbol of the record, or is the name of another symbol.
        """
        if "accepted" in self._cache:
            return self._cache["accepted"]
        table = self.symbol_table()
        found: dict = {}
        for name, sym in table.items():
            for spelling in spellings(name):
                found.setdefault(spelling, set()).add(sym)
        out = {k: next(iter(v)) for k, v in found.items() if len(v) == 1}
        out.update(table)
        for spelling, name in dict(_resolve(self.aliases) or {}).items():
            if name not in table:
                raise ValueError(f"{self.id}: alias {spelling!r} names {name!r}, which is not a "
                                 f"symbol of the record (symbols: {sorted(table)})")
            if spelling in table and table[spelling] != table[name]:
                raise ValueError(f"{self.id}: alias {spelling!r} for {name!r} is already the "
                                 f"name of another symbol")
            out[unicodedata.normalize("NFKC", spelling)] = table[name]
        self._cache["accepted"] = out
        return out

    def expected_names(self) -> dict:
        """``{symbol name: [other accepted spellings]}``, sorted: what ``check-formula`` lists
        when a typed formula has a name the record does not know."""
        out: dict = {}
        for spelling, sym in self.accepted_names().items():
            out.setdefault(sym.name, [])
            if spelling != sym.name:
                out[sym.name].append(spelling)
            if spelling.endswith("_p") and len(spelling) > 2:   # z' is read as z_p
                out[sym.name].append(spelling[:-2] + "'")
        return {k: sorted(v) for k, v in sorted(out.items(), key=lambda kv: kv[0].lower())}

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
