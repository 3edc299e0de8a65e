"""Chapter 02 pictures and widgets: optics of the camera (Optik).

The chapter's lens is a thin lens of f = 50 mm on a 36 mm × 24 mm format with the lecture
summary's circle of confusion u' = s'/1500 (s' the format diagonal, 43.3 mm → 29 µm).
Reports (``*_report``) compute what a widget shows, with :mod:`photolib.optics`, and return
plain dicts with an HTML text; the explorers only move artists.
"""

from __future__ import annotations

import functools

import numpy as np

import photolib.optics as po
from photolib.nb.live import Explorer, LiveFigure, finished, slider

__all__ = [
    "DIAGONAL_MM",
    "F_MM",
    "U_MM",
    "AiryExplorer",
    "DepthOfFieldExplorer",
    "ThinLensExplorer",
    "airy_report",
    "dof_report",
    "lens_rays",
    "plot_airy_profile",
    "plot_chromatic_shift",
    "plot_dispersion",
    "plot_edge_diffraction",
    "plot_grating",
    "plot_pinhole_blur",
    "plot_refraction",
    "plot_stereo_acuity",
    "plot_vignetting_map",
    "thin_lens_report",
]

#: focal length of the chapter's lens, mm
F_MM = 50.0
#: format diagonal of 36 mm × 24 mm, mm
DIAGONAL_MM = float(np.hypot(36.0, 24.0))
#: circle of confusion u' = s'/1500 of the lecture summary, mm
U_MM = DIAGONAL_MM / 1500.0
_U_UM = round(U_MM * 1e3, 1)  # the explorer's start value, µm


# -- thin lens ------------------------------------------------------------------------------------

def lens_rays(a: float, f: float, height: float = 10.0):
    """The three construction rays of a thin lens, as polylines (z, y) in mm.

    The object arrow stands at z = −a with tip (−a, height); the lens is the plane z = 0.
    Ray 1 runs parallel to the axis and then through the focus F' = (f, 0); ray 2 passes
    the centre undeviated; ray 3 passes the front focus F = (−f, 0) and leaves parallel.
    For a > f they meet at the image tip (a', −height·a'/a); for a ≤ f they diverge (a
    virtual image) and are drawn to z = 3f.

    Returns
    -------
    list of ndarray, each shape (3, 2)

    Examples
    --------
    >>> rays = lens_rays(150.0, 50.0)
    >>> [r[-1].round(6).tolist() for r in rays]
    [[75.0, -5.0], [75.0, -5.0], [75.0, -5.0]]
    """
    a, f, h = float(a), float(f), float(height)
    z_end = po.image_distance(a, f) if a > f else 3.0 * f
    tip = np.array([-a, h])
    ray1 = np.array([tip, [0.0, h], [z_end, h - h * z_end / f]])
    ray2 = np.array([tip, [0.0, 0.0], [z_end, -h * z_end / a]])
    if abs(a - f) < 1e-9:
        ray3 = np.array([tip, [0.0, h], [z_end, h]])  # through F: cannot reach the lens below
    else:
        y_lens = h * f / (f - a)  # the line from the tip through F = (−f, 0) at z = 0
        ray3 = np.array([tip, [0.0, y_lens], [z_end, y_lens]])
    return [ray1, ray2, ray3]


def thin_lens_report(a: float = 150.0, f: float = F_MM, height: float = 10.0) -> dict:
    """Image distance, scale number and image height of a thin lens (mm).

    Returns
    -------
    dict
        ``real`` (bool), ``image_distance`` a' (NaN if no real image), ``scale_number``
        m_b = a/a', ``image_height`` (−height/m_b), ``rays`` (see :func:`lens_rays`),
        ``virtual`` (z, y) of the virtual image tip for a < f (else None), ``html``.

    Examples
    --------
    >>> rep = thin_lens_report(150.0, 50.0)
    >>> rep["image_distance"], rep["scale_number"]
    (75.0, 2.0)
    >>> thin_lens_report(40.0, 50.0)["real"]
    False
    """
    rays = lens_rays(a, f, height)
    try:
        ap = po.image_distance(a, f)
    except po.NoRealImageError:
        html = (f"<p>a = {a:.1f} mm, f = {f:.1f} mm<br><span style='color:#b00'>a ≤ f: the "
                "object is inside the focal length, the rays diverge: no real image (a "
                "virtual image, as in a magnifying glass)</span></p>")
        virtual = None
        if a < f:  # the rays after the lens, extended backwards, meet upright and enlarged
            virtual = (-a * f / (f - a), height * f / (f - a))
            html = html.replace("</span></p>", f"</span><br>virtual image at z = "
                                f"{virtual[0]:.1f} mm, height {virtual[1]:+.1f} mm</p>")
        return {"real": False, "image_distance": np.nan, "scale_number": np.nan,
                "image_height": np.nan, "rays": rays, "virtual": virtual, "html": html}
    mb = a / ap
    html = (f"<p>a = {a:.1f} mm, f = {f:.1f} mm<br>"
            f"image distance a' = af/(a − f) = <b>{ap:.2f} mm</b><br>"
            f"scale number m<sub>b</sub> = a/a' = <b>{mb:.3f}</b> (image scale 1 : {mb:.3f})<br>"
            f"image height {-height / mb:+.2f} mm (inverted)</p>")
    return {"real": True, "image_distance": ap, "scale_number": mb,
            "image_height": -height / mb, "rays": rays, "virtual": None, "html": html}


# -- depth of field -------------------------------------------------------------------------------

#: object distances of the depth-of-field curve, mm (0.3 m … 100 m)
DISTANCES_MM = np.geomspace(300.0, 1e5, 240)


def dof_report(k: float = 8.0, focus_m: float = 5.0, u_um: float = U_MM * 1e3,
               f: float = F_MM) -> dict:
    """Depth of field of the chapter's lens: limits, hyperfocal distance and the blur curve.

    Parameters
    ----------
    k : float
        f-number.
    focus_m : float
        Focus distance a, m.
    u_um : float
        Circle of confusion u', µm.
    f : float
        Focal length, mm.

    Returns
    -------
    dict
        ``dof`` (:class:`photolib.optics.DepthOfField`, mm), ``distances`` (mm) and ``blur``
        (µm) of the blur curve, ``html``.

    Examples
    --------
    >>> rep = dof_report(8.0, 5.0, 30.0)
    >>> round(rep["dof"].near), round(rep["dof"].far)
    (3389, 9527)
    """
    a = float(focus_m) * 1e3
    u = float(u_um) * 1e-3
    dof = po.depth_of_field(a, f, k, u)
    blur = np.asarray(po.blur_diameter(DISTANCES_MM, a, f, k)) * 1e3
    far = "∞" if np.isinf(dof.far) else f"{dof.far / 1e3:.3f} m"
    depth = "∞" if np.isinf(dof.depth) else f"{dof.depth / 1e3:.3f} m"
    html = (f"<p>f = {f:.0f} mm, k = {k:.1f}, a = {a / 1e3:.2f} m, u' = {u_um:.1f} µm<br>"
            f"near limit a<sub>v</sub> = <b>{dof.near / 1e3:.3f} m</b><br>"
            f"far limit a<sub>h</sub> = <b>{far}</b><br>depth t = {depth}<br>"
            f"hyperfocal distance H = {dof.hyperfocal / 1e3:.2f} m</p>")
    return {"dof": dof, "distances": DISTANCES_MM, "blur": blur, "html": html}


# -- Airy disk ------------------------------------------------------------------------------------

@functools.lru_cache(maxsize=1)
def _airy_table():
    """The Airy pattern on v = πr/(λk) ∈ [0, 40], computed once with SciPy's Bessel J1."""
    v = np.linspace(0.0, 40.0, 4001)
    return v, np.asarray(po.airy_psf(v, np.pi, 1.0))  # λk = π: r = v


def _airy_fast(r_um, lam_um, k):
    v, table = _airy_table()
    return np.interp(np.pi * np.abs(r_um) / (lam_um * k), v, table, right=0.0)


def airy_report(wavelength_nm: float = 550.0, k: float = 8.0, pixel_um: float = 4.0,
                half_um: float = 20.0, n: int = 121) -> dict:
    """The Airy pattern of a diffraction-limited lens against the pixel grid.

    Returns
    -------
    dict
        ``radius_um`` (Airy radius 1.22·λ·k), ``diameter_px`` (Airy disk diameter in
        pixels), ``image`` (n × n PSF on ±``half_um``), ``r_um``/``profile`` (radial
        profile), ``pixel_psf`` (the PSF integrated over each pixel of a 5 × 5 patch,
        normalised to sum 1), ``html``.

    Examples
    --------
    >>> rep = airy_report(550.0, 8.0, 4.0)
    >>> round(rep["radius_um"], 3), round(rep["diameter_px"], 3)
    (5.367, 2.683)
    """
    lam = float(wavelength_nm) * 1e-3
    radius = po.airy_radius(lam, k)
    t = np.linspace(-half_um, half_um, n)
    X, Y = np.meshgrid(t, t)
    image = _airy_fast(np.hypot(X, Y), lam, k)
    r = np.linspace(0.0, half_um, 400)
    profile = _airy_fast(r, lam, k)
    # pixel integration: 9 × 9 samples per pixel over a 5 × 5 pixel patch centred on a pixel
    s = (np.arange(9) + 0.5) / 9 - 0.5
    centres = (np.arange(5) - 2) * pixel_um
    fine = (centres[:, None] + s[None, :] * pixel_um).ravel()
    FX, FY = np.meshgrid(fine, fine)
    fine_psf = _airy_fast(np.hypot(FX, FY), lam, k).reshape(5, 9, 5, 9).sum(axis=(1, 3))
    pixel_psf = fine_psf / fine_psf.sum()
    html = (f"<p>λ = {wavelength_nm:.0f} nm, k = {k:.1f}<br>"
            f"Airy radius r<sub>A</sub> = 1.22·λ·k = <b>{radius:.2f} µm</b><br>"
            f"disk diameter 2r<sub>A</sub> = {2 * radius:.2f} µm = "
            f"<b>{2 * radius / pixel_um:.2f} pixels</b> of {pixel_um:.1f} µm<br>"
            f"centre pixel holds {pixel_psf[2, 2] * 100:.1f} % of the 5 × 5 light</p>")
    return {"radius_um": radius, "diameter_px": 2 * radius / pixel_um, "image": image,
            "extent": (-half_um, half_um, -half_um, half_um), "r_um": r, "profile": profile,
            "pixel_psf": pixel_psf, "html": html}


_SUPERSCRIPTS = str.maketrans("-0123456789", "⁻⁰¹²³⁴⁵⁶⁷⁸⁹")


def _decade_label(value, _pos=None) -> str:
    """Tick label ``10ⁿ`` of a decade as plain text (Unicode superscripts), else ``""``.

    It reads as matplotlib's default log labels; those are mathtext (``$10^{n}$``), and
    laying them out cost a log–log figure some 0.15 s of its 0.25 s draw.
    """
    if not value > 0:
        return ""
    n = np.log10(value)
    if abs(n - round(n)) > 1e-9:
        return ""
    return "10" + str(int(round(n))).translate(_SUPERSCRIPTS)


def _decade_labels(*axes):
    """Label the major ticks of the given log-scaled axes (``ax.xaxis``, …) 10ⁿ, as text."""
    import matplotlib.ticker as mticker

    for axis in axes:
        axis.set_major_formatter(mticker.FuncFormatter(_decade_label))


# -- static figures -------------------------------------------------------------------------------

def plot_refraction(n1: float = 1.0, n2: float = 1.5, angles_deg=(10, 30, 50, 70, 85)):
    """Rays from one point refracted at a plane interface z = 0 (Snell), with reflections."""
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(5.4, 3.6))
    # shade the denser medium
    ax.axhspan(*((0, 2.2) if n1 > n2 else (-2.2, 0)), color="#c6dbef", alpha=0.5)
    ax.axhline(0, color="0.3", lw=1)
    for deg in angles_deg:
        alpha = np.radians(deg)
        d = np.array([np.sin(alpha), 0.0, -np.cos(alpha)])
        start = -2.0 * d
        t, valid = po.refract(d, [0.0, 0.0, 1.0], n1, n2, on_total_reflection="flag")
        line, = ax.plot([start[0], 0], [start[2], 0], lw=1.4)
        colour = line.get_color()
        ax.plot([0, 2.0 * t[0]], [0, 2.0 * t[2]], color=colour, lw=1.4,
                ls="-" if valid else "--", label=f"α = {deg}°" + ("" if valid else " (TIR)"))
    ax.set(xlim=(-2.1, 2.1), ylim=(-2.2, 2.2), aspect="equal", xlabel="x", ylabel="z",
           title=f"refraction / Brechung: n1 = {n1:g} (top), n2 = {n2:g} (bottom)")
    ax.legend(fontsize=7, loc="upper right")
    return finished(fig)


def plot_dispersion(glasses=("N-BK7", "F2", "N-SF11", "fused silica")):
    """n(λ) of some glasses by the Sellmeier formula over the visible range."""
    import matplotlib.pyplot as plt

    lam = np.linspace(0.38, 0.78, 200)
    fig, ax = plt.subplots(figsize=(5.4, 3.2))
    for g in glasses:
        ax.plot(lam * 1e3, po.refractive_index(lam, g),
                label=f"{g} (V_d = {po.abbe_number(g):.1f})")
    for w, name in ((po.F_LINE, "F"), (po.D_LINE, "d"), (po.C_LINE, "C")):
        ax.axvline(w * 1e3, color="0.6", lw=0.8, ls=":")
        ax.text(w * 1e3, 1.44, name, ha="center", fontsize=8)
    ax.set(xlabel="wavelength λ [nm]", ylabel="refractive index n",
           title="dispersion / Dispersion (Sellmeier)")
    ax.legend(fontsize=7)
    return finished(fig)


def plot_chromatic_shift(f: float = F_MM, glass: str = "N-BK7"):
    """Longitudinal chromatic aberration f(λ) − f(d line) of a thin single lens, mm."""
    import matplotlib.pyplot as plt

    lam = np.linspace(0.40, 0.75, 200)
    fig, ax = plt.subplots(figsize=(5.4, 3.0))
    ax.plot(lam * 1e3, po.chromatic_focal_shift(f, lam, glass=glass), color="#9467bd")
    ax.axhline(0, color="0.5", lw=0.8)
    ax.set(xlabel="wavelength λ [nm]", ylabel="f(λ) − f_d [mm]",
           title=f"chromatic focal shift / Farblängsfehler, f = {f:g} mm, {glass}")
    return finished(fig)


def plot_airy_profile(wavelength_nm: float = 550.0, k: float = 8.0, half_um: float = 20.0):
    """Radial Airy profile and encircled energy, with the Airy radius marked."""
    import matplotlib.pyplot as plt

    lam = wavelength_nm * 1e-3
    r = np.linspace(0.0, half_um, 300)
    fig, ax = plt.subplots(figsize=(5.4, 3.0))
    ax.plot(r, po.airy_psf(r, lam, k), label="I(r)/I₀")
    ax.plot(r, po.airy_encircled_energy(r, lam, k), label="encircled energy")
    ax.axvline(po.airy_radius(lam, k), color="#d62728", lw=1, ls="--", label="r_A = 1.22 λk")
    ax.set(xlabel="r [µm]", ylabel="relative", ylim=(0, 1.05),
           title=f"Airy pattern / Beugungsscheibchen, λ = {wavelength_nm:g} nm, k = {k:g}")
    ax.legend(fontsize=7)
    return finished(fig)


def plot_edge_diffraction(wavelength_nm: float = 550.0, distance_mm: float = 1000.0,
                          half_mm: float = 2.5):
    """Fresnel fringes behind a straight edge: the profile and the pattern as a grey image."""
    import matplotlib.pyplot as plt

    lam_um, z_um = wavelength_nm * 1e-3, distance_mm * 1e3
    x_mm = np.linspace(-half_mm / 2, half_mm, 1200)
    intensity = po.edge_diffraction(x_mm * 1e3, lam_um, z_um)
    x1 = po.edge_first_fringe(lam_um, z_um) * 1e-3
    fig, (top, bottom) = plt.subplots(2, 1, figsize=(5.4, 3.6), sharex=True,
                                      gridspec_kw={"height_ratios": [3, 1]})
    top.plot(x_mm, intensity, lw=1.2, label="I/I₀ (Fresnel)")
    top.plot(x_mm, (x_mm >= 0).astype(float), color="0.5", lw=1, ls=":",
             label="geometric shadow")
    top.axvline(x1, color="#d62728", lw=1, ls="--",
                label=f"first fringe x₁ = {x1:.3f} mm, I = 1.37 I₀")
    top.axhline(0.25, color="#2ca02c", lw=0.8, ls="-.", label="¼ on the shadow line")
    top.set(ylabel="I/I₀", ylim=(0, 1.5),
            title=f"edge / Kante: λ = {wavelength_nm:g} nm, screen at z = {distance_mm:g} mm")
    top.legend(fontsize=7, loc="upper left")
    bottom.imshow(np.tile(intensity, (20, 1)), cmap="gray", aspect="auto", vmin=0, vmax=1.4,
                  extent=(x_mm[0], x_mm[-1], 0, 1))
    bottom.set(xlabel="x from the shadow line [mm] (x < 0: shadow)", yticks=[])
    return finished(fig)


def plot_grating(wavelength_nm: float = 550.0, pitch_um: float = 2.0, slit_um: float = 0.6,
                 slits=(2, 5, 20)):
    """N-slit Fraunhofer patterns of one grating: sharper orders as N grows, one envelope."""
    import matplotlib.pyplot as plt

    lam = wavelength_nm * 1e-3
    theta = np.radians(np.linspace(-60.0, 60.0, 4001))
    fig, ax = plt.subplots(figsize=(5.4, 3.0))
    for n in slits:
        ax.plot(np.degrees(theta), po.grating_intensity(theta, lam, pitch_um, slit_um, n),
                lw=1, label=f"N = {n}")
    envelope = np.sinc(slit_um * np.sin(theta) / lam) ** 2
    ax.plot(np.degrees(theta), envelope, color="0.3", ls="--", lw=1, label="single slit")
    top = int(np.floor(pitch_um / lam))
    for m in range(-top, top + 1):
        angle = float(np.degrees(po.grating_angles(pitch_um, lam, m)))
        if abs(angle) <= 60.0:
            ax.annotate(f"m = {m}", (angle, 1.02), ha="center", fontsize=7)
    ax.set(xlabel="θ [°]", ylabel="I(θ)/I(0)", ylim=(0, 1.12),
           title=f"grating / Gitter: d = {pitch_um:g} µm, a = {slit_um:g} µm, "
                 f"λ = {wavelength_nm:g} nm")
    ax.legend(fontsize=7, loc="center right")
    return finished(fig)


def plot_vignetting_map(c: float = 24.0, half=(18.0, 12.0)):
    """cos⁴ natural vignetting over a format, as an image with contour lines."""
    import matplotlib.pyplot as plt

    x = np.linspace(-half[0], half[0], 145)
    y = np.linspace(-half[1], half[1], 97)
    X, Y = np.meshgrid(x, y)
    E = po.natural_vignetting(np.column_stack([X.ravel(), Y.ravel()]), c).reshape(X.shape)
    fig, ax = plt.subplots(figsize=(5.4, 3.4))
    im = ax.imshow(E, extent=(x[0], x[-1], y[0], y[-1]), origin="lower", vmin=0, vmax=1,
                   cmap="gray")
    cs = ax.contour(X, Y, E, levels=[0.5, 0.6, 0.7, 0.8, 0.9], colors="#ff7f0e",
                    linewidths=0.8)
    ax.clabel(cs, fontsize=7)
    fig.colorbar(im, ax=ax, label="E(τ)/E(0) = cos⁴τ")
    ax.set(xlabel="x' [mm]", ylabel="y' [mm]",
           title=f"natural vignetting / Lichtabfall, c = {c:g} mm")
    return finished(fig)


def plot_pinhole_blur(c: float = 100.0, wavelength_nm: float = 550.0):
    """Blur of a pinhole camera: hole diameter + Airy disk diameter, and the optimum."""
    import matplotlib.pyplot as plt

    lam = wavelength_nm * 1e-6  # mm
    d = np.linspace(0.05, 1.0, 300)
    airy = 2 * po.airy_radius(lam, c / d)  # diffraction: k = c/d
    fig, ax = plt.subplots(figsize=(5.4, 3.0))
    ax.plot(d, d, "--", label="geometric: d")
    ax.plot(d, airy, "--", label="diffraction: 2·1.22·λc/d")
    ax.plot(d, d + airy, color="k", label="sum")
    d_opt = np.sqrt(2 * po.J1_FIRST_ZERO / np.pi * lam * c)
    ax.plot([d_opt], [2 * d_opt], "o", color="#d62728", label=f"optimum d = {d_opt:.3f} mm")
    ax.set(xlabel="pinhole diameter d [mm]", ylabel="blur diameter [mm]", ylim=(0, 1.2),
           title=f"pinhole camera / Lochkamera, c = {c:g} mm")
    ax.legend(fontsize=7)
    return finished(fig)


def plot_stereo_acuity(base_mm: float = 65.0, acuity_arcsec=(5.0, 10.0, 30.0)):
    """Smallest depth difference seen with two eyes over the distance (log–log)."""
    import matplotlib.pyplot as plt

    Z = np.geomspace(250.0, 1e6, 200)
    fig, ax = plt.subplots(figsize=(5.4, 3.2))
    for s in acuity_arcsec:
        eps = np.radians(s / 3600.0)
        ax.loglog(Z / 1e3, po.stereo_depth_acuity(Z, base_mm, eps) / 1e3, label=f"ε = {s:g}''")
    ax.set(xlabel="distance Z [m]", ylabel="ΔZ [m]",
           title=f"stereoscopic depth acuity, eye base b = {base_mm:g} mm")
    # decades only: the minor ticks of a log–log plot over seven decades cost a third of its draw
    ax.minorticks_off()
    _decade_labels(ax.xaxis, ax.yaxis)
    ax.legend(fontsize=7)
    return finished(fig)


# -- widgets --------------------------------------------------------------------------------------

class ThinLensExplorer(Explorer):
    """Object distance and focal length → ray diagram, image distance and scale number."""

    title = "thin lens explorer"
    height = 10.0

    def __init__(self, a=150.0, f=F_MM):
        self.controls = {"a": slider("object dist. a [mm]", a, 20, 400, 1, fmt=".0f"),
                         "f": slider("focal length f [mm]", f, 20, 100, 1, fmt=".0f")}
        self.live = LiveFigure((6.0, 3.0))
        ax = self.live.figure.add_subplot()
        self.live.figure.subplots_adjust(0.1, 0.17, 0.98, 0.9)
        ax.axhline(0, color="0.5", lw=0.8)
        ax.plot([0, 0], [-22, 22], color="#1f77b4", lw=3, alpha=0.4)
        ax.set(xlim=(-410, 420), ylim=(-25, 25), xlabel="z [mm]", ylabel="y [mm]",
               title="thin lens / dünne Linse: construction rays")
        self._object = self.live.animate(ax.annotate(
            "", xy=(0, 0), xytext=(0, 0), arrowprops={"arrowstyle": "-|>", "color": "#2ca02c",
                                                      "lw": 2}))
        self._image = self.live.animate(ax.annotate(
            "", xy=(0, 0), xytext=(0, 0), arrowprops={"arrowstyle": "-|>", "color": "#d62728",
                                                      "lw": 2}))
        colours = ("#ff7f0e", "#9467bd", "#8c564b")
        self._rays = [self.live.animate(ax.plot([], [], color=c, lw=1.2)[0]) for c in colours]
        (self._foci,) = ax.plot([], [], "k+", ms=9, mew=1.5)
        (self._virtual,) = ax.plot([], [], ":", color="0.4", lw=1.2)
        self.live.animate(self._foci)
        self.live.animate(self._virtual)
        self.report = None
        self._finish()

    def draw(self, a, f) -> str:
        self.report = rep = thin_lens_report(a, f, self.height)
        self._object.xy, self._object.xyann = (-a, self.height), (-a, 0.0)
        if rep["real"]:
            ap = rep["image_distance"]
            self._image.xy, self._image.xyann = (ap, rep["image_height"]), (ap, 0.0)
            self._image.set_visible(True)
        else:
            self._image.set_visible(False)
        for line, ray in zip(self._rays, rep["rays"]):
            line.set_data(*ray.T)
        if rep["virtual"] is None:
            self._virtual.set_data([], [])
        else:  # back-extensions of rays 1 and 2 and the upright virtual image
            zv, yv = rep["virtual"]
            self._virtual.set_data([0.0, zv, np.nan, 0.0, zv, np.nan, zv, zv],
                                   [self.height, yv, np.nan, 0.0, yv, np.nan, 0.0, yv])
        self._foci.set_data([-f, f], [0.0, 0.0])
        return rep["html"]


class DepthOfFieldExplorer(Explorer):
    """f-number, focus distance and circle of confusion → near and far limit on the blur curve."""

    title = "depth of field explorer"

    def __init__(self, k=8.0, focus_m=5.0, u_um=_U_UM):
        self.controls = {"k": slider("f-number k", k, 1.4, 22, 0.1, fmt=".1f"),
                         "focus_m": slider("focus a [m]", focus_m, 0.5, 20, 0.1, fmt=".1f"),
                         "u_um": slider("u' [µm]", u_um, 5, 60, 0.5, fmt=".1f")}
        self.live = LiveFigure((6.0, 3.0))
        ax = self.live.figure.add_subplot()
        self.live.figure.subplots_adjust(0.12, 0.17, 0.98, 0.9)
        ax.set(xscale="log", xlim=(0.3, 100), ylim=(0, 150), xlabel="object distance [m]",
               ylabel="blur u' [µm]", title=f"depth of field / Schärfentiefe, f = {F_MM:g} mm")
        _decade_labels(ax.xaxis)
        self._band = self.live.animate(ax.axvspan(1.0, 2.0, color="#2ca02c", alpha=0.2))
        (self._curve,) = ax.plot([], [], color="#1f77b4")
        (self._limit,) = ax.plot([], [], "--", color="#d62728", lw=1)
        (self._marks,) = ax.plot([], [], "o", color="#d62728", ms=5)
        (self._focus,) = ax.plot([], [], "v", color="k", ms=7)
        for artist in (self._curve, self._limit, self._marks, self._focus):
            self.live.animate(artist)
        self.report = None
        self._finish()

    def draw(self, k, focus_m, u_um) -> str:
        self.report = rep = dof_report(k, focus_m, u_um)
        dof = rep["dof"]
        self._curve.set_data(rep["distances"] / 1e3, rep["blur"])
        self._limit.set_data([0.3, 100], [u_um, u_um])
        far = min(dof.far / 1e3, 1e3)
        self._band.set_x(dof.near / 1e3)
        self._band.set_width(far - dof.near / 1e3)
        self._marks.set_data([dof.near / 1e3, far], [u_um, u_um])
        self._focus.set_data([focus_m], [2.0])
        return rep["html"]


class AiryExplorer(Explorer):
    """Wavelength, f-number and pixel pitch → the Airy disk over the pixel grid."""

    title = "Airy disk explorer"
    half = 20.0

    def __init__(self, wavelength_nm=550.0, k=8.0, pixel_um=4.0):
        self.controls = {"wavelength_nm": slider("λ [nm]", wavelength_nm, 400, 700, 5, fmt=".0f"),
                         "k": slider("f-number k", k, 1.4, 22, 0.1, fmt=".1f"),
                         "pixel_um": slider("pixel [µm]", pixel_um, 1, 10, 0.1, fmt=".1f")}
        self.live = LiveFigure((6.4, 3.0))
        fig = self.live.figure
        ax = fig.add_subplot(1, 2, 1)
        bx = fig.add_subplot(1, 2, 2)
        fig.subplots_adjust(0.08, 0.17, 0.98, 0.9, wspace=0.3)
        h = self.half
        self._img = self.live.animate(ax.imshow(np.zeros((121, 121)), extent=(-h, h, -h, h),
                                                origin="lower", vmin=0, vmax=1, cmap="magma"))
        (self._grid,) = ax.plot([], [], color="#7fdbff", lw=0.6)
        (self._circle,) = ax.plot([], [], color="w", lw=0.8, ls="--")
        ax.set(xlim=(-h, h), ylim=(-h, h), xlabel="x' [µm]", ylabel="y' [µm]",
               title="√PSF (rings visible) and pixels")
        ax.grid(False)
        bx.set(xlim=(0, h), ylim=(0, 1.05), xlabel="r [µm]", ylabel="I/I₀",
               title="radial profile")
        (self._profile,) = bx.plot([], [], color="#1f77b4")
        (self._radius,) = bx.plot([], [], "--", color="#d62728", lw=1)
        (self._pixel,) = bx.plot([], [], color="#ff7f0e", lw=2, label="half a pixel")
        bx.legend(fontsize=7, loc="upper right")
        for artist in (self._grid, self._circle, self._profile, self._radius, self._pixel):
            self.live.animate(artist)
        self.report = None
        self._finish()

    def draw(self, wavelength_nm, k, pixel_um) -> str:
        self.report = rep = airy_report(wavelength_nm, k, pixel_um, self.half)
        self._img.set_data(np.sqrt(rep["image"]))
        h = self.half
        edges = (np.arange(-20, 21) + 0.5) * pixel_um
        edges = edges[np.abs(edges) <= h]
        xs, ys = [], []
        for e in edges:
            xs += [e, e, np.nan, -h, h, np.nan]
            ys += [-h, h, np.nan, e, e, np.nan]
        self._grid.set_data(xs, ys)
        t = np.linspace(0, 2 * np.pi, 73)
        r = rep["radius_um"]
        self._circle.set_data(r * np.cos(t), r * np.sin(t))
        self._profile.set_data(rep["r_um"], rep["profile"])
        self._radius.set_data([r, r], [0, 1.05])
        self._pixel.set_data([0, pixel_um / 2], [0.02, 0.02])
        return rep["html"]
