"""Aerial images: earth curvature, atmospheric refraction and direct georeferencing.

Erdkrümmung und atmosphärische Refraktion; Polish notes: krzywizna Ziemi, refrakcja
atmosferyczna. Both displace the image of a ground point radially from the nadir of a vertical
image; the corrections are applied to the measured image coordinates, reduced to the principal
point and corrected for distortion, before they enter the collinearity equations::

    x* = (x' − x'0 − Δx' − Δx'_refraction − Δx'_curvature,  y' − …,  −c)

Derived in :mod:`photolib.derive.aerial`:

* earth curvature moves an image point towards the nadir by ``r'³·H/(2 R c²)`` (H the flying
  height above the ground, R the earth radius), relative to the flat object space (a tangent
  plane, map coordinates) of the collinearity equations;
* refraction moves it outwards by ``K·(r' + r'³/c²)``, with the refraction constant K of the
  air between the ground and the camera (:func:`refraction_constant`).

Units: image coordinates and c in one unit (mm in the course); H, h and R in metres.
For a near-vertical image only (the nadir at the principal point).

Direct georeferencing (direkte Georeferenzierung, GNSS/IMU): the exterior orientation from the
antenna position and the attitude of the inertial unit, through the lever arm (Hebelarm) and
the boresight misalignment (Fehlausrichtung) of the camera (:func:`exterior_from_navigation`).
"""

from __future__ import annotations

import numpy as np

from photolib._docs import shared_doc
from photolib._validate import as_points, as_scalar

__all__ = ["EARTH_RADIUS", "NADIR_MOUNT", "NED_TO_ENU", "earth_curvature_correction",
           "exterior_from_navigation", "refraction_constant", "refraction_correction",
           "refractive_index_icao", "rotation_body_to_ned"]

#: mean earth radius, m (IUGG)
EARTH_RADIUS = 6_371_000.0

#: the parameters ``xy, c`` of the image corrections
_XY_C = """xy : array_like, shape (N, 2) or (2,)
    Image coordinates reduced to the principal point, mm (distortion already corrected).
c : float
    Camera constant, mm, > 0."""


def _radial(xy, c):
    """Checked image points (N, 2), the single-point flag, ``c`` (mm) and ``r'²`` (N, 1), mm²."""
    pts, single = as_points(xy, 2, "xy")
    c = as_scalar(c, "camera constant c", positive=True)
    r2 = np.sum(pts**2, axis=1, keepdims=True)
    return pts, single, c, r2


@shared_doc(xy_c=_XY_C)
def earth_curvature_correction(xy, c, flying_height, radius=EARTH_RADIUS):
    """Image coordinates with the earth curvature removed (to the tangent plane at the nadir).

    Parameters
    ----------
    {xy_c}
    flying_height : float
        Flying height above the ground H, m, > 0.
    radius : float
        Earth radius R, m (default the mean radius 6371 km).

    Returns
    -------
    ndarray, same shape as ``xy``
        ``xy·(1 + r'²·H/(2 R c²))``: the curvature displaced the image towards the nadir by
        ``Δr' = r'³·H/(2 R c²)``; the correction moves it back out.

    Examples
    --------
    >>> xy = earth_curvature_correction([100.0, 0.0], 153.0, 3000.0)
    >>> round(float(xy[0] - 100.0) * 1000, 2)      # µm, at r' = 100 mm, H = 3 km
    10.06
    """
    pts, single, c, r2 = _radial(xy, c)
    H = as_scalar(flying_height, "flying height H", positive=True)
    R = as_scalar(radius, "earth radius R", positive=True)
    out = pts * (1.0 + r2 * H / (2.0 * R * c**2))
    return out[0] if single else out


def refractive_index_icao(height):
    """Refractive index of air n(z) − 1 in the ICAO standard atmosphere (visible light).

    ``n − 1 = 77.6e-6 · p/T`` (p in hPa, T in K; Smith–Weintraub, dry air), with the ICAO
    troposphere ``T = 288.15 K − 6.5 K/km·z``, ``p = 1013.25 hPa·(T/288.15 K)^5.25588`` up to
    11 km and the isothermal stratosphere above (``T = 216.65 K``, scale height 6.3416 km).

    Parameters
    ----------
    height : float or array_like
        Height above sea level z, m, from −500 m to 20 km.

    Returns
    -------
    ndarray or float
        n − 1 (dimensionless), e.g. 2.73e-4 at sea level.
    """
    z = np.asarray(height, float) / 1000.0
    if not np.all(np.isfinite(z)) or np.any((z < -0.5) | (z > 20.0)):
        raise ValueError(f"height must lie between -500 m and 20 km, got {height!r}")
    T = np.where(z <= 11.0, 288.15 - 6.5 * z, 216.65)
    p = np.where(z <= 11.0, 1013.25 * (T / 288.15) ** 5.25588,
                 226.3206 * np.exp(-(z - 11.0) / 6.3416))
    n1 = 77.6e-6 * p / T
    return float(n1) if n1.ndim == 0 else n1


def refraction_constant(flying_height, ground_height=0.0, model="icao"):
    """The refraction constant K of ``dα = K·tan α`` between the ground and the camera.

    Parameters
    ----------
    flying_height : float
        Height of the camera above sea level H, m.
    ground_height : float
        Height of the ground above sea level h, m, below H.
    model : {"icao", "ardc"}
        ``"icao"``: the first-order layer formula of :mod:`photolib.derive.aerial`,
        ``K = (1/(H − h))·∫_h^H (n(z) − n(H))/n(H) dz``, integrated over the ICAO standard
        atmosphere (:func:`refractive_index_icao`; Gauss–Legendre, 32 nodes).
        ``"ardc"``: the empirical formula of the ARDC model atmosphere used in American
        textbooks (Wolf), with H and h in km:
        ``K = (2410 H/(H² − 6H + 250) − 2410 h²/((h² − 6h + 250) H))·10⁻⁶``.
        The two differ by up to 25 % below 2 km and agree within 10 % from 4 to 10 km: the
        atmosphere of the day differs from both by as much, which is why precise work measures it.

    Returns
    -------
    float
        K, radians per unit of tan α (a few 10⁻⁵ for aerial images).

    Examples
    --------
    >>> round(refraction_constant(3000.0) * 1e6, 1), round(refraction_constant(3000.0, model="ardc") * 1e6, 1)
    (33.8, 30.0)
    """
    H = as_scalar(flying_height, "flying height H")
    h = as_scalar(ground_height, "ground height h")
    if not H > h:
        raise ValueError(f"the camera must be above the ground: flying height H = {H!r} m, "
                         f"ground height h = {h!r} m")
    if model == "ardc":
        Hk, hk = H / 1000.0, h / 1000.0
        return (2410.0 * Hk / (Hk**2 - 6.0 * Hk + 250.0)
                - 2410.0 * hk**2 / ((hk**2 - 6.0 * hk + 250.0) * Hk)) * 1e-6
    if model != "icao":
        raise ValueError(f"model must be 'icao' or 'ardc', got {model!r}")
    nodes, weights = np.polynomial.legendre.leggauss(32)
    zs = h + (H - h) * (nodes + 1.0) / 2.0
    nH = refractive_index_icao(H)
    excess = (np.asarray(refractive_index_icao(zs)) - nH) / (1.0 + nH)
    return float(np.sum(weights * excess) / 2.0)


@shared_doc(xy_c=_XY_C)
def refraction_correction(xy, c, K):
    """Image coordinates with the atmospheric refraction removed.

    Parameters
    ----------
    {xy_c}
    K : float
        Refraction constant (:func:`refraction_constant`), ≥ 0 and below 10⁻³.

    Returns
    -------
    ndarray, same shape as ``xy``
        ``xy·(1 − K·(1 + r'²/c²))``: refraction displaced the image outwards by
        ``Δr' = K·(r' + r'³/c²)`` (first order in K); the correction moves it back in.

    Examples
    --------
    >>> xy = refraction_correction([100.0, 0.0], 153.0, 30e-6)
    >>> round(float(xy[0] - 100.0) * 1000, 2)      # µm
    -4.28
    """
    pts, single, c, r2 = _radial(xy, c)
    K = as_scalar(K, "refraction constant K")
    if not 0.0 <= K < 1e-3:
        raise ValueError(f"refraction constant K must lie in [0, 1e-3) (a few 1e-5 in air), "
                         f"got {K!r}")
    out = pts * (1.0 - K * (1.0 + r2 / c**2))
    return out[0] if single else out


# -- direct georeferencing ----------------------------------------------------------------------

#: local north-east-down (navigation) → east-north-up (the course's object frame, Z up)
NED_TO_ENU = np.array([[0.0, 1.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, -1.0]])

#: camera → body frame of a nadir camera with x' along the flight direction: the body frame is
#: x forward, y right, z down (aerospace); the course's camera frame x' right in the image
#: (= forward), y' up in the image (= left), z out of the back of the camera (= up)
NADIR_MOUNT = np.diag([1.0, -1.0, -1.0])


def rotation_body_to_ned(roll, pitch, heading):
    """Attitude of the inertial unit: body → north-east-down, ``R_z(ψ)·R_y(θ)·R_x(φ)``.

    Parameters
    ----------
    roll, pitch, heading : float
        Roll φ about the body x axis (forward), pitch θ about y (right), heading ψ about z
        (down, clockwise from north seen from above), radians: the aerospace z-y-x order.

    Returns
    -------
    ndarray, shape (3, 3)
        Rotates body vectors into the local NED frame.

    Examples
    --------
    >>> R = rotation_body_to_ned(0.0, 0.0, np.pi / 2)      # flying east
    >>> np.round(R @ [1.0, 0.0, 0.0], 12).tolist()          # forward = east
    [0.0, 1.0, 0.0]
    """
    r, p, y = (as_scalar(v, n) for v, n in ((roll, "roll"), (pitch, "pitch"),
                                              (heading, "heading")))
    cr, sr, cp, sp_, cy, sy = np.cos(r), np.sin(r), np.cos(p), np.sin(p), np.cos(y), np.sin(y)
    Rx = np.array([[1.0, 0.0, 0.0], [0.0, cr, -sr], [0.0, sr, cr]])
    Ry = np.array([[cp, 0.0, sp_], [0.0, 1.0, 0.0], [-sp_, 0.0, cp]])
    Rz = np.array([[cy, -sy, 0.0], [sy, cy, 0.0], [0.0, 0.0, 1.0]])
    return Rz @ Ry @ Rx


def exterior_from_navigation(antenna, roll, pitch, heading, lever_arm=(0.0, 0.0, 0.0),
                             boresight=(0.0, 0.0, 0.0), mount=NADIR_MOUNT):
    """Exterior orientation (X0, R) of a camera from GNSS/IMU (direct georeferencing).

    Parameters
    ----------
    antenna : array_like, shape (3,)
        Position of the GNSS antenna (phase centre) in the object frame (east, north, up), m.
    roll, pitch, heading : float
        Attitude of the inertial unit, radians (:func:`rotation_body_to_ned`).
    lever_arm : array_like, shape (3,)
        Lever arm / Hebelarm: the vector from the camera's projection centre to the antenna,
        in the body frame (x forward, y right, z down), m.
    boresight : array_like, shape (3,)
        Boresight misalignment / Fehlausrichtung (ω, φ, κ), radians: the small rotation of the
        real camera frame against the nominal mount, ``R_mount·R_ω·R_φ·R_κ``.
    mount : array_like, shape (3, 3)
        Nominal camera → body rotation (default :data:`NADIR_MOUNT`, x' along the flight).

    Returns
    -------
    X0 : ndarray, shape (3,)
        Projection centre, ``X0 = antenna − R_nav·lever_arm`` with ``R_nav = NED_TO_ENU·R_nb``.
    R : ndarray, shape (3, 3)
        Camera → object rotation of the conventions, ``R = NED_TO_ENU·R_nb·mount·ΔR``.

    Notes
    -----
    A boresight error δ moves the ground point of the principal ray by ``H·δ`` (first order,
    :func:`photolib.derive.aerial.boresight_ground_shift`): 0.01° at 1000 m is 17 cm, which is
    why the boresight is calibrated in a test field; a lever-arm error enters X0 one to one.

    Examples
    --------
    >>> X0, R = exterior_from_navigation([500.0, 200.0, 1000.0], 0.0, 0.0, 0.0,
    ...                                  lever_arm=[0.2, 0.0, -1.5])
    >>> np.round(X0, 9).tolist()            # the antenna is 1.5 m above the camera
    [500.0, 199.8, 998.5]
    >>> np.round(R, 12).tolist()            # flying north: x' north, y' west, looking down
    [[0.0, -1.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, 1.0]]
    """
    from photolib._validate import as_vector3
    from photolib.rotations import rotation_opk

    antenna = as_vector3(antenna, "antenna")
    lever = as_vector3(lever_arm, "lever_arm")
    bore = as_vector3(boresight, "boresight")
    mount = np.asarray(mount, float)
    if mount.shape != (3, 3) or not np.allclose(mount @ mount.T, np.eye(3), atol=1e-9) \
            or not np.linalg.det(mount) > 0:
        raise ValueError(f"mount must be a 3×3 rotation matrix, got {mount.tolist()}")
    R_nav = NED_TO_ENU @ rotation_body_to_ned(roll, pitch, heading)
    return antenna - R_nav @ lever, R_nav @ mount @ rotation_opk(*bore)
