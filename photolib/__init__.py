"""photolib: the numeric library of the photogrammetry course.

``import photolib`` loads NumPy only (no SymPy, no matplotlib). The formulas are derived
in :mod:`photolib.derive` with SymPy and generated as NumPy code into
:mod:`photolib._generated`; the modules below wrap that code with shape checks,
clear errors and the conventions of ``docs/conventions.md``.

Every public name is importable from ``photolib`` directly; its module is loaded on first
use (PEP 562), so ``import photolib`` costs little more than NumPy itself.
"""

from __future__ import annotations

import importlib

import numpy as _np  # noqa: F401 - the one dependency, loaded up front

#: the one place the version is written: pyproject.toml reads it ([tool.setuptools.dynamic])
__version__ = "0.1.0"

#: public name -> module that defines it
_EXPORTS = {
    # angles
    "deg2gon": "angles", "deg2rad": "angles", "gon2deg": "angles", "gon2rad": "angles",
    "rad2deg": "angles", "rad2gon": "angles", "wrap_angle": "angles",
    # rotations
    "GimbalLockError": "rotations", "exterior_from_opencv_pose": "rotations",
    "opencv_pose_from_exterior": "rotations", "opk_from_rotation": "rotations",
    "pok_from_rotation": "rotations", "rotation_2d": "rotations",
    "rotation_from_wolf_m": "rotations", "rotation_opk": "rotations",
    "rotation_pok": "rotations", "wolf_m_from_rotation": "rotations",
    # collinearity, distortion, pixels
    "PointBehindCameraError": "collinearity", "collinearity_jacobian": "collinearity",
    "monoplot": "collinearity", "project": "collinearity",
    "monoplot_dtm": "collinearity",
    # earth curvature and atmospheric refraction of aerial images (chapter 06)
    "earth_curvature_correction": "aerial", "refraction_constant": "aerial",
    "refraction_correction": "aerial", "exterior_from_navigation": "aerial",
    # area-based matching (NCC) and RANSAC (chapter 11)
    "ncc_match": "correlation", "normalised_cross_correlation": "correlation",
    "ransac": "correlation", "ransac_trials": "correlation",
    "rotation_body_to_ned": "aerial",
    "ConvergenceReport": "distortion", "Distortion": "distortion",
    "DistortionDivergenceError": "distortion", "OpenCVFit": "distortion",
    "PlumbLineResult": "calibration", "plumb_line": "calibration",
    "image_from_pixel": "pixels", "pixel_from_image": "pixels",
    # COLMAP and Agisoft Metashape (docs/conventions.md, "Other software")
    "MetashapeInterior": "conversions", "colmap_from_pixel": "conversions",
    "colmap_pose_from_exterior": "conversions", "exterior_from_colmap_pose": "conversions",
    "exterior_from_metashape_transform": "conversions",
    "interior_from_metashape": "conversions",
    "metashape_transform_from_exterior": "conversions", "pixel_from_colmap": "conversions",
    # plane transformations (Luhmann 2.18-2.21)
    "AffineTransform": "transforms", "BilinearTransform": "transforms",
    "ComposedTransform": "transforms", "ConvergenceError": "transforms",
    "DegenerateGeometryError": "transforms", "HelmertTransform": "transforms",
    "NewtonInverse": "transforms", "PolynomialTransform": "transforms",
    "ProjectiveTransform": "transforms", "cross_ratio": "transforms",
    # DLT, space resection, image measurement
    "DLTDecomposition": "dlt", "DLTEstimate": "dlt", "dlt_decompose": "dlt",
    "dlt_estimate": "dlt", "dlt_from_camera": "dlt",
    "ResectionResult": "resection", "space_resection": "resection",
    "CircleFit": "measurement", "MomentThreshold": "measurement", "fit_circle": "measurement",
    "laplacian_of_gaussian": "measurement", "moment_threshold": "measurement",
    # chapter 11: image measurement (LoG image filter, edges, centroid, ellipse, plane, LSM)
    "Centroid": "measurement", "EdgePoints": "measurement", "edge_points": "measurement",
    "log_filter": "measurement", "sobel_gradient": "measurement",
    "weighted_centroid": "measurement", "zero_crossings": "measurement",
    "Ellipse": "fitting", "EllipseFit": "fitting", "Plane": "fitting", "PlaneFit": "fitting",
    "circle_from_conic": "fitting", "conic_to_ellipse": "fitting", "fit_ellipse": "fitting",
    "fit_plane": "fitting", "plane_through_points": "fitting",
    "LSMResult": "matching", "least_squares_matching": "matching",
    "StartOutsideImageError": "matching",
    # chapters 01 and 03: digital images and sensors (quantisation, noise, colour, sampling, GSD)
    "DynamicRange": "sensors", "FlightBlock": "sensors", "alias_frequency": "sensors",
    "bayer_masks": "sensors", "bayer_mosaic": "sensors", "bits_for_levels": "sensors",
    "decibels": "sensors", "demosaic_bilinear": "sensors", "dequantise": "sensors",
    "dynamic_range": "sensors", "flight_block": "sensors", "footprint": "sensors",
    "gain_e_per_dn": "sensors", "grey_levels": "sensors",
    "ground_sampling_distance": "sensors", "line_rate": "sensors",
    "nyquist_frequency": "sensors", "pixel_mtf": "sensors",
    "quantisation_noise_variance": "sensors", "quantisation_step": "sensors",
    "quantise": "sensors", "sample_sine": "sensors", "snr": "sensors",
    # chapter 02: optics (thin lens, depth of field, diffraction, refraction, dispersion)
    "DepthOfField": "optics", "NoRealImageError": "optics",
    "TotalInternalReflectionError": "optics", "abbe_number": "optics",
    "airy_encircled_energy": "optics", "airy_psf": "optics", "airy_radius": "optics",
    "bessel_jn": "optics", "edge_diffraction": "optics", "edge_first_fringe": "optics",
    "grating_angles": "optics", "grating_intensity": "optics",
    "blur_diameter": "optics", "chromatic_focal_shift": "optics",
    "critical_angle": "optics", "depth_of_field": "optics", "f_number": "optics",
    "half_aperture_angle": "optics", "half_field_angle": "optics",
    "hyperfocal_distance": "optics", "image_distance": "optics",
    "image_scale_number": "optics", "natural_vignetting": "optics", "reflect": "optics",
    "refract": "optics", "refraction_angle": "optics", "refractive_index": "optics",
    "stereo_depth_acuity": "optics",
    # chapter 09: stereo (normal case, forward intersection, orientations, epipolar geometry)
    "AbsoluteOrientation": "stereo", "ForwardIntersection": "stereo",
    "RelativeOrientation": "stereo", "StereoAccuracy": "stereo",
    "absolute_orientation": "stereo", "epipolar_lines": "stereo",
    "essential_matrix": "stereo", "forward_intersection": "stereo",
    "fundamental_matrix": "stereo", "height_from_parallax": "stereo",
    "normal_case_accuracy": "stereo", "normal_case_points": "stereo",
    "normal_case_rotation": "stereo", "normalised_image_points": "stereo",
    "relative_orientation": "stereo", "independent_relative_orientation": "stereo",
    "depth_from_disparity": "stereo", "depth_sigma": "stereo", "points_from_disparity": "stereo",
    "match_disparities": "stereo", "textured_points": "stereo", "epipolar_distances": "stereo",
    "estimate_fundamental": "stereo", "estimate_fundamental_ransac": "stereo",
    # chapter 12: products (orthophoto, true orthophoto, mosaic) and the glossary
    "DTM": "orthophoto", "FrameCamera": "orthophoto", "OutsideModelError": "orthophoto",
    "differential_rectification": "orthophoto", "mosaic_nearest_nadir": "orthophoto",
    "ortho_pixel_positions": "orthophoto", "relief_displacement": "orthophoto",
    "true_orthophoto": "orthophoto", "visibility": "orthophoto",
    "load_glossary": "glossary",
    # chapter 10: bundle adjustment (reduced normal equations, datum, σ0, data snooping,
    # reliability)
    "BundleResult": "bundle", "DatumError": "bundle", "IterationRecord": "bundle",
    "SnoopingResult": "bundle", "bundle_adjustment": "bundle", "critical_value": "bundle",
    "data_snooping": "bundle", "inner_constraints": "bundle",
    "normal_matrix_pattern": "bundle", "student_t_cdf": "bundle",
    "ReliabilityResult": "bundle", "non_centrality": "bundle", "reliability": "bundle",
    # the bases of the error hierarchy (photolib.errors); the leaves are listed above
    "PhotolibError": "errors", "InputError": "errors", "GeometryError": "errors",
    "ExteriorOrientation": "exterior",
}

#: deprecated names: still importable (they warn when called), not in ``__all__``;
#: removed in the next release
_DEPRECATED = {
    "bessel_jn": "scipy.special.jv",
    "student_t_cdf": "scipy.stats.t.cdf",
}

__all__ = sorted(set(_EXPORTS) - set(_DEPRECATED))


def __getattr__(name: str):
    module = _EXPORTS.get(name)
    if module is None:
        raise AttributeError(f"module 'photolib' has no attribute {name!r}")
    value = getattr(importlib.import_module(f"photolib.{module}"), name)
    globals()[name] = value  # later look-ups skip this function
    return value


def __dir__():
    return sorted(set(globals()) | set(_EXPORTS))
