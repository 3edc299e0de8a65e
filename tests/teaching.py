"""The teaching implementations of the chapter notebooks, loaded for tests.

A chapter shows each core method first as short, readable code (the loop, the normal
equations, the stopping rule) and then the photolib function. The cells that define that code
carry the tag ``teaching``; :func:`teaching_functions` runs exactly those cells (with ``np``,
``sp`` and ``pl`` imported as the notebooks import them) and returns what they define, so a
test can call the notebook's own code on inputs of its own and compare it with photolib to
1e-9: the notebook's printed comparison is not the only check, and a teaching cell edited
into disagreement fails here, naming the function.
"""

from __future__ import annotations

import functools
import json
from pathlib import Path

NOTEBOOKS = Path(__file__).resolve().parents[1] / "notebooks"
TAG = "teaching"


@functools.cache
def _sources(stem: str) -> tuple[str, ...]:
    nb = json.loads((NOTEBOOKS / f"{stem}.ipynb").read_text(encoding="utf-8"))
    return tuple("".join(c["source"]) for c in nb["cells"]
                 if c["cell_type"] == "code" and TAG in c.get("metadata", {}).get("tags", []))


def teaching_functions(stem: str) -> dict:
    """Names defined by the ``teaching`` cells of ``notebooks/<stem>.ipynb``.

    Raises ``LookupError`` when the notebook has no such cell (a test that would otherwise
    compare nothing).
    """
    import numpy as np
    import sympy as sp

    import photolib as pl

    sources = _sources(stem)
    if not sources:
        raise LookupError(f"notebooks/{stem}.ipynb has no cell tagged {TAG!r}")
    ns = {"np": np, "sp": sp, "pl": pl, "__name__": f"teaching_{stem.replace('-', '_')}"}
    for source in sources:
        exec(compile(source, f"{stem}.ipynb[teaching]", "exec"), ns)  # noqa: S102 - our own notebook
    return {k: v for k, v in ns.items() if callable(v) and not k.startswith("_")
            and getattr(v, "__module__", None) == ns["__name__"]}
