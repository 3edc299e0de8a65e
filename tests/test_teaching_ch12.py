"""Chapter 12's teaching code (differential rectification written out in the notebook) agrees
with :func:`photolib.differential_rectification` to 1e-9 on scenes of this test's own."""

from __future__ import annotations

import numpy as np
import pytest

import photolib as pl
from photolib.orthophoto import DTM, FrameCamera

from .teaching import teaching_functions

CODE = teaching_functions("12-products")


def _scene(seed, distortion):
    rng = np.random.default_rng(seed)
    W, H, s = int(rng.integers(60, 120)), int(rng.integers(50, 90)), 0.02
    c = float(rng.uniform(20, 40))
    X0 = np.array([rng.uniform(-5, 5), rng.uniform(-5, 5), rng.uniform(80, 120)])
    R = pl.rotation_opk(*np.radians(rng.uniform(-3, 3, 3)))
    d = pl.Distortion(A1=float(rng.uniform(-5e-4, 5e-4))) if distortion else None
    cam = FrameCamera(X0, R, c, W, H, s, float(rng.uniform(-0.05, 0.05)),
                      float(rng.uniform(-0.05, 0.05)), distortion=d)
    heights = rng.uniform(0, 8, (9, 11))
    dtm = DTM(heights, (-20.0, 20.0), 4.0)
    image = rng.uniform(0, 255, (H, W))
    return cam, dtm, image


@pytest.mark.parametrize("seed", range(4))
@pytest.mark.parametrize("distortion", [False, True])
def test_teaching_orthophoto_is_photolibs(seed, distortion):
    cam, dtm, image = _scene(seed, distortion)
    shape, origin, gsd = (23, 31), (-15.0, 14.0), 0.97       # partly outside the image
    mine = CODE["ortho_by_hand"](image, cam, dtm.heights, dtm.origin, dtm.spacing, shape,
                                 origin, gsd)
    ref = pl.differential_rectification(image, cam, dtm, shape, origin, gsd)
    assert mine.shape == ref.shape
    assert np.allclose(mine, ref, rtol=0, atol=1e-9)


def test_teaching_orthophoto_refuses_a_point_behind_the_camera():
    cam, dtm, image = _scene(0, False)
    high = DTM(np.full((9, 11), cam.X0[2] + 5.0), dtm.origin, dtm.spacing)
    with pytest.raises(ValueError, match="behind"):
        CODE["ortho_by_hand"](image, cam, high.heights, high.origin, high.spacing, (3, 3),
                              (0.0, 0.0), 1.0)
