"""``python -m photolib check-formula`` in the textbook's language (issue 14, point 5).

A reader types a formula as the book prints it: ``kx``, ``ky``, ``z'`` or ``zp``, ``κ`` (or
``kappa``). The checker binds those spellings to the record's symbols, names the unknown ones
together with the names it accepts, states the condition first for an
``equal-under-condition`` result, and prints counterexamples as short decimals.
"""

from __future__ import annotations

import re

import pytest
import sympy as sp

from photolib import errata
from photolib.errata import cli
from photolib.errata._record import Record, VersionSpec, spellings

# Luhmann 4.18b as the errata list prints it (its symbols k_x, k_y, z', κ), typed in the book's
# spellings; the corrected ("richtig") and the old bracket
BOOK_RIGHT = "zp/N*(ky/N*(ky*sin(κ) - kx*cos(κ)) + N*sin(κ))"
BOOK_OLD = "z'/N*(ky/N*(kx*cos(kappa) + ky*sin(kappa)) + N*sin(kappa))"
DECIMAL = re.compile(r"-?\d+(?:\.\d+)?(?:e[-+]?\d+)?")


def _numbers(text: str) -> list[str]:
    """The numbers after each ``=`` of a ``name = value, …`` list."""
    return [m.group(1) for m in re.finditer(r"= (\S+?)(?:,|$| )", text)]


@pytest.mark.slow
def test_book_spellings_of_the_right_formula_are_equal_under_the_condition(capsys):
    assert cli.check_formula_main([BOOK_RIGHT, "--against", "luhmann:4.18b"]) == 0
    out = capsys.readouterr().out
    lines = out.splitlines()
    # the condition first, in the first line, then the record's own wording of it
    assert lines[0] == "luhmann:4.18b: equal-under-condition: z_p = -c", out
    assert lines[1].startswith("  the record's condition: z' = −c"), out
    # no "counterexample" that reads as a failure, and no extra free symbols
    assert "counterexample" not in out and "kx" not in out.split("condition:")[0]
    assert "the condition is needed" in out


@pytest.mark.slow
def test_book_spellings_of_the_old_formula_are_not_equal_with_a_short_decimal_point(capsys):
    assert cli.check_formula_main([BOOK_OLD, "--against", "luhmann:4.18b"]) == 1
    out = capsys.readouterr().out
    assert out.startswith("luhmann:4.18b: not-equal"), out
    point = next(line for line in out.splitlines() if line.startswith("  counterexample: "))
    values = _numbers(point)
    assert len(values) == 11, point          # X, Y, Z, X0, Y0, Z0, ω, φ, κ, c, z' after 'given'
    for v in values:                         # decimals, a few significant digits, no p/q
        assert DECIMAL.fullmatch(v), v
        assert len(v.lstrip("-").replace(".", "").lstrip("0").split("e")[0]) <= cli.POINT_DIGITS
    yours, derived = out.split("values (yours, derived): ")[1].strip().split(" | ")
    assert yours != derived and len(yours) < 12 and len(derived) < 12


def test_an_unknown_symbol_is_named_with_the_names_the_record_accepts(capsys):
    typo = BOOK_RIGHT.replace("kx", "kz")
    assert cli.check_formula_main([typo, "--against", "luhmann:4.18b"]) == 2
    captured = capsys.readouterr()
    assert captured.out == ""
    err = captured.err
    assert err.startswith("luhmann:4.18b: unknown symbol kz; the record knows: "), err
    for shown in ("k_x (kx)", "k_y (ky)", "kappa (κ)", "z_p (z', zp)", "phi (φ)", "N"):
        assert shown in err, shown


def test_greek_letters_as_unicode_and_as_names_on_another_record(capsys):
    log = "-(1 - r**2/(2*{s}**2))*exp(-r**2/(2*{s}**2))/(pi*{s}**4)"
    for sigma in ("σ", "sigma"):
        assert cli.check_formula_main([log.format(s=sigma), "--against", "luhmann:5.42"]) == 0
        first = capsys.readouterr().out.splitlines()[0]
        assert first == "luhmann:5.42: equal-under-condition: K = 1/(2*pi*sigma**2)", first


def test_spellings_follow_the_rules():
    assert spellings("k_x") == {"k_x", "kx"}
    assert spellings("kappa") == {"kappa", "κ"}
    assert spellings("z_p") == {"z_p", "zp"}
    assert spellings("r11") == {"r11", "r_11"}
    assert "s\u0304" in spellings("s_bar") and "σ\u0304" in spellings("sigma_bar")
    assert "sigmā" not in spellings("sigma_bar")          # no macron over a long name's last letter
    assert "Δξ" in spellings("Delta_xi")


def test_accepted_names_of_418b_bind_the_book_spellings_to_the_record_symbols():
    rec = errata.get("luhmann:4.18b")
    names = rec.accepted_names()
    table = rec.symbol_table()
    for book, ours in (("kx", "k_x"), ("ky", "k_y"), ("zp", "z_p"), ("κ", "kappa"),
                       ("kappa", "kappa"), ("φ", "phi"), ("X_0", "X0")):
        assert names[book] is table[ours], book
    assert errata.get("luhmann:4.13").accepted_names()["X0_star"].name == "X0s"


def _toy(aliases=None, names=("ab_c", "a_bc", "k_x", "kx")):
    syms = {n: sp.Symbol(n, real=True) for n in names}
    return Record(id="toy:1", source="test", item="toy", kind="formula",
                  specs={"printed": VersionSpec("right", expr=sum(syms.values()), claim="right")},
                  derivation=sum(syms.values()), aliases=aliases)


def test_shared_spellings_are_left_out_and_own_names_win():
    names = _toy().accepted_names()
    assert "abc" not in names                      # ab_c and a_bc would both be 'abc'
    assert names["kx"].name == "kx"                # a symbol's own name means that symbol
    assert names["k_x"].name == "k_x"


def test_a_bad_alias_is_a_clear_error():
    with pytest.raises(ValueError, match=r"toy:1: alias 'q' names 'nope', which is not a symbol"):
        _toy({"q": "nope"}).accepted_names()
    with pytest.raises(ValueError, match=r"alias 'kx' for 'k_x' is already the name of another"):
        _toy({"kx": "k_x"}).accepted_names()
