"""Chapter execution time from a fresh kernel, against a course-style floor notebook.

Target: each chapter at most 2.5 × the floor, measured in the same run; 4 × for the chapters
that work on real photographs (issue 15), and the errata chapter under 5 s (issue 14). The floor
notebook does what every chapter must do anyway: start a kernel, import NumPy, SymPy,
matplotlib and ipywidgets, and draw one figure. Both are the best of two runs.
"""

from __future__ import annotations

import sys
import time
from pathlib import Path

import nbformat
from nbclient import NotebookClient

ROOT = Path(__file__).resolve().parents[1]
CHAPTERS = ["01-introduction", "02-optics", "03-digital-images", "04-rotations",
            "05-interior-orientation", "06-collinearity", "07-plane-transformations",
            "08-resection-dlt", "09-stereo", "10-bundle-adjustment", "11-image-measurement",
            "12-products", "13-errata", "14-project"]
FACTOR = 2.5
#: chapters that load and measure real photographs (mvtb-data, scikit-image's data)
REAL_IMAGES = {"05-interior-orientation", "07-plane-transformations", "08-resection-dlt",
               "09-stereo", "11-image-measurement", "12-products", "14-project"}
REAL_FACTOR = 4.0
#: the errata chapter's own budget, in seconds
ERRATA_SECONDS = 5.0

FLOOR = """\
import numpy as np
import sympy as sp
import matplotlib.pyplot as plt
import ipywidgets
fig, ax = plt.subplots()
ax.plot(np.linspace(0, 1, 50), np.linspace(0, 1, 50) ** 2)
"""


def _execute(nb) -> float:
    t = time.perf_counter()
    NotebookClient(nb, timeout=300, kernel_name="python3",
                   resources={"metadata": {"path": str(ROOT / "notebooks")}}).execute()
    return time.perf_counter() - t


def floor_notebook():
    return nbformat.v4.new_notebook(cells=[nbformat.v4.new_code_cell(FLOOR)])


def run() -> int:
    floor = min(_execute(floor_notebook()) for _ in range(2))
    print(f"floor notebook (kernel + imports + one figure): {floor:.2f} s")
    ok = True
    for name in CHAPTERS:
        nb = nbformat.read(ROOT / "notebooks" / f"{name}.ipynb", as_version=4)
        seconds = min(_execute(nb) for _ in range(2))  # best of two, like the floor
        ratio = seconds / floor
        factor = REAL_FACTOR if name in REAL_IMAGES else FACTOR
        good = ratio <= factor and (name != "13-errata" or seconds < ERRATA_SECONDS)
        ok &= good
        target = f"≤ {factor} ×" + (f", < {ERRATA_SECONDS:.0f} s" if name == "13-errata" else "")
        print(f"{name:26s} {seconds:6.2f} s = {ratio:4.2f} × floor "
              f"({'OK' if good else 'TOO SLOW'}, target {target})")
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(run())
