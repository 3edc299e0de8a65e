"""Real photographs for the course / Reale Aufnahmen: loaders of freely licensed image sets.

Every set ships inside a package of the package index, installed by the ``data`` extra
(``pip install -c constraints.txt -e '.[data]'``; ``make lab`` and ``make test`` install it
through the ``course`` extra). Nothing is downloaded at run time: the loaders read the files
installed with the packages, and a missing package raises :class:`DataPackageMissing`, which
names the install command. ``import photolib`` and ``import photolib.data`` import neither
package (nor Pillow): each loader imports what it needs when it is called.

=====================  ===============================================  ======================
loader                 what                                             package (licence)
=====================  ===============================================  ======================
:func:`chessboard`     14 views of a 9 × 6 chessboard, one 640 × 480     ``mvtb-data`` (MIT)
                       camera, and its published OpenCV calibration
:func:`mosaic`         10 overlapping aerial images ``aerial2-001…010``  ``mvtb-data`` (MIT)
:func:`stereo_pair`    ``rocks2`` and ``walls``: left/right pairs        ``mvtb-data`` (MIT)
:func:`building2`      three views of a building                        ``mvtb-data`` (MIT)
:func:`church`         one view of a church                             ``mvtb-data`` (MIT)
:func:`eiffel`         two views of the Eiffel tower                    ``mvtb-data`` (MIT)
:func:`yellowtargets`  yellow targets on a background                   ``mvtb-data`` (MIT)
:func:`campus`         20 views of a campus (5 more held out)           ``mvtb-data`` (MIT)
:func:`motorcycle`     rectified Middlebury 2014 pair, calibration and   ``scikit-image``
                       ground-truth disparity                           (BSD-3-Clause)
=====================  ===============================================  ======================

Pixel coordinates follow the course (``docs/conventions.md``): (col, row), (0, 0) at the centre
of the top-left pixel, which is also OpenCV's and Middlebury's pixel origin. None of the
cameras' pixel pitch (Pixelabstand) is published, so ``pixel_pitch_mm`` is None for every set
and the image unit of a calibration from these images is the pixel.

The package data of photolib itself (``glossary.csv``) also lives in this folder and is read
by :mod:`photolib.glossary` through ``importlib.resources``.
"""

from __future__ import annotations

import importlib.util
import re
from dataclasses import dataclass, field
from importlib import metadata
from pathlib import Path

import numpy as np

__all__ = [
    "CAMPUS_FILES",
    "CAMPUS_HOLDOUT",
    "DataPackageMissing",
    "ImageSet",
    "OpenCVCalibration",
    "StereoCalibration",
    "StereoPair",
    "building2",
    "campus",
    "chessboard",
    "church",
    "eiffel",
    "mosaic",
    "motorcycle",
    "stereo_pair",
    "yellowtargets",
]

#: the command that installs the data packages (from the repository's root)
INSTALL = "pip install -c constraints.txt -e '.[data]'"

MVTB_LICENCE = "MIT"
MVTB_ATTRIBUTION = ("Machine Vision Toolbox for Python data package mvtb-data {version}, "
                    "Peter Corke (rvc@petercorke.com), MIT licence; "
                    "https://github.com/petercorke/machinevision-toolbox-python")
SKIMAGE_LICENCE = "BSD-3-Clause (the scikit-image package that distributes the images)"
MOTORCYCLE_ATTRIBUTION = (
    "Middlebury 2014 stereo data set 'Motorcycle' (D. Scharstein, H. Hirschmüller, "
    "Y. Kitajima, G. Krathwohl, N. Nesic, X. Wang, P. Westling: High-resolution stereo "
    "datasets with subpixel-accurate ground truth, GCPR 2014), down-sampled by 4 and "
    "distributed with scikit-image {version} as skimage.data.stereo_motorcycle")

#: the 20 campus images of the set, and the 5 the package keeps apart ("holdout")
CAMPUS_FILES = ("P1070491", "P1070493", "P1070494", "P1070495", "P1070496", "P1070497",
                "P1070498", "P1070499", "P1070500", "P1070501", "P1070503", "P1070504",
                "P1070505", "P1070506", "P1070507", "P1070509", "P1070510", "P1070512",
                "P1070514", "P1070515")
CAMPUS_HOLDOUT = ("P1070492", "P1070502", "P1070508", "P1070511", "P1070513")


class DataPackageMissing(ImportError):
    """A package that holds a data set is not installed; the message names the install command."""


@dataclass(frozen=True)
class OpenCVCalibration:
    """A calibration published in OpenCV's form (``cv2.calibrateCamera``'s YAML file).

    OpenCV's pinhole ``u = fx·x_d + cx``, ``v = fy·y_d + cy`` (pixels, (0, 0) at the centre of
    the top-left pixel, v down) with the distortion ``(k1, k2, p1, p2, k3)`` at the ideal
    normalised point. :meth:`interior` maps it to the course (docs/conventions.md, OpenCV row).
    """

    width: int  #: image width W, px
    height: int  #: image height H, px
    camera_matrix: np.ndarray  #: (3, 3) K = [[fx, 0, cx], [0, fy, cy], [0, 0, 1]], px
    distortion: np.ndarray  #: (5,) k1, k2, p1, p2, k3 (dimensionless, normalised coordinates)
    rms_px: float  #: OpenCV's avg_reprojection_error: √(Σ|e|²/N) over points, px
    per_view_rms_px: np.ndarray  #: (n_frames,) the same per view, px
    n_frames: int  #: the number of views the calibration used
    board: tuple  #: (columns, rows) of inner corners
    square_mm: float  #: side of a chessboard square, mm
    extrinsics: np.ndarray  #: (n_frames, 6) rvec (rad), tvec (m), as published
    flags: int  #: cv2.calibrateCamera flags (2 = CALIB_FIX_ASPECT_RATIO)

    @property
    def f_px(self) -> float:
        """Focal length ``fx`` (= fy here), px."""
        return float(self.camera_matrix[0, 0])

    def interior(self) -> dict:
        """The course's interior orientation in pixel units (image unit: px, s = 1).

        ``c = fx``, ``x'0 = cx − (W − 1)/2``, ``y'0 = (H − 1)/2 − cy`` (OpenCV's pixel origin is
        the course's: the centre of the top-left pixel), and the OpenCV coefficients, whose
        same-form course terms are ``A1 = k1/c²``, ``A2 = k2/c⁴``, ``A3 = k3/c⁶``,
        ``B1 = p2/c``, ``B2 = −p1/c`` (first order only: OpenCV evaluates at the ideal point,
        the course at the measured one; :meth:`photolib.Distortion.from_opencv` fits them).

        >>> cal = OpenCVCalibration(640, 480, np.diag([500.0, 500.0, 1.0]) + [[0, 0, 330.5],
        ...     [0, 0, 229.5], [0, 0, 0]], np.zeros(5), 0.3, np.zeros(1), 1, (9, 6), 25.0,
        ...     np.zeros((1, 6)), 2)
        >>> {k: cal.interior()[k] for k in ("c", "x0", "y0")}
        {'c': 500.0, 'x0': 11.0, 'y0': 10.0}
        """
        K = self.camera_matrix
        return {"c": float(K[0, 0]), "x0": float(K[0, 2] - (self.width - 1) / 2),
                "y0": float((self.height - 1) / 2 - K[1, 2]),
                "opencv": tuple(float(v) for v in self.distortion)}


@dataclass(frozen=True)
class StereoCalibration:
    """Calibration of a rectified stereo pair (Middlebury form), pixels and mm.

    Depth of a pixel with disparity d (px): ``Z = f·B/(d + doffs)`` (mm), with ``doffs`` the
    difference of the principal points' columns, ``cx_right − cx_left`` (Middlebury's
    ``doffs``).
    """

    f_px: float  #: focal length, px (both images)
    cx_px: float  #: principal point column of the left image, px
    cy_px: float  #: principal point row, px
    doffs_px: float  #: x-difference of the principal points, px
    baseline_mm: float  #: B, mm

    def depth_mm(self, disparity) -> np.ndarray:
        """Depth ``Z = f·B/(d + doffs)`` in mm of disparities ``d`` (px); NaN where d is not finite.

        >>> StereoCalibration(1000.0, 0.0, 0.0, 0.0, 200.0).depth_mm([100.0]).tolist()
        [2000.0]
        """
        d = np.asarray(disparity, dtype=float)
        with np.errstate(invalid="ignore", divide="ignore"):
            z = self.f_px * self.baseline_mm / (d + self.doffs_px)
        return np.where(np.isfinite(d) & (d + self.doffs_px > 0), z, np.nan)


@dataclass(frozen=True)
class ImageSet:
    """Images of one set with their metadata."""

    name: str  #: the set's name
    images: tuple  #: of uint8 ndarrays, (H, W) grey or (H, W, 3) RGB
    files: tuple  #: file name of each image, in the package
    sizes: tuple  #: (W, H) of each image, px
    pixel_pitch_mm: float | None  #: pixel pitch, mm; None: not published
    licence: str  #: licence of the images
    attribution: str  #: text to cite with the images
    source: str  #: package and folder the images come from
    calibration: OpenCVCalibration | None = None  #: published calibration, if any
    notes: str = ""  #: what else is known (or not) about the images
    extra: dict = field(default_factory=dict)  #: set-specific items (e.g. board geometry)

    def __len__(self) -> int:
        return len(self.images)

    def __getitem__(self, i):
        return self.images[i]


@dataclass(frozen=True)
class StereoPair:
    """A left/right pair, with calibration and ground-truth disparity where published."""

    name: str
    left: np.ndarray  #: uint8 (H, W, 3)
    right: np.ndarray  #: uint8 (H, W, 3)
    files: tuple  #: (left, right) file names in the package
    size: tuple  #: (W, H), px
    pixel_pitch_mm: float | None
    licence: str
    attribution: str
    source: str
    calibration: StereoCalibration | None = None
    #: (H, W) float, px: left pixel (row, col) matches right (row, col − d); NaN unknown
    disparity: np.ndarray | None = None
    notes: str = ""


# -- package access --------------------------------------------------------------------------

def _require(module: str, dist: str) -> Path:
    """The folder of the installed package ``module``, found without importing it, or
    :class:`DataPackageMissing` naming the install command."""
    spec = importlib.util.find_spec(module)
    if spec is None or not spec.submodule_search_locations:
        raise DataPackageMissing(
            f"the data set needs the package {dist!r}, which is not installed: run "
            f"{INSTALL} (or make lab / make test, which install it)")
    return Path(next(iter(spec.submodule_search_locations)))


def _version(dist: str) -> str:
    try:
        return metadata.version(dist)
    except metadata.PackageNotFoundError:
        return "(version unknown)"


def _read(path) -> np.ndarray:
    """One image file as a uint8 array: grey (H, W) or RGB (H, W, 3) (an alpha channel dropped)."""
    try:
        from PIL import Image
    except ModuleNotFoundError:
        raise DataPackageMissing(f"reading the images needs Pillow: run {INSTALL}") from None
    with Image.open(path) as im:
        if im.mode not in ("L", "RGB"):
            im = im.convert("RGB")
        return np.asarray(im).copy()


def _mvtb_images(names, folder: str = "images"):
    root = _require("mvtbdata", "mvtb-data").joinpath(folder)
    paths = [root.joinpath(n) for n in names]
    for n, p in zip(names, paths):
        if not p.is_file():
            raise FileNotFoundError(f"mvtb-data {_version('mvtb-data')} has no file "
                                    f"{folder}/{n}; the course was made with mvtb-data 1.6.1 "
                                    f"({INSTALL} installs it)")
    return [_read(p) for p in paths]


def _mvtb_set(name, files, folder, notes="", **kw) -> ImageSet:
    images = _mvtb_images(files, folder)
    return ImageSet(name, tuple(images), tuple(files),
                    tuple((im.shape[1], im.shape[0]) for im in images), None, MVTB_LICENCE,
                    MVTB_ATTRIBUTION.format(version=_version("mvtb-data")),
                    f"mvtb-data: mvtbdata/{folder}", notes=notes, **kw)


def _check_choice(value, name: str, choices) -> None:
    if value not in choices:
        raise ValueError(f"{name} must be one of {tuple(choices)}, got {value!r}")


# -- the sets --------------------------------------------------------------------------------

def _yaml_matrix(text: str, key: str) -> np.ndarray:
    """The ``data: [...]`` list of an OpenCV YAML matrix node ``key``."""
    m = re.search(rf"^{key}:.*?data:\s*\[([^\]]*)\]", text, flags=re.S | re.M)
    if m is None:
        raise ValueError(f"left_intrinsics.yml has no matrix {key!r}")
    return np.array([float(v) for v in m.group(1).replace("\n", " ").split(",")])


def _yaml_scalar(text: str, key: str) -> float:
    m = re.search(rf"^{key}:\s*([-+0-9.eE]+)\s*$", text, flags=re.M)
    if m is None:
        raise ValueError(f"left_intrinsics.yml has no value {key!r}")
    return float(m.group(1))


def published_chessboard_calibration() -> OpenCVCalibration:
    """The OpenCV calibration published with the chessboard images (``data/left_intrinsics.yml``).

    Parsed without a YAML library (the file is OpenCV's ``%YAML 1.0`` with matrix nodes).
    Its ``square_size`` is 0.025 (m); ``square_mm`` is 25.0.
    """
    text = _require("mvtbdata", "mvtb-data").joinpath("data", "left_intrinsics.yml").read_text(
        encoding="utf-8")
    n = int(_yaml_scalar(text, "nframes"))
    return OpenCVCalibration(
        width=int(_yaml_scalar(text, "image_width")),
        height=int(_yaml_scalar(text, "image_height")),
        camera_matrix=_yaml_matrix(text, "camera_matrix").reshape(3, 3),
        distortion=_yaml_matrix(text, "distortion_coefficients"),
        rms_px=_yaml_scalar(text, "avg_reprojection_error"),
        per_view_rms_px=_yaml_matrix(text, "per_view_reprojection_errors"),
        n_frames=n,
        board=(int(_yaml_scalar(text, "board_width")), int(_yaml_scalar(text, "board_height"))),
        square_mm=round(_yaml_scalar(text, "square_size") * 1000.0, 6),
        extrinsics=_yaml_matrix(text, "extrinsic_parameters").reshape(n, 6),
        flags=int(_yaml_scalar(text, "flags")))


def chessboard() -> ImageSet:
    """The 14 chessboard views ``images/calibration/left01–14.jpg`` (mvtb-data).

    One 640 × 480 camera (the left camera of a stereo rig; also OpenCV's sample images
    ``samples/data/left*.jpg``), a 9 × 6 board of inner corners with 25 mm squares, grey JPEG.
    ``calibration`` is the published OpenCV calibration (:func:`published_chessboard_calibration`,
    13 views); ``extra`` holds ``board`` (9, 6), ``square_mm`` 25.0 and ``object_points``
    (54, 3), mm, of the inner corners in the course's frame: ``X = 25·i``, ``Y = −25·j``,
    ``Z = 0`` for corner ``k = 9j + i`` (i along the rows of ``cv2.findChessboardCorners``),
    right-handed with +Z towards the camera, so the camera sees the board with N < 0.
    """
    files = [f"left{i:02d}.jpg" for i in range(1, 15)]
    cal = published_chessboard_calibration()
    i, j = np.meshgrid(np.arange(9), np.arange(6))
    obj = np.column_stack([25.0 * i.ravel(), -25.0 * j.ravel(), np.zeros(54)])
    return _mvtb_set("chessboard", files, "images/calibration", calibration=cal,
                     notes="pixel pitch not published: calibrate in pixels",
                     extra={"board": (9, 6), "square_mm": 25.0, "object_points": obj})


def mosaic() -> ImageSet:
    """Ten overlapping grey aerial images ``images/mosaic/aerial2-001…010.png`` (mvtb-data).

    Sizes differ between images (e.g. 1279 × 1023 and 1103 × 815 px); no calibration, scale
    or flying height is published.
    """
    files = [f"aerial2-{i:03d}.png" for i in range(1, 11)]
    return _mvtb_set("mosaic", files, "images/mosaic",
                     notes="no calibration, flying height or pixel pitch published")


def stereo_pair(name: str = "rocks2") -> StereoPair:
    """A left/right pair of mvtb-data: ``'rocks2'`` (1276 × 1110 px) or ``'walls'`` (3264 × 2448 px).

    RGB; no calibration or ground truth is published with them (``calibration`` and
    ``disparity`` are None).
    """
    _check_choice(name, "name", ("rocks2", "walls"))
    files = (f"{name}-l.png", f"{name}-r.png")
    left, right = _mvtb_images(files)
    return StereoPair(name, left, right, files, (left.shape[1], left.shape[0]), None,
                      MVTB_LICENCE, MVTB_ATTRIBUTION.format(version=_version("mvtb-data")),
                      "mvtb-data: mvtbdata/images",
                      notes="no calibration or ground truth published")


def building2() -> ImageSet:
    """Three views of a building, ``images/building2-1…3.png`` (mvtb-data).

    Views 1 and 2 are grey 1181 × 851 px, view 3 RGB 1280 × 851 px (its alpha channel dropped).
    """
    return _mvtb_set("building2", [f"building2-{i}.png" for i in (1, 2, 3)], "images",
                     notes="no calibration published; the views differ in size and colour")


def church() -> ImageSet:
    """One RGB view of a church, ``images/church.png`` (1280 × 851 px, mvtb-data)."""
    return _mvtb_set("church", ["church.png"], "images", notes="no calibration published")


def eiffel() -> ImageSet:
    """Two RGB views of the Eiffel tower, ``images/eiffel-1.png`` (1280 × 851 px) and
    ``eiffel-2.png`` (1280 × 960 px) (mvtb-data)."""
    return _mvtb_set("eiffel", ["eiffel-1.png", "eiffel-2.png"], "images",
                     notes="no calibration published; two different cameras or zooms")


def yellowtargets() -> ImageSet:
    """Yellow circular targets, ``images/yellowtargets.png`` (RGB, 640 × 480 px, mvtb-data)."""
    return _mvtb_set("yellowtargets", ["yellowtargets.png"], "images",
                     notes="no calibration published")


def campus(holdout: bool = False) -> ImageSet:
    """The 20 campus views ``images/campus/P10704xx.png`` (RGB, 640 × 426 px, mvtb-data).

    ``holdout=True`` loads the 5 views the package keeps in ``campus/holdout`` instead.
    """
    if holdout not in (True, False):
        raise ValueError(f"holdout must be True or False, got {holdout!r}")
    names = CAMPUS_HOLDOUT if holdout else CAMPUS_FILES
    folder = "images/campus/holdout" if holdout else "images/campus"
    return _mvtb_set("campus-holdout" if holdout else "campus", [f"{n}.png" for n in names],
                     folder, notes="no calibration published")


#: the calibration of the down-sampled Middlebury pair, as printed in scikit-image's docstring
MOTORCYCLE_CALIBRATION = StereoCalibration(f_px=994.978, cx_px=311.193, cy_px=254.877,
                                           doffs_px=31.086, baseline_mm=193.001)


def motorcycle() -> StereoPair:
    """The rectified Middlebury 2014 pair 'Motorcycle' of scikit-image, 741 × 500 px.

    Bundled in the scikit-image wheel (``skimage/data/motorcycle_*.png``,
    ``motorcycle_disp.npz``): read from the installed package, never downloaded — this
    function refuses a file that is not inside the installed distribution rather than let
    scikit-image fetch it. The ground-truth disparity is px, with the unknown pixels (stored as
    inf in the file; scikit-image's docstring says NaN) set to NaN. Calibration:
    :data:`MOTORCYCLE_CALIBRATION` (f = 994.978 px, B = 193.001 mm, doffs = 31.086 px).
    """
    root = _require("skimage", "scikit-image").joinpath("data")
    files = ("motorcycle_left.png", "motorcycle_right.png", "motorcycle_disp.npz")
    for n in files:
        if not root.joinpath(n).is_file():
            raise FileNotFoundError(f"scikit-image {_version('scikit-image')} does not bundle "
                                    f"skimage/data/{n}; the course reads it only from the "
                                    f"installed package (made with scikit-image 0.26.0: "
                                    f"{INSTALL})")
    left, right = (_read(root.joinpath(n)) for n in files[:2])
    with np.load(root.joinpath(files[2])) as npz:
        disp = np.array(npz["arr_0"], dtype=float)
    disp[~np.isfinite(disp)] = np.nan
    return StereoPair("motorcycle", left, right, files[:2], (left.shape[1], left.shape[0]), None,
                      SKIMAGE_LICENCE,
                      MOTORCYCLE_ATTRIBUTION.format(version=_version("scikit-image")),
                      "scikit-image: skimage/data", calibration=MOTORCYCLE_CALIBRATION,
                      disparity=disp,
                      notes="rectified: corresponding points share a row; pixel pitch not "
                            "published")
