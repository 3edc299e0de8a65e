"""Run every benchmark of the course: ``make bench`` or ``python -m benchmarks``.

Each benchmark module prints its figures; the targets are stated in its docstring.
"""

from __future__ import annotations

import importlib
import pkgutil
import sys
from pathlib import Path


def main() -> int:
    here = Path(__file__).resolve().parent
    names = sorted(m.name for m in pkgutil.iter_modules([str(here)]) if m.name.startswith("bench_"))
    wanted = sys.argv[1:] or names
    for name in wanted:
        print(f"== {name} ==", flush=True)
        mod = importlib.import_module(f"benchmarks.{name}")
        if hasattr(mod, "run"):
            mod.run()
        elif hasattr(mod, "main"):
            mod.main([])  # defaults; sys.argv names the benchmarks here
        print(flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
