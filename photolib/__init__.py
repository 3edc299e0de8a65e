"""photolib: the numeric library of the photogrammetry course.

``import photolib`` loads NumPy only (no SymPy, no matplotlib). The formulas are derived
in :mod:`photolib.derive` with SymPy and generated as NumPy code into
:mod:`photolib._generated`; the modules below wrap that code with shape checks,
clear errors and the conventions of ``docs/conventions.md``.
"""

from __future__ import annotations

from photolib.angles import deg2gon, deg2rad, gon2deg, gon2rad, rad2deg, rad2gon, wrap_angle
from photolib.collinearity import PointBehindCameraError, collinearity_jacobian, monoplot, project
from photolib.distortion import ConvergenceReport, Distortion, DistortionDivergenceError, OpenCVFit
from photolib.dlt import DLTDecomposition, DLTEstimate, dlt_decompose, dlt_estimate, dlt_from_camera
from photolib.measurement import (
    CircleFit,
    MomentThreshold,
    fit_circle,
    laplacian_of_gaussian,
    moment_threshold,
)
from photolib.pixels import image_from_pixel, pixel_from_image
from photolib.resection import ResectionResult, space_resection
from photolib.rotations import (
    GimbalLockError,
    exterior_from_opencv_pose,
    opencv_pose_from_exterior,
    opk_from_rotation,
    pok_from_rotation,
    rotation_2d,
    rotation_from_wolf_m,
    rotation_opk,
    rotation_pok,
    wolf_m_from_rotation,
)

from photolib.transforms import (
    AffineTransform,
    BilinearTransform,
    ComposedTransform,
    ConvergenceError,
    DegenerateGeometryError,
    HelmertTransform,
    NewtonInverse,
    PolynomialTransform,
    ProjectiveTransform,
    cross_ratio,
)

__version__ = "0.1.0"

__all__ = [
    "ConvergenceReport", "Distortion", "DistortionDivergenceError", "GimbalLockError",
    "OpenCVFit", "PointBehindCameraError", "collinearity_jacobian", "deg2gon", "deg2rad",
    "exterior_from_opencv_pose", "gon2deg", "gon2rad", "image_from_pixel", "monoplot",
    "opencv_pose_from_exterior", "opk_from_rotation", "pixel_from_image", "pok_from_rotation",
    "project", "rad2deg", "rad2gon", "rotation_2d", "rotation_from_wolf_m", "rotation_opk",
    "rotation_pok", "wolf_m_from_rotation", "wrap_angle",
    # plane transformations (Luhmann 2.18-2.21)
    "AffineTransform", "BilinearTransform", "ComposedTransform", "ConvergenceError",
    "DegenerateGeometryError", "HelmertTransform", "NewtonInverse", "PolynomialTransform",
    "ProjectiveTransform", "cross_ratio",
    # DLT, space resection, image measurement
    "DLTDecomposition", "DLTEstimate", "dlt_decompose", "dlt_estimate", "dlt_from_camera",
    "ResectionResult", "space_resection",
    "CircleFit", "MomentThreshold", "fit_circle", "laplacian_of_gaussian", "moment_threshold",
]
