r"""Image mosaic (Bildmosaik) of overlapping photographs by plane transformations.

Tie points (Verknüpfungspunkte) measured in pairs of images give, for each pair, a plane
transformation from one image's pixels into the other's (projective, Luhmann 2.18, or
affine), estimated by least squares inside RANSAC (:func:`photolib.correlation.ransac`) so
that mismatched tie points do not enter. Chained from image to image, the transformations
take every image into the **mosaic frame**: the pixel frame of the reference image 0 as a
plane with ``X = col₀``, ``Y = −row₀`` (Y up, as every object plane of the course), so that
the mosaic is a grid of :mod:`photolib.rectify` (``X = X0 + col·Δ``, ``Y = Y0 − row·Δ``)
and each image is resampled onto it by the indirect method (:func:`rectify_image`).

Seam lines (Schnittkanten) are the nearest-centre (Voronoi) partition: a mosaic pixel takes
the image whose centre, mapped into the mosaic frame, is nearest among the images that
cover it (:func:`photolib.mosaic_nearest_nadir`) — the least extrapolation of each
transformation and, for near-vertical photographs, the least relief displacement.

The residuals at the tie points in the mosaic frame, ``v = T_i(p_i) − T_j(p_j)``, show how
well the images fit at the seams: for the pairs that were fitted they are the least-squares
residuals; for the other overlapping pairs they add the drift of the chain.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from photolib._validate import as_float_array, as_scalar
from photolib.correlation import ransac
from photolib.orthophoto._mosaic import mosaic_nearest_nadir
from photolib.rectify import rectify_image
from photolib.transforms import AffineTransform, ProjectiveTransform

__all__ = ["MODELS", "ImageMosaic", "PairFit", "chain_transforms", "fit_pair", "image_mosaic",
           "plane_from_pixel", "pixel_from_plane", "tie_point_residuals"]

#: plane transformations a pair may be fitted with, and their minimal samples
MODELS = {"projective": (ProjectiveTransform, 4), "affine": (AffineTransform, 3)}


class PairFit(NamedTuple):
    """Result of :func:`fit_pair`."""

    transform: object  #: src pixel (col, row) → dst pixel, refitted on the inliers
    inliers: np.ndarray  #: (N,) bool, tie points within the threshold
    residuals: np.ndarray  #: (N, 2) px, ``T(src) − dst`` of every tie point
    rms: float  #: px, RMS of the residual vector length over the inliers
    sigma0: float  #: px, ``sqrt(vᵀv/(2n − u))`` over the inliers (per coordinate)
    trials: int  #: RANSAC samples drawn


def _pairs(src, dst):
    src = as_float_array(src, "src")
    dst = as_float_array(dst, "dst")
    if src.ndim != 2 or src.shape[1] != 2 or src.shape != dst.shape:
        raise ValueError(f"src and dst must be (N, 2) tie points of one shape, got {src.shape} "
                         f"and {dst.shape}")
    return src, dst


def fit_pair(src, dst, *, model: str = "projective", threshold: float = 3.0,
             confidence: float = 0.999, rng=0) -> PairFit:
    r"""Plane transformation between two images from tie points, robust by RANSAC.

    Parameters
    ----------
    src, dst : array_like, shape (N, 2)
        The tie points (col, row), px, in the image to transform and in the target image.
    model : {'projective', 'affine'}
        Projective (8 parameters, Luhmann 2.18) or affine (6 parameters).
    threshold : float
        Inlier bound on ``|T(src) − dst|`` (px), e.g. 3σ of the feature measurement.
    confidence : float
        RANSAC's probability of drawing at least one outlier-free sample.
    rng : int or Generator
        Seed of RANSAC's samples (reproducible).

    Returns
    -------
    PairFit
        ``sigma0 = sqrt(Σ|v|²/(2n − u))`` with n inliers and u parameters (8 or 6).

    Raises
    ------
    ValueError
        Unknown model, tie points of the wrong shape, fewer than the minimal sample, or no
        consensus (:class:`~photolib.transforms.DegenerateGeometryError`).

    Examples
    --------
    >>> rng = np.random.default_rng(1)
    >>> src = rng.uniform(0, 500, (30, 2))
    >>> dst = AffineTransform(5.0, 1.01, 0.02, -3.0, -0.02, 0.99)(src)
    >>> dst[:3] += 40.0                                   # three mismatches
    >>> fit = fit_pair(src, dst, model="affine", threshold=1.0)
    >>> int(fit.inliers.sum()), bool(fit.inliers[:3].any()), round(fit.rms, 9)
    (27, False, 0.0)
    """
    if model not in MODELS:
        raise ValueError(f"model must be one of {sorted(MODELS)}, got {model!r}")
    src, dst = _pairs(src, dst)
    cls, s = MODELS[model]
    if len(src) < s + 1:
        raise ValueError(f"{len(src)} tie points are too few for a {model} transformation "
                         f"with RANSAC (at least {s + 1})")
    threshold = as_scalar(threshold, "threshold", positive=True)
    res = ransac(len(src), s, lambda i: cls.from_estimate(src[i], dst[i]),
                 lambda T: np.linalg.norm(T(src) - dst, axis=1), threshold,
                 confidence=confidence, rng=rng)
    T = res.model
    v = T(src) - dst
    vin = v[res.inliers]
    n, u = len(vin), cls.n_params
    rms = float(np.sqrt(np.mean(np.sum(vin**2, axis=1))))
    sigma0 = float(np.sqrt(np.sum(vin**2) / (2 * n - u))) if 2 * n > u else float("nan")
    return PairFit(T, res.inliers, v, rms, sigma0, res.trials)


def chain_transforms(pair_transforms):
    r"""Transformations of every image into the frame of image 0, chained pair by pair.

    ``pair_transforms[k − 1]`` maps image k into image k − 1 (pixels → pixels); then
    ``T_k = T_{k−1} ∘ t_k`` maps image k into image 0, with ``T_0`` the identity.

    >>> t = AffineTransform(10.0, 1.0, 0.0, 0.0, 0.0, 1.0)          # shift by 10 px in col
    >>> [T([[0.0, 0.0]]).tolist() for T in chain_transforms([t, t])]
    [[[0.0, 0.0]], [[10.0, 0.0]], [[20.0, 0.0]]]
    """
    out = [AffineTransform()]
    for t in pair_transforms:
        out.append(out[-1] @ t)
    return out


def plane_from_pixel(colrow) -> np.ndarray:
    """Mosaic-frame plane coordinates of reference pixels: ``X = col``, ``Y = −row``."""
    p = np.asarray(colrow, dtype=float)
    return np.stack([p[..., 0], -p[..., 1]], axis=-1)


def pixel_from_plane(XY) -> np.ndarray:
    """Reference pixels (col, row) of mosaic-frame plane coordinates: ``col = X``, ``row = −Y``."""
    p = np.asarray(XY, dtype=float)
    return np.stack([p[..., 0], -p[..., 1]], axis=-1)


def tie_point_residuals(transforms, ties):
    r"""Residuals of tie points in the mosaic frame (px of the reference image).

    Parameters
    ----------
    transforms : sequence of PlaneTransform
        Image k → reference image 0 (:func:`chain_transforms`).
    ties : iterable of (i, j, p_i, p_j)
        Tie points measured in images i and j, (N, 2) each.

    Returns
    -------
    list of dict
        Per pair: ``i``, ``j``, ``at`` (N, 2) the mean position in the reference image,
        ``v`` (N, 2) ``T_i(p_i) − T_j(p_j)``, ``rms`` and ``max`` of ``|v|`` (px).

    >>> t = AffineTransform(10.0, 1.0, 0.0, 0.0, 0.0, 1.0)
    >>> r = tie_point_residuals(chain_transforms([t]), [(0, 1, [[15.0, 2.0]], [[5.5, 2.0]])])
    >>> r[0]["v"].tolist(), r[0]["rms"]
    ([[-0.5, 0.0]], 0.5)
    """
    out = []
    for i, j, pi, pj in ties:
        pi, pj = _pairs(pi, pj)
        a, b = transforms[i](pi), transforms[j](pj)
        v = a - b
        d = np.hypot(v[:, 0], v[:, 1])
        out.append({"i": int(i), "j": int(j), "at": (a + b) / 2, "v": v,
                    "rms": float(np.sqrt(np.mean(d**2))), "max": float(d.max())})
    return out


class ImageMosaic(NamedTuple):
    """Result of :func:`image_mosaic`."""

    mosaic: np.ndarray  #: (rows, cols) float grey values, NaN where no image covers
    source: np.ndarray  #: (rows, cols) int, the image used (−1: none)
    origin: tuple  #: (X0, Y0) of the centre of the top-left mosaic pixel (mosaic frame)
    pixel_size: float  #: mosaic pixel in reference pixels
    centres: np.ndarray  #: (K, 2) image centres in the mosaic frame (the seed points of the seams)
    extent: tuple  #: (Xmin, Xmax, Ymin, Ymax) of the pixel edges, for ``imshow``

    def pixel(self, XY) -> np.ndarray:
        """Mosaic pixel (col, row) of mosaic-frame points (..., 2)."""
        p = np.asarray(XY, dtype=float)
        return np.stack([(p[..., 0] - self.origin[0]) / self.pixel_size,
                         (self.origin[1] - p[..., 1]) / self.pixel_size], axis=-1)


def image_mosaic(images, transforms, *, pixel_size: float = 1.0, order: int = 1) -> ImageMosaic:
    r"""Resample images into one mosaic with nearest-centre (Voronoi) seam lines.

    Each mosaic pixel at plane position (X, Y) of the mosaic frame is the reference pixel
    ``(X, −Y)``; image k is sampled at ``T_k⁻¹(X, −Y)`` (indirect method, bilinear for
    ``order=1``) and the pixel takes the covering image with the nearest centre.

    Parameters
    ----------
    images : sequence of array_like (H_k, W_k)
        Grey images.
    transforms : sequence of PlaneTransform
        Image k pixels → reference pixels (:func:`chain_transforms`).
    pixel_size : float
        Mosaic pixel size in reference pixels (> 0; 2 halves the resolution).
    order : {0, 1}
        Resampling: nearest neighbour or bilinear.

    Returns
    -------
    ImageMosaic

    Examples
    --------
    >>> a, b = np.zeros((4, 4)), np.ones((4, 4))
    >>> t = AffineTransform(2.0, 1.0, 0.0, 0.0, 0.0, 1.0)
    >>> m = image_mosaic([a, b], chain_transforms([t]))
    >>> m.mosaic.shape, m.source[0].tolist()
    ((4, 6), [0, 0, 0, 1, 1, 1])
    """
    if len(images) != len(transforms) or not images:
        raise ValueError(f"{len(images)} images but {len(transforms)} transforms; one per image")
    d = as_scalar(pixel_size, "pixel_size", positive=True)
    corners, centres = [], []
    for img, T in zip(images, transforms):
        H, W = np.shape(img)[:2]
        c = np.array([[0.0, 0.0], [W - 1.0, 0.0], [W - 1.0, H - 1.0], [0.0, H - 1.0]])
        corners.append(plane_from_pixel(T(c)))
        centres.append(plane_from_pixel(T(np.array([[(W - 1) / 2, (H - 1) / 2]])))[0])
    allc = np.vstack(corners)
    Xmin, Ymin = allc.min(axis=0)
    Xmax, Ymax = allc.max(axis=0)
    cols = int(np.floor((Xmax - Xmin) / d)) + 1
    rows = int(np.floor((Ymax - Ymin) / d)) + 1
    origin = (float(Xmin), float(Ymax))
    parts = []
    for img, T in zip(images, transforms):
        inv = T.inverse
        parts.append(rectify_image(img, lambda XY, inv=inv: inv(pixel_from_plane(XY)),
                                   (rows, cols), origin=origin, pixel_size=d, order=order,
                                   fill=np.nan))
    centres = np.array(centres)
    mosaic, source = mosaic_nearest_nadir(parts, centres, origin, d)
    extent = (Xmin - d / 2, Xmin + (cols - 0.5) * d, Ymax - (rows - 0.5) * d, Ymax + d / 2)
    return ImageMosaic(mosaic, source, origin, d, centres, tuple(float(e) for e in extent))
