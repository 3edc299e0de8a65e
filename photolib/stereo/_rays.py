"""The image vector of the course convention, shared by the modules of :mod:`photolib.stereo`.

``x* = (x' − x'0, y' − y'0, −c)`` in the camera frame (c > 0, camera looking down −z); the
ray of an image point is ``X = X0 + λ·R·x*`` with ``λ > 0`` in front of the camera.
"""

from __future__ import annotations

import numpy as np


def _image_vectors(xy, c, x0, y0):
    """x* = (x' − x'0, y' − y'0, −c) of (N, 2) image points."""
    return np.column_stack([xy[:, 0] - x0, xy[:, 1] - y0, np.full(len(xy), -c)])
