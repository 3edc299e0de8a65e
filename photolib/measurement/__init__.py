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
:mod:`~photolib.measurement._targets` (moment-preserving threshold, weighted centroid),
:mod:`~photolib.measurement._circle` (circle fit) and :mod:`~photolib.measurement._real`
(targets in a real photograph: yellowness, TLS line, :func:`measure_targets`); every name is importable from
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
from photolib.measurement._real import (
    RealTarget,
    fit_line_tls,
    measure_targets,
    noise_autocorrelation,
    yellowness,
)
from photolib.measurement._targets import (
    Centroid,
    MomentThreshold,
    moment_threshold,
    weighted_centroid,
)

__all__ = ["Centroid", "CircleFit", "EdgePoints", "MomentThreshold", "RealTarget", "edge_points",
           "fit_circle", "fit_line_tls", "gaussian_radius", "laplacian_of_gaussian", "log_filter",
           "log_kernel_1d", "measure_targets", "moment_threshold", "noise_autocorrelation",
           "sobel_gradient",
           "weighted_centroid", "yellowness", "zero_crossings"]
