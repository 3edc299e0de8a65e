"""Generate NumPy code from the SymPy derivations in :mod:`photolib.derive`.

Each derive module listed in ``photolib.derive.CODEGEN_MODULES`` exposes ``CODEGEN``, a tuple
of :class:`photolib.derive._spec.GeneratedFunction`. This module prints each one as a plain
NumPy function with common-subexpression elimination into ``photolib/_generated/<module>.py``.

The output is deterministic: CSE with canonical ordering and numbered temporaries, SymPy's
NumPy printer, arguments in the order the derivation states, and a header carrying the
SHA-256 of the derive source and of every derive module it imports (transitively, found in
the source by :func:`derive_dependencies`), so the sync test (``tests/test_codegen.py``) can regenerate
into a temporary folder and diff. ``python -m photolib codegen`` (or ``make regen``, or
``pytest --update-generated``) rewrites the committed files.
"""

from __future__ import annotations

import hashlib
import importlib
import sys
import textwrap
from pathlib import Path

import sympy as sp
from sympy.printing.numpy import NumPyPrinter
from sympy.printing.precedence import precedence

from photolib.derive import CODEGEN_MODULES

PACKAGE_DIR = Path(__file__).resolve().parent
GENERATED_DIR = PACKAGE_DIR / "_generated"
DERIVE_DIR = PACKAGE_DIR / "derive"


class _Printer(NumPyPrinter):
    """NumPy printer that writes ``np.`` instead of ``numpy.`` and plain float literals."""

    def __init__(self):
        super().__init__({"fully_qualified_modules": True, "inline": True,
                          "allow_unknown_functions": False})

    def _module_format(self, fqn, register=True):  # noqa: D401 - printer hook
        return super()._module_format(fqn, register).replace("numpy.", "np.")

    def _print_Pow(self, expr, rational=False):
        # small integer powers as products: NumPy's float ``**`` calls pow(), ~10× slower
        if expr.exp.is_Integer and 2 <= int(expr.exp) <= 4 and not expr.base.is_Number:
            base = self.parenthesize(expr.base, precedence(expr))
            return "(" + "*".join([base] * int(expr.exp)) + ")"
        return super()._print_Pow(expr, rational=rational)


def derive_dependencies(module_name: str, derive_dir: Path | str = DERIVE_DIR) -> tuple[str, ...]:
    """The ``photolib.derive`` modules a derivation imports, directly or through each other.

    Read from the source (``ast``), not by importing: every ``import photolib.derive.X`` and
    ``from photolib.derive[.X] import …`` anywhere in the module (also inside functions),
    followed transitively; ``from photolib.derive import X`` counts X when it is a module of
    ``derive_dir``, the package's ``__init__`` only for a name that is not. Returns the module
    names (``"rotation"``, ``"_spec"``, ``"__init__"``), ``module_name`` first, then sorted.
    """
    import ast

    derive_dir = Path(derive_dir)
    prefix = "photolib.derive"

    def imported(name: str) -> set[str]:
        tree = ast.parse((derive_dir / f"{name}.py").read_text(encoding="utf-8"))
        found = set()
        for node in ast.walk(tree):
            if isinstance(node, ast.Import):
                targets = [(a.name, None) for a in node.names]
            elif isinstance(node, ast.ImportFrom):
                if node.level:      # relative: from . import x, from ._spec import y
                    base = ".".join([prefix, node.module] if node.module else [prefix])
                else:
                    base = node.module or ""
                targets = [(base, a.name) for a in node.names]
            else:
                continue
            for module, attr in targets:
                if module == prefix and attr is not None:
                    sub = attr if (derive_dir / f"{attr}.py").exists() else "__init__"
                    found.add(sub)
                elif module.startswith(prefix + "."):
                    found.add(module[len(prefix) + 1:].split(".")[0])
                elif module == prefix:
                    found.add("__init__")
        return found

    seen, todo = {module_name}, [module_name]
    while todo:
        for dep in imported(todo.pop()) - seen:
            seen.add(dep)
            todo.append(dep)
    return (module_name, *sorted(seen - {module_name}))


def source_hash(module_name: str, derive_dir: Path | str = DERIVE_DIR) -> str:
    """SHA-256 over the derive module and every ``photolib.derive`` module it imports.

    The modules of :func:`derive_dependencies` in its order, each as its file name, a NUL
    byte, its source with ``\\n`` line ends and a NUL byte: a change to any of them (the
    rotation matrices that the collinearity Jacobians differentiate, the shared spec) changes
    the hash, so the sync test says the generated file is out of date.
    """
    derive_dir = Path(derive_dir)
    h = hashlib.sha256()
    for name in derive_dependencies(module_name, derive_dir):
        h.update(f"{name}.py".encode() + b"\0")
        h.update((derive_dir / f"{name}.py").read_bytes().replace(b"\r\n", b"\n") + b"\0")
    return h.hexdigest()


def render_function(fn) -> str:
    """Python source of one generated function (CSE, NumPy printer)."""
    printer = _Printer()
    exprs = fn.exprs
    temps = sp.numbered_symbols("_t")
    replacements, reduced = sp.cse(exprs, symbols=temps, order="canonical")
    args = ", ".join(str(a) for a in fn.args)
    lines = [f"def {fn.name}({args}):"]
    doc = textwrap.fill(fn.doc, width=88, initial_indent="    ", subsequent_indent="    ")
    outs = ", ".join(fn.output_names)
    lines.append('    """' + doc.strip())
    lines.append("")
    lines.append(f"    Returns ({outs}); all arguments broadcast like NumPy arrays.")
    lines.append('    """')
    for sym, expr in fn.intermediates:
        lines.append(f"    {sym} = {printer.doprint(expr)}")
    for sym, expr in replacements:
        lines.append(f"    {sym} = {printer.doprint(expr)}")
    for name, expr in zip(fn.output_names, reduced):
        code = printer.doprint(expr)
        if not expr.free_symbols:  # a constant output still has to broadcast
            code = f"np.zeros(np.broadcast({args}).shape) + {code}" if fn.args else code
        lines.append(f"    {name} = {code}")
    lines.append(f"    return {outs}" + ("," if len(fn.output_names) == 1 else ""))
    return "\n".join(lines) + "\n"


def render_module(module_name: str) -> str:
    """Complete source of ``photolib/_generated/<module_name>.py``."""
    mod = importlib.import_module(f"photolib.derive.{module_name}")
    header = (
        f"# generated from photolib/derive/{module_name}.py, do not edit\n"
        f"# source sha256: {source_hash(module_name)}\n"
        f"# hashed: {', '.join(f'derive/{d}.py' for d in derive_dependencies(module_name))}\n"
        f"# regenerate with: python -m photolib codegen   (SymPy {sp.__version__.split('.')[0]}."
        f"{sp.__version__.split('.')[1]})\n"
        f'"""NumPy code generated from :mod:`photolib.derive.{module_name}`."""\n\n'
        "import numpy as np\n\n"
        f"__all__ = {sorted(fn.name for fn in mod.CODEGEN)!r}\n"
    )
    body = "\n\n".join(render_function(fn) for fn in mod.CODEGEN)
    return header + "\n\n" + body


def generate(outdir: Path | str = GENERATED_DIR) -> list[Path]:
    """Write every generated module (and ``__init__.py``) into ``outdir``; return the paths."""
    outdir = Path(outdir)
    outdir.mkdir(parents=True, exist_ok=True)
    written = []
    init = outdir / "__init__.py"
    init.write_text('"""Generated NumPy code; see photolib/codegen.py. Do not edit."""\n')
    written.append(init)
    for name in CODEGEN_MODULES:
        path = outdir / f"{name}.py"
        path.write_text(render_module(name))
        written.append(path)
    return written


def main(argv: list[str] | None = None) -> int:
    """Entry point of ``python -m photolib codegen [OUTDIR]``."""
    import argparse
    parser = argparse.ArgumentParser(
        prog="python -m photolib codegen",
        description="regenerate the NumPy code of photolib/_generated from photolib/derive")
    parser.add_argument("outdir", nargs="?", type=Path, default=GENERATED_DIR,
                        help=f"folder to write into (default: {GENERATED_DIR})")
    args = parser.parse_args(list(sys.argv[1:] if argv is None else argv))
    for path in generate(args.outdir):
        print(f"wrote {path}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
