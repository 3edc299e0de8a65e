"""Digital images and sensors: quantisation, noise, dynamic range, colour, sampling, coverage.

Conventions of this module (chapter 03, ``docs/conventions.md``):

* A sensor element collects *electrons* (e⁻); the analogue-to-digital converter maps them to
  *digital numbers* DN (Grauwerte) ``0 … 2^b − 1``. The gain K is in e⁻/DN; the full well
  saturates at the largest DN, so ``K = full_well / (2^b − 1)``.
* Quantisation rounds to the nearest level (midtread): ``DN = clip(round(s/Δ), 0, 2^b − 1)``
  with the step ``Δ = full_scale / (2^b − 1)``.
* Noise is given as a standard deviation in electrons; an SNR is a ratio of amplitudes and its
  decibel value ``20·log10``.
* Lengths in the image (pixel pitch, camera constant c) share one image unit (mm in the
  course); object distances and ground sizes share the object unit (m). Spatial frequencies
  are cycles per image unit.
* Bayer patterns are named by the colours of the top-left 2 × 2 block read row by row:
  ``"RGGB"``, ``"BGGR"``, ``"GRBG"``, ``"GBRG"``.

Modules: :mod:`~photolib.sensors._quantisation` (grey levels, quantisation, gain, dynamic
range, SNR), :mod:`~photolib.sensors._colour` (Bayer mosaic, demosaicing),
:mod:`~photolib.sensors._sampling` (Nyquist, aliasing, pixel MTF) and
:mod:`~photolib.sensors._coverage` (GSD, footprint, flight block, line rate); every name is
importable from :mod:`photolib.sensors`.

NumPy only.
"""

from photolib.sensors._colour import (
    BAYER_PATTERNS,
    bayer_masks,
    bayer_mosaic,
    demosaic_bilinear,
)
from photolib.sensors._coverage import (
    FlightBlock,
    flight_block,
    footprint,
    ground_sampling_distance,
    image_scale_number,
    line_rate,
)
from photolib.sensors._quantisation import (
    DynamicRange,
    bits_for_levels,
    decibels,
    dequantise,
    dynamic_range,
    gain_e_per_dn,
    grey_levels,
    quantisation_noise_variance,
    quantisation_step,
    quantise,
    snr,
)
from photolib.sensors._sampling import (
    alias_frequency,
    nyquist_frequency,
    pixel_mtf,
    sample_sine,
)

__all__ = [
    "BAYER_PATTERNS", "DynamicRange", "FlightBlock", "alias_frequency", "bayer_masks",
    "bayer_mosaic", "bits_for_levels", "decibels", "demosaic_bilinear", "dequantise",
    "dynamic_range", "flight_block", "footprint", "gain_e_per_dn", "grey_levels",
    "ground_sampling_distance", "image_scale_number", "line_rate", "nyquist_frequency",
    "pixel_mtf", "quantisation_noise_variance", "quantisation_step", "quantise", "sample_sine",
    "snr",
]
