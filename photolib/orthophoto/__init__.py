r"""Orthophoto / Orthophoto by differential rectification (differentielle Entzerrung).

A map has one scale everywhere (parallel projection, Parallelprojektion); an image is a
central projection (Zentralprojektion) whose scale changes with the height of the ground.
The **indirect differential rectification** computes, for every pixel of the orthophoto,

1. the plan position (X, Y) of its centre (:func:`photolib.rectify.output_grid`),
2. the height Z(X, Y) from a digital terrain model (DTM, digitales Geländemodell) — or, for a
   *true* orthophoto, from a surface model (DSM, digitales Oberflächenmodell),
3. the image coordinates of (X, Y, Z) by the collinearity equations
   (:func:`photolib.project`, with distortion),
4. the pixel position (:func:`photolib.pixel_from_image`) and the grey value there
   (:func:`photolib.rectify.sample_image`, nearest neighbour or bilinear).

Grids (DTM, DSM, orthophoto) follow :mod:`photolib.rectify`: ``origin = (X0, Y0)`` is the
centre of the top-left cell, ``X = X0 + col·Δ``, ``Y = Y0 − row·Δ``.

Relief displacement (radiale Versetzung) of a vertical image, derived in
:mod:`photolib.derive.products`:

.. math:: Δr = r\,\frac{Δh}{H}

with r the radial image distance of the *displaced* (top) point, Δh its height above the
reference plane and H the flying height above that plane. Plane rectification
(ebene Entzerrung, :class:`photolib.ProjectiveTransform`) ignores Δh and misplaces the point
by exactly Δr, i.e. by Δr·H/c on the ground.

Modules: :mod:`~photolib.orthophoto._dtm` (height models),
:mod:`~photolib.orthophoto._camera` (the frame camera),
:mod:`~photolib.orthophoto._relief` (relief displacement),
:mod:`~photolib.orthophoto._rectification` (differential rectification),
:mod:`~photolib.orthophoto._visibility` (visibility, true orthophoto) and
:mod:`~photolib.orthophoto._mosaic` (mosaic); every name is importable from
:mod:`photolib.orthophoto`.
"""

from photolib.orthophoto._camera import FrameCamera
from photolib.orthophoto._dtm import DTM, OutsideModelError
from photolib.orthophoto._mosaic import mosaic_nearest_nadir
from photolib.orthophoto._rectification import (
    BLOCK_ROWS,  # noqa: F401 - public in the module before the split
    differential_rectification,
    ortho_pixel_positions,
)
from photolib.orthophoto._relief import relief_displacement
from photolib.orthophoto._visibility import true_orthophoto, visibility

__all__ = ["DTM", "FrameCamera", "OutsideModelError", "differential_rectification",
           "mosaic_nearest_nadir", "ortho_pixel_positions", "relief_displacement",
           "true_orthophoto", "visibility"]

#: most samples :func:`visibility` takes along one ray with a ``step``; a smaller step raises
#: (defined here: :func:`visibility` reads it from the package at each call)
MAX_RAY_STEPS = 1_000_000
