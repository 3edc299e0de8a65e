"""Optics of the camera (Optik): thin lens, depth of field, diffraction, refraction, dispersion.

The formulas are derived in :mod:`photolib.derive.optics` (Fermat → Snell, ray construction →
imaging equation, similar triangles → depth of field, Fraunhofer diffraction → Airy pattern)
and judged against the German lecture summary in :mod:`photolib.errata.de_summary_optics`.

Units: every length argument of one function shares one unit, chosen by the caller (mm in the
course), except where a name says otherwise: Sellmeier wavelengths are in µm (the unit of the
glass catalogues). Angles are radians. Distances a, a' are positive, measured from the lens.

Arrays broadcast: each function accepts scalars or arrays and returns a float for scalar input.

Modules: :mod:`~photolib.optics._thin_lens` (imaging equation, angles, f-number, depth of
field), :mod:`~photolib.optics._diffraction` (Airy pattern, edge and grating),
:mod:`~photolib.optics._refraction` (Snell, reflection, dispersion),
:mod:`~photolib.optics._vignetting` (cos⁴ law) and :mod:`~photolib.optics._stereo_acuity`;
every name is importable from :mod:`photolib.optics`. ``bessel_jn`` is deprecated (use
``scipy.special.jv``): it still imports from here, warns when called and is not in ``__all__``.
"""

from photolib.optics._diffraction import (
    J1_FIRST_ZERO,
    airy_encircled_energy,
    airy_psf,
    airy_radius,
    bessel_jn,  # noqa: F401 - deprecated (scipy.special.jv), kept for one release
    edge_diffraction,
    edge_first_fringe,
    grating_angles,
    grating_intensity,
)
from photolib.optics._refraction import (
    C_LINE,
    D_LINE,
    F_LINE,
    GLASSES,
    TotalInternalReflectionError,
    abbe_number,
    chromatic_focal_shift,
    critical_angle,
    reflect,
    refract,
    refraction_angle,
    refractive_index,
)
from photolib.optics._stereo_acuity import stereo_depth_acuity
from photolib.optics._thin_lens import (
    DepthOfField,
    NoRealImageError,
    blur_diameter,
    depth_of_field,
    f_number,
    half_aperture_angle,
    half_field_angle,
    hyperfocal_distance,
    image_distance,
    image_scale_number,
)
from photolib.optics._vignetting import natural_vignetting

__all__ = [
    "C_LINE",
    "D_LINE",
    "F_LINE",
    "GLASSES",
    "J1_FIRST_ZERO",
    "DepthOfField",
    "NoRealImageError",
    "TotalInternalReflectionError",
    "abbe_number",
    "airy_encircled_energy",
    "airy_psf",
    "airy_radius",
    "edge_diffraction",
    "edge_first_fringe",
    "grating_angles",
    "grating_intensity",
    "blur_diameter",
    "chromatic_focal_shift",
    "critical_angle",
    "depth_of_field",
    "f_number",
    "half_aperture_angle",
    "half_field_angle",
    "hyperfocal_distance",
    "image_distance",
    "image_scale_number",
    "natural_vignetting",
    "reflect",
    "refract",
    "refraction_angle",
    "refractive_index",
    "stereo_depth_acuity",
]
