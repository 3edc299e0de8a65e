"""Image measurement / Bildmessung: LoG, edges, moment-preserving threshold, centroid, circle fit.

* :func:`laplacian_of_gaussian` (5.42 as a function of r), :func:`log_filter` (separable LoG
  of an image, kernel half width ``ceil(4σ)``) and :func:`zero_crossings` (edges);
* :func:`sobel_gradient` and :func:`edge_points` (non-maximum suppression, subpixel position);
* :func:`moment_threshold` (Tsai, 5.49/5.50) and :func:`weighted_centroid` (with background
  threshold and precision);
* :func:`fit_circle`. Ellipse and plane fits are in :mod:`photolib.fitting`, least-squares
  matching in :mod:`photolib.matching`.

The formulas are derived here (and checked with SymPy in the tests), not copied: Luhmann's
5.42 as corrected in the errata is right; the corrected 5.50 as printed in the errata list
(``p1 = ½[1 + s̄·sqrt(4 + s̄²)]``) is not — the square root belongs in the denominator.

Modules: :mod:`~photolib.measurement._log` (Laplacian of Gaussian, zero crossings),
:mod:`~photolib.measurement._edges` (Sobel gradient, edge points),
:mod:`~photolib.measurement._targets` (moment-preserving threshold, weighted centroid) and
:mod:`~photolib.measurement._circle` (circle fit); every name is importable from
:mod:`photolib.measurement`.
"""

from photolib.measurement._circle import CircleFit, fit_circle
from photolib.measurement._edges import EdgePoints, edge_points, sobel_gradient
from photolib.measurement._log import (
    gaussian_radius,
    laplacian_of_gaussian,
    log_filter,
    log_kernel_1d,
    zero_crossings,
)
from photolib.measurement._targets import (
    Centroid,
    MomentThreshold,
    moment_threshold,
    weighted_centroid,
)

__all__ = ["Centroid", "CircleFit", "EdgePoints", "MomentThreshold", "edge_points", "fit_circle",
           "gaussian_radius", "laplacian_of_gaussian", "log_filter", "log_kernel_1d",
           "moment_threshold", "sobel_gradient", "weighted_centroid", "zero_crossings"]
