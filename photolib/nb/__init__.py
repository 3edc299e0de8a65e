"""Notebook helpers of the course: setup, plotting style, figures and widgets.

Every chapter notebook starts with::

    import numpy as np
    import photolib as pl
    from photolib import nb
    nb.setup()

:func:`setup` checks the installation and sets a common plotting style; the figures and the
widgets of each chapter live in the submodules (:mod:`photolib.nb.intro`,
:mod:`photolib.nb.optics`, :mod:`photolib.nb.sensors`, :mod:`photolib.nb.rotations`,
:mod:`photolib.nb.distortion`, :mod:`photolib.nb.projection`, :mod:`photolib.nb.plane`,
:mod:`photolib.nb.resection`, :mod:`photolib.nb.stereo`, :mod:`photolib.nb.bundle`,
:mod:`photolib.nb.measurement`, :mod:`photolib.nb.products`, :mod:`photolib.nb.glossary`),
so that a notebook shows the idea and not the plumbing. The widgets' callbacks are plain
functions, tested in ``tests/test_nb*.py`` and timed in ``benchmarks/bench_widgets.py``.
"""

from __future__ import annotations

import gc
import importlib
from importlib import metadata

from photolib.nb.text import formulas, matrix_html, rounded, show

__all__ = [
    "REQUIREMENTS",
    "bundle",
    "check_environment",
    "distortion",
    "formulas",
    "glossary",
    "intro",
    "matrix_html",
    "measurement",
    "optics",
    "plane",
    "products",
    "projection",
    "resection",
    "rotations",
    "rounded",
    "sensors",
    "setup",
    "show",
    "stereo",
]

#: the distributions :func:`setup` checks (each imports under its own name)
COURSE_DISTRIBUTIONS = ("numpy", "sympy", "matplotlib", "ipywidgets")
#: of these, the ones whose upper pin matters for the committed outputs (SymPy's printing,
#: NumPy's reprs): a newer version is reported
OUTPUT_PINNED = ("numpy", "sympy")


def _version_tuple(text: str) -> tuple:
    parts = []
    for piece in text.split(".")[:2]:
        digits = "".join(ch for ch in piece if ch.isdigit())
        parts.append(int(digits) if digits else 0)
    return tuple(parts)


def _pins(requires) -> dict:
    """distribution → (lower, upper) version tuples (``None`` where not pinned) from the
    requirement strings of photolib's metadata (``"numpy<3,>=2.1"``, markers ignored).

    >>> _pins(["numpy<3,>=2.1", 'ipywidgets<9,>=8.1; extra == "course"', "scipy>=1.13"])
    {'numpy': ((2, 1), (3,)), 'ipywidgets': ((8, 1), (9,)), 'scipy': ((1, 13), None)}
    """
    import re

    out = {}
    for line in requires:
        spec = line.split(";")[0].strip()
        m = re.match(r"([A-Za-z0-9_.-]+)(\[[^\]]*\])?\s*(.*)", spec)
        name, clauses = m.group(1).lower(), m.group(3)
        low = re.search(r">=\s*([\d.]+)", clauses)
        high = re.search(r"(?<![<>=!])<\s*([\d.]+)", clauses)
        if name in out or not (low or high):
            continue
        out[name] = (_version_tuple(low.group(1)) if low else None,
                     tuple(int(v) for v in high.group(1).split(".")) if high else None)
    return out


def _requirements() -> tuple[dict, dict]:
    """The pins of pyproject.toml, read from the installed package's metadata (one source):
    ``REQUIREMENTS`` (distribution → (minimum, module)) and ``TESTED_BELOW`` (distribution →
    first version not tested). Empty when photolib is not installed as a distribution."""
    try:
        pins = _pins(metadata.requires("photolib") or [])
    except metadata.PackageNotFoundError:
        return {}, {}
    req = {d: (pins[d][0], d) for d in COURSE_DISTRIBUTIONS if d in pins and pins[d][0]}
    below = {d: pins[d][1] for d in OUTPUT_PINNED if d in pins and pins[d][1]}
    return req, below


#: distribution → (minimum version, the module to import), for :func:`check_environment`
#: distribution → first version not tested (the upper pins of pyproject.toml): the committed
#: outputs were made below it. Both from the installed metadata of photolib (pyproject.toml).
REQUIREMENTS, TESTED_BELOW = _requirements()


def check_environment() -> list[str]:
    """Problems with the installation, as sentences; an empty list when all is well.

    >>> check_environment()
    []
    """
    problems = []
    if not REQUIREMENTS:
        problems.append("photolib is not installed as a package, so its requirements are "
                        "unknown: run make lab (or pip install -c constraints.txt -e '.[course]')")
    for dist, (minimum, module) in REQUIREMENTS.items():
        try:
            version = metadata.version(dist)
            importlib.import_module(module)
        except (metadata.PackageNotFoundError, ImportError):
            problems.append(f"{dist} is missing: pip install -e '.[course]'")
            continue
        if _version_tuple(version) < minimum:
            need = ".".join(map(str, minimum))
            problems.append(f"{dist} {version} is too old: the course needs {need} or newer")
        elif dist in TESTED_BELOW and _version_tuple(version)[:len(TESTED_BELOW[dist])] >= TESTED_BELOW[dist]:
            limit = ".".join(map(str, TESTED_BELOW[dist]))
            problems.append(f"{dist} {version} is newer than the course was tested with "
                            f"(below {limit}): outputs may differ from the committed ones; "
                            f"`make lab` installs the tested versions")
    return problems


STYLE = {
    "figure.figsize": (6.4, 3.6),
    "figure.dpi": 80,
    "axes.grid": True,
    "grid.alpha": 0.3,
    "axes.spines.top": False,
    "axes.spines.right": False,
    "font.size": 10,
    "image.cmap": "viridis",
    "savefig.bbox": "tight",
}


def setup() -> None:
    """Check the installation and set the course's plotting style and NumPy print options.

    Prints one line: that the environment is ready, or what is wrong and how to fix it.
    """
    problems = check_environment()
    if problems:
        print("photolib course environment: PROBLEMS")
        for p in problems:
            print("  -", p)
        return
    import matplotlib.pyplot as plt  # loads the inline backend's defaults first
    import numpy as np

    plt.rcParams.update(STYLE)
    np.set_printoptions(precision=6, suppress=True)
    # The objects alive after a chapter's imports (NumPy, SymPy, matplotlib, ipywidgets,
    # photolib: some 250 000) live as long as the kernel. The collector's permanent
    # generation keeps each full collection from walking them again: a chapter runs several,
    # 0.1–0.2 s each. (Cyclic garbage left at this moment, if any, is never freed.)
    gc.freeze()
    print("photolib course environment: OK")


def __getattr__(name):
    # chapter modules on first use: `nb.rotations` without importing all chapters
    if name in ("intro", "optics", "sensors", "rotations", "distortion", "projection", "plane",
                "resection", "stereo", "bundle", "measurement", "products", "glossary",
                "live", "draw"):
        return importlib.import_module(f"photolib.nb.{name}")
    raise AttributeError(f"module 'photolib.nb' has no attribute {name!r}")
