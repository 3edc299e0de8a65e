"""Chapter 06 pictures of aerial images: refraction, earth curvature and direct georeferencing.

:func:`correction_sizes` and :func:`plot_corrections` show how large the image displacements of
atmospheric refraction (:func:`photolib.refraction_constant`) and earth curvature
(:func:`photolib.earth_curvature_correction`) are for realistic flying heights and camera
constants; :func:`georeferencing_errors` and :func:`plot_georeferencing_errors` what a
boresight or lever-arm error of GNSS/IMU does on the ground (:func:`photolib.exterior_from_navigation`
and :func:`photolib.monoplot`).
"""

from __future__ import annotations

import numpy as np

import photolib as pl
from photolib.nb.live import finished

__all__ = ["correction_sizes", "georeferencing_errors", "plot_corrections",
           "plot_georeferencing_errors"]


def correction_sizes(heights, c, r=100.0, ground=0.0):
    """Radial image displacements at image radius ``r`` (mm) for flying heights above ground.

    Parameters
    ----------
    heights : array_like
        Flying heights above the ground H − h, m.
    c : float
        Camera constant, mm.
    r : float
        Image radius r' from the nadir (principal point), mm.
    ground : float
        Ground height h above sea level, m.

    Returns
    -------
    dict of ndarray
        ``refraction_icao``, ``refraction_ardc`` (outwards) and ``curvature`` (towards the
        nadir), µm: the size of the correction that :func:`photolib.refraction_correction` and
        :func:`photolib.earth_curvature_correction` apply.

    Examples
    --------
    >>> s = correction_sizes([3000.0], 153.0)
    >>> round(float(s["curvature"][0]), 2), round(float(s["refraction_ardc"][0]), 2)
    (10.06, 4.28)
    """
    heights = np.asarray(heights, float)
    xy = np.array([r, 0.0])
    out = {"refraction_icao": [], "refraction_ardc": [], "curvature": []}
    for H in heights:
        for model in ("icao", "ardc"):
            K = pl.refraction_constant(ground + H, ground, model=model)
            out[f"refraction_{model}"].append((r - pl.refraction_correction(xy, c, K)[0]) * 1e3)
        out["curvature"].append((pl.earth_curvature_correction(xy, c, H)[0] - r) * 1e3)
    return {k: np.array(v) for k, v in out.items()}


def plot_corrections(cameras=((153.0, "wide angle, c = 153 mm"), (303.0, "normal, c = 303 mm")),
                     r=100.0):
    """Two panels: the displacements against the flying height at r' = ``r`` for each camera,
    and against the image radius at a flying height of 3000 m (c = 153 mm)."""
    import matplotlib.pyplot as plt

    fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(8.0, 3.2))
    H = np.linspace(300.0, 9000.0, 30)
    styles = ("-", "--")
    for (c, label), ls in zip(cameras, styles):
        s = correction_sizes(H, c, r)
        ax1.plot(H / 1000, s["refraction_icao"], ls, color="#1f77b4",
                 label=f"refraction (ICAO), {label}")
        ax1.plot(H / 1000, s["curvature"], ls, color="#d62728", label=f"earth curvature, {label}")
    s = correction_sizes(H, cameras[0][0], r)
    ax1.plot(H / 1000, s["refraction_ardc"], ":", color="#1f77b4", label="refraction (ARDC), c = 153 mm")
    ax1.set(xlabel="flying height above ground H − h [km]", ylabel=f"Δr' at r' = {r:g} mm [µm]",
            title="size against flying height")
    ax1.legend(fontsize=6, loc="upper left")
    radii = np.linspace(0.0, 150.0, 31)
    c = cameras[0][0]
    K = pl.refraction_constant(3000.0)
    pts = np.column_stack([radii, np.zeros_like(radii)])
    ax2.plot(radii, (radii - pl.refraction_correction(pts, c, K)[:, 0]) * 1e3, color="#1f77b4",
             label="refraction, outwards")
    ax2.plot(radii, (pl.earth_curvature_correction(pts, c, 3000.0)[:, 0] - radii) * 1e3,
             color="#d62728", label="earth curvature, inwards")
    ax2.set(xlabel="image radius r' [mm]", ylabel="Δr' [µm]",
            title=f"H − h = 3 km, c = {c:g} mm")
    ax2.legend(fontsize=7)
    fig.tight_layout()
    return finished(fig)


def georeferencing_errors(height, boresight_deg=(0.0, 0.0, 0.0), lever_error=(0.0, 0.0, 0.0),
                          c=100.0, half=(40.0, 40.0), n=5, heading_deg=0.0):
    """Ground displacement of image points by a boresight or lever-arm error (direct
    georeferencing of a level nadir image over flat ground).

    Parameters
    ----------
    height : float
        Flying height above the ground, m.
    boresight_deg : 3 floats
        Boresight error (ω, φ, κ) not calibrated, degrees.
    lever_error : 3 floats
        Error of the lever arm in the body frame, m.
    c, half, n
        Camera constant (mm), half image format (mm) and grid points per side.
    heading_deg : float
        Heading of the flight, degrees.

    Returns
    -------
    dict
        ``ground`` (n², 3) the true ground points, ``shift`` (n², 2) the displacement of each
        in m, ``centre_shift`` the displacement of the principal point's ground point.

    Examples
    --------
    >>> e = georeferencing_errors(1000.0, boresight_deg=(0.01, 0.0, 0.0))
    >>> round(float(np.hypot(*e["centre_shift"])), 3)   # H·δ = 1000 m · 0.01° in rad
    0.175
    """
    antenna = [0.0, 0.0, float(height)]
    args = (0.0, 0.0, np.radians(heading_deg))
    X0, R = pl.exterior_from_navigation(antenna, *args)
    X0e, Re = pl.exterior_from_navigation(antenna, *args, lever_arm=lever_error,
                                          boresight=np.radians(boresight_deg))
    # the orientation used has no boresight and no lever arm; the real camera has both
    X0_true = X0e
    g = np.linspace(-1.0, 1.0, n)
    xy = np.array([(u * half[0], v * half[1]) for v in g for u in g] + [(0.0, 0.0)])
    true = pl.monoplot(xy, X0_true, Re, c, Z=0.0)        # where the rays really meet the ground
    used = pl.monoplot(xy, X0, R, c, Z=0.0)              # where the nominal orientation puts them
    shift = used[:, :2] - true[:, :2]
    return {"ground": true[:-1], "shift": shift[:-1], "centre_shift": shift[-1]}


def plot_georeferencing_errors(boresight_deg=(0.01, 0.01, 0.02), height=1000.0):
    """Two panels: ground shift against flying height for boresight and lever-arm errors, and
    the displacement field over the footprint for one boresight error."""
    import matplotlib.pyplot as plt

    fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(8.0, 3.4))
    H = np.linspace(200.0, 4000.0, 20)
    for d, col in ((0.001, "#2ca02c"), (0.005, "#1f77b4"), (0.01, "#9467bd"), (0.05, "#d62728")):
        shift = [np.hypot(*georeferencing_errors(h, (d, 0.0, 0.0))["centre_shift"]) for h in H]
        ax1.plot(H, shift, color=col, label=f"boresight δω = {d:g}°")
    lever = [np.hypot(*georeferencing_errors(h, lever_error=(0.05, 0.0, 0.0))["centre_shift"])
             for h in H]
    ax1.plot(H, lever, "k--", label="lever arm off by 5 cm")
    ax1.set(xlabel="flying height above ground [m]", ylabel="ground shift [m]", yscale="log",
            title="principal point on the ground")
    ax1.legend(fontsize=7)
    e = georeferencing_errors(height, boresight_deg)
    scale = 0.12 * 2 * np.max(np.abs(e["ground"][:, :2])) / max(np.max(np.hypot(*e["shift"].T)), 1e-12)
    ax2.quiver(e["ground"][:, 0], e["ground"][:, 1], e["shift"][:, 0], e["shift"][:, 1],
               angles="xy", scale_units="xy", scale=1.0 / scale, color="#d62728")
    lim = 1.25 * np.max(np.abs(e["ground"][:, :2]))
    ax2.set(xlim=(-lim, lim), ylim=(-lim, lim), aspect="equal", xlabel="X (east) [m]", ylabel="Y (north) [m]",
            title="boresight (ω, φ, κ) = ({:g}°, {:g}°, {:g}°), H = {:g} m".format(*boresight_deg,
                                                                                    height))
    ax2.title.set_fontsize(8)
    m = np.max(np.hypot(*e["shift"].T))
    ax2.text(0.02, 0.02, f"largest shift {m:.2f} m (arrows ×{scale:.0f})", transform=ax2.transAxes,
             fontsize=7)
    fig.tight_layout()
    return finished(fig)
