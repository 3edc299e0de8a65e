r"""Stereo photogrammetry / Stereophotogrammetrie: normal case, intersection, orientations.

Course conventions (``docs/conventions.md``): c > 0, ``R = R_ω·R_φ·R_κ`` rotates camera
vectors into the object frame, the image vector is ``x* = (x' − x'0, y' − y'0, −c)`` and
``(kx, ky, N) = Rᵀ(X − X0)`` with ``N < 0`` in front of the camera. The ray of an image point
is ``X = X0 + λ·R·x*`` with ``λ > 0`` in front.

* Normal case (Normalfall): R1 = R2 = I, camera 1 at the origin, camera 2 at ``(B, 0, 0)``;
  the x-parallax ``px' = x'1 − x'2`` gives ``Z = −c·B/px'`` (derived in
  :mod:`photolib.derive.stereo`), and its accuracy ``σ_Z = (h/B)·m·σ_px'``, ``σ_XY = m·σ_x'``.
* :func:`forward_intersection` (räumlicher Vorwärtsschnitt): least-squares point of two or
  more rays.
* Coplanarity / Komplanarität: ``det[b, R1·x*1, R2·x*2] = x*1ᵀ E x*2 = 0`` with the essential
  matrix ``E = R1ᵀ [b]× R2``; the fundamental matrix for image coordinates, epipolar lines.
* :func:`relative_orientation`: dependent relative orientation (Folgebildanschluss) with the
  five unknowns by, bz, ω2, φ2, κ2 (camera 1 fixed at the origin with R1 = I, bx fixed).
* :func:`independent_relative_orientation`: independent relative orientation (unabhängige
  Bildpaare) with the five angles φ1, κ1, ω2, φ2, κ2 (the base fixed along x).
* :func:`absolute_orientation`: 3-D similarity (Helmert, 7 parameters) ``X = X0 + m·R·x``.
* :func:`normal_case_rotation`, :func:`normalised_image_points`: epipolar (normalised) images.

Modules: :mod:`~photolib.stereo._normal` (normal case and its accuracy),
:mod:`~photolib.stereo._intersection` (forward intersection),
:mod:`~photolib.stereo._epipolar` (essential and fundamental matrix, epipolar lines,
normalised images) and :mod:`~photolib.stereo._orientation` (relative and absolute
orientation); every name is importable from :mod:`photolib.stereo`.
"""

from photolib.stereo._epipolar import (
    epipolar_lines,
    essential_matrix,
    fundamental_matrix,
    normal_case_rotation,
    normalised_image_points,
)
from photolib.stereo._intersection import ForwardIntersection, forward_intersection
from photolib.stereo._normal import (
    StereoAccuracy,
    height_from_parallax,
    normal_case_accuracy,
    normal_case_points,
)
from photolib.stereo._orientation import (
    AbsoluteOrientation,
    IndependentRelativeOrientation,
    RelativeOrientation,
    absolute_orientation,
    coplanarity_residuals,  # noqa: F401 - public in the module before the split
    independent_coplanarity_residuals,  # noqa: F401 - the residuals of the form below
    independent_relative_orientation,
    relative_orientation,
)

__all__ = [
    "AbsoluteOrientation",
    "ForwardIntersection",
    "IndependentRelativeOrientation",
    "RelativeOrientation",
    "StereoAccuracy",
    "absolute_orientation",
    "epipolar_lines",
    "essential_matrix",
    "forward_intersection",
    "fundamental_matrix",
    "height_from_parallax",
    "independent_relative_orientation",
    "normal_case_accuracy",
    "normal_case_points",
    "normal_case_rotation",
    "normalised_image_points",
    "relative_orientation",
]

# chapter 09, real photographs: depth from disparity, the fundamental matrix from points
from photolib.stereo._disparity import (  # noqa: E402
    depth_from_disparity,
    depth_sigma,
    match_disparities,
    points_from_disparity,
    textured_points,
)
from photolib.stereo._fundamental import (  # noqa: E402
    epipolar_distances,
    estimate_fundamental,
    estimate_fundamental_ransac,
)

__all__ += ["depth_from_disparity", "depth_sigma", "match_disparities", "points_from_disparity",
            "textured_points", "epipolar_distances", "estimate_fundamental",
            "estimate_fundamental_ransac"]
