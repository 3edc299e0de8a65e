"""Chapter 14's teaching code (pixel → distortion-free image coordinates, and the
least-squares intersection of rays) agrees with photolib to 1e-9 on inputs of this test's own."""

from __future__ import annotations

import numpy as np
import pytest

import photolib as pl

from .teaching import teaching_functions

CODE = teaching_functions("14-project")


@pytest.mark.parametrize("seed", range(3))
def test_teaching_ideal_image_point_is_photolibs(seed):
    rng = np.random.default_rng(seed)
    W, H = 800, 600
    x0, y0 = rng.uniform(-20, 20, 2)
    d = {"A1": -1e-6 * rng.uniform(0.5, 1.5), "A2": 2e-12 * rng.uniform(-1, 1),
         "A3": 1e-17 * rng.uniform(-1, 1), "B1": 1e-6 * rng.uniform(-1, 1),
         "B2": 1e-6 * rng.uniform(-1, 1)}
    px = np.column_stack([rng.uniform(0, W - 1, 20), rng.uniform(0, H - 1, 20)])
    ours = np.array([CODE["ideal_image_point"](c, r, W, H, x0, y0, **d) for c, r in px])
    pp = np.array([x0, y0])
    lib = pp + pl.Distortion(**d).correct(pl.image_from_pixel(px, W, H, 1.0) - pp)
    assert np.max(np.abs(ours - lib)) <= 1e-9


@pytest.mark.parametrize("seed", range(3))
def test_teaching_intersection_is_photolibs(seed):
    rng = np.random.default_rng(seed)
    X = np.column_stack([rng.uniform(-5, 5, 8), rng.uniform(-5, 5, 8), rng.uniform(-1, 1, 8)])
    X0s = np.array([[-4.0, 0.0, 20.0], [5.0, 1.0, 21.0], [0.0, -6.0, 19.0]])
    Rs = np.array([pl.rotation_opk(*np.radians(rng.uniform(-10, 10, 3))) for _ in X0s])
    c, x0, y0 = 500.0, 3.0, -2.0
    xy = np.stack([pl.project(X, X0, R, c, x0, y0) for X0, R in zip(X0s, Rs)])
    xy += rng.normal(0, 0.3, xy.shape)
    ours = CODE["intersect"](xy, X0s, Rs, c, x0, y0)
    lib = pl.forward_intersection(xy, X0s, Rs, c, x0, y0).points
    assert np.max(np.abs(ours - lib)) <= 1e-9
