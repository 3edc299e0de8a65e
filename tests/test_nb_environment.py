"""nb.setup()'s installation check: too old, and newer than the versions the outputs were made with."""

from __future__ import annotations

import re
from pathlib import Path

from photolib import nb

ROOT = Path(__file__).resolve().parents[1]


def test_untested_newer_version_is_reported(monkeypatch):
    monkeypatch.setitem(nb.TESTED_BELOW, "sympy", (0, 1))
    problems = nb.check_environment()
    assert len(problems) == 1 and problems[0].startswith("sympy ")
    assert "newer than the course was tested with (below 0.1)" in problems[0]


def test_tested_range_is_the_pin_of_pyproject():
    text = (ROOT / "pyproject.toml").read_text()
    for dist, below in nb.TESTED_BELOW.items():
        pin = re.search(rf'"{dist}>=([\d.]+),<([\d.]+)"', text)
        assert pin, f"{dist} has no upper pin in pyproject.toml"
        assert tuple(int(v) for v in pin.group(2).split(".")) == below, dist
        assert tuple(int(v) for v in pin.group(1).split(".")) == nb.REQUIREMENTS[dist][0], dist
