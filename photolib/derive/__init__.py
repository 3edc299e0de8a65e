"""SymPy sources of truth, one module per topic.

Every module here derives its formulas from first principles with SymPy and lists, in
``CODEGEN``, the functions that :mod:`photolib.codegen` turns into NumPy code under
``photolib/_generated/``. Nothing in this package is imported by ``import photolib``:
the numeric library runs on NumPy alone.
"""

#: derive modules that produce generated code, in generation order
CODEGEN_MODULES = ("rotation", "collinearity", "distortion")
