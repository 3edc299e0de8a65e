"""The grey image that the modules of :mod:`photolib.measurement` measure in.

``_image2d`` accepts a finite 2-D array of at least 3 × 3 pixels as floats and refuses
anything else with the argument's name.
"""

from __future__ import annotations

import numpy as np

from photolib._validate import as_float_array, check_finite


def _image2d(image, name="image") -> np.ndarray:
    img = as_float_array(image, name)
    if img.ndim != 2 or min(img.shape) < 3:
        raise ValueError(f"{name} has shape {np.shape(image)}; expected a 2-D grey image of at "
                         "least 3 × 3 pixels")
    check_finite(img, name)
    return img
