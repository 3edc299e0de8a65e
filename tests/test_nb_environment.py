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


def test_pins_are_read_from_the_installed_metadata_not_repeated():
    """One source of the pins: photolib's metadata (built from pyproject.toml's dependencies),
    so nb's check and pyproject.toml cannot disagree; every checked distribution has a minimum."""
    assert set(nb.REQUIREMENTS) == set(nb.COURSE_DISTRIBUTIONS)
    assert set(nb.TESTED_BELOW) == set(nb.OUTPUT_PINNED)
    source = (ROOT / "photolib" / "nb" / "__init__.py").read_text()
    assert not re.search(r'"sympy":\s*\(\(?\d', source), "a pin is written in nb/__init__.py"


def test_a_missing_distribution_metadata_is_reported(monkeypatch):
    monkeypatch.setattr(nb, "REQUIREMENTS", {})
    assert any("not installed as a package" in p for p in nb.check_environment())
