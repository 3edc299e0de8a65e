"""photolib._docs.shared_doc: one text for parameters several functions document alike (issue 18)."""

from __future__ import annotations

import inspect
import re

import pytest

import photolib as pl
from photolib._docs import shared_doc

MARKER = re.compile(r"^\s*\{\w+\}\s*$", re.M)


def test_a_piece_takes_the_indentation_of_its_marker():
    @shared_doc(p="a : int\n    The a.\n\nb : int\n    The b.")
    def f(a, b):
        """F.

        Parameters
        ----------
        {p}
        """
    assert f.__doc__.splitlines()[4:9] == ["        a : int", "            The a.", "",
                                           "        b : int", "            The b."]


def test_a_marker_without_a_piece_and_a_piece_without_a_marker_raise():
    with pytest.raises(ValueError, match=r"no shared piece for \['q'\]"):
        @shared_doc(p="x")
        def f():
            """{p}
            {q}
            """
    with pytest.raises(ValueError, match=r"no marker for \['r'\]"):
        @shared_doc(p="x", r="y")
        def g():
            """
            {p}
            """


@pytest.mark.parametrize("name", ["image_from_pixel", "pixel_from_image", "rotation_opk",
                                  "rotation_pok", "earth_curvature_correction",
                                  "refraction_correction", "relative_orientation",
                                  "independent_relative_orientation", "deg2rad", "gon2deg"])
def test_the_shared_docstrings_are_complete(name):
    doc = inspect.getdoc(getattr(pl, name))
    assert not MARKER.search(doc), f"{name}: unfilled marker"
    params = inspect.signature(getattr(pl, name)).parameters
    for p in params:   # each parameter is described at the start of a Parameters line
        assert re.search(rf"^(\w+, )*{p}\b[\w, ]*( :|$)", doc, flags=re.M), (name, p)


def test_no_public_docstring_keeps_a_marker():
    for name in pl.__all__:
        obj = getattr(pl, name)
        if inspect.isfunction(obj):
            assert not MARKER.search(obj.__doc__ or ""), name
