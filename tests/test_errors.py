"""One error hierarchy (photolib.errors, issue 18): every error photolib raises on purpose is a
PhotolibError and still the built-in class it always was; the classes are the same objects
wherever they are imported from; the raising functions raise them."""

from __future__ import annotations

import numpy as np
import pytest

import photolib as pl
from photolib import errors

LEAVES = {
    "DegenerateGeometryError": ("transforms", errors.GeometryError),
    "GimbalLockError": ("rotations", errors.GeometryError),
    "PointBehindCameraError": ("collinearity", errors.GeometryError),
    "DatumError": ("bundle", errors.GeometryError),
    "OutsideModelError": ("orthophoto", errors.GeometryError),
    "NoRealImageError": ("optics", errors.GeometryError),
    "TotalInternalReflectionError": ("optics", errors.GeometryError),
    "StartOutsideImageError": ("matching", errors.InputError),
    "ConvergenceError": ("transforms", errors.PhotolibError),
    "DistortionDivergenceError": ("distortion", errors.ConvergenceError),
}


@pytest.mark.parametrize("name", sorted(LEAVES))
def test_each_error_is_in_the_hierarchy_and_one_object(name):
    import importlib
    module, base = LEAVES[name]
    cls = getattr(errors, name)
    assert issubclass(cls, base) and issubclass(cls, errors.PhotolibError)
    assert getattr(pl, name) is cls
    assert getattr(importlib.import_module(f"photolib.{module}"), name) is cls


def test_the_built_in_classes_are_kept():
    for name, (_, base) in LEAVES.items():
        cls = getattr(errors, name)
        builtin = RuntimeError if issubclass(base, errors.ConvergenceError) or \
            cls is errors.ConvergenceError else ValueError
        assert issubclass(cls, builtin), name
    assert not issubclass(errors.StartOutsideImageError, RuntimeError)   # bad input only


def test_the_raising_functions_raise_them():
    with pytest.raises(errors.GeometryError, match="gimbal|±90|π/2"):
        pl.opk_from_rotation(pl.rotation_opk(0.2, np.pi / 2, 0.1))
    with pytest.raises(errors.GeometryError):
        pl.project([[0.0, 0.0, 10.0]], X0=[0.0, 0.0, 0.0], R=np.eye(3), c=50.0)
    search = np.random.default_rng(0).uniform(0, 255, (30, 30))
    with pytest.raises(errors.InputError, match="initial|outside"):
        pl.least_squares_matching(search[5:16, 5:16], search, (-20.0, -20.0))
    with pytest.raises(AttributeError, match="no_such"):
        errors.no_such  # noqa: B018
