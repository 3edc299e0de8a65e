"""Chapter 01 pictures and widgets: what photogrammetry is (Was ist Photogrammetrie?).

* :class:`ImageScaleExplorer`: camera constant, object distance and pixel size → image scale
  number, ground sampling distance and footprint, from close range to aerial;
* :class:`FlightBlockExplorer`: flying height, forward overlap and side lap → the images of a
  photo flight over a block (Bildflugplanung), by :func:`photolib.sensors.flight_block`;
* :func:`plot_timeline` and :func:`plot_process`: the history after the sources, and the
  photogrammetric process.
"""

from __future__ import annotations

import numpy as np

from photolib import sensors as ps
from photolib.nb.live import Explorer, LiveFigure, finished, slider

__all__ = [
    "BLOCK_M",
    "CONFIGURATIONS",
    "FLIGHT_CAMERA",
    "HISTORY",
    "SENSOR_PX",
    "FlightBlockExplorer",
    "ImageScaleExplorer",
    "configuration",
    "flight_report",
    "footprint_outlines",
    "plot_process",
    "plot_timeline",
    "scale_report",
]

#: sensor of the image-scale explorer: 6000 × 4000 pixels
SENSOR_PX = (6000, 4000)
#: (name, distance range in m) of typical configurations, for the explorer's bands
CONFIGURATIONS = (("close range / Nahbereich", 0.3, 100.0), ("UAV / Drohne", 30.0, 150.0),
                  ("aerial / Luftbild", 300.0, 6000.0), ("satellite / Satellit", 4e5, 8e5))
#: block of the flight-planning explorer, m (length along the flight, width across)
BLOCK_M = (4000.0, 3000.0)
#: the flight camera: c (mm), pixel (mm), pixels along and across the flight
FLIGHT_CAMERA = {"c": 100.5, "pixel": 0.004, "n_along": 7000, "n_across": 11000}

#: (year, short label, event, source) of the history, as the sources tell it; the years of the
#: three stages are decades for the figure, not dates from the sources
HISTORY = (
    (1858, "Meydenbauer, Wetzlar", "Meydenbauer nearly falls while surveying Wetzlar "
     "cathedral: measure the façade from photographs instead", "hu-wiki"),
    (1867, "the word 'Photogrammetrie'", "the word first printed (Wochenblatt des "
     "Architektenvereins zu Berlin), by Meydenbauer", "hu-wiki"),
    (1910, "ISP (ISPRS), Vienna", "International Society for Photogrammetry (ISP, today "
     "ISPRS) founded in Vienna", "hu-wiki"),
    (1930, "analogue plotters", "analogue photogrammetry: optical-mechanical stereo plotters "
     "map whole countries", "hu-wiki, de-summary"),
    (1960, "analytical plotters", "analytical photogrammetry: analogue images, "
     "computer-controlled analytical plotters", "hu-wiki, de-summary"),
    (1990, "digital workstations", "digital photogrammetry: digital images, digital "
     "photogrammetric workstations (DPWS)", "hu-wiki, de-summary"),
)


def configuration(distance_m: float) -> str:
    """The typical configuration of an object distance (m), by :data:`CONFIGURATIONS`.

    >>> configuration(5.0), configuration(1200.0)
    ('close range / Nahbereich', 'aerial / Luftbild')
    """
    d = float(distance_m)
    names = [name for name, lo, hi in CONFIGURATIONS if lo <= d <= hi]
    return " or ".join(names) if names else "between the usual configurations"


def scale_report(c_mm: float, log_distance: float, pixel_um: float) -> dict:
    """Image scale, GSD and footprint of a nadir (or normal-case) image.

    Parameters
    ----------
    c_mm : float
        Camera constant, mm.
    log_distance : float
        log₁₀ of the object distance or flying height in m.
    pixel_um : float
        Pixel pitch, µm.

    Returns
    -------
    dict
        ``distance`` (m), ``scale_number`` (m_b = H/c), ``gsd`` (m), ``footprint`` (width,
        height in m of a :data:`SENSOR_PX` sensor), ``configuration``, ``html``.

    Examples
    --------
    >>> rep = scale_report(100.0, 3.0, 6.0)
    >>> rep["scale_number"], round(rep["gsd"], 9), rep["footprint"]
    (10000.0, 0.06, (360.0, 240.0))
    """
    H = float(10.0 ** float(log_distance))
    c_m = float(c_mm) / 1000.0
    mb = ps.image_scale_number(c_m, H)
    gsd = ps.ground_sampling_distance(float(pixel_um) / 1000.0, float(c_mm), H)
    corners = ps.footprint(*SENSOR_PX, float(pixel_um) / 1000.0, float(c_mm), [0.0, 0.0, H])
    width = round(float(corners[1, 0] - corners[0, 0]), 9)
    height = round(float(corners[0, 1] - corners[3, 1]), 9)
    where = configuration(H)
    unit, factor = ("mm", 1e3) if gsd < 0.01 else ("cm", 1e2)
    html = (f"<p>distance H = <b>{H:,.1f} m</b> ({where})<br>image scale 1 : m<sub>b</sub> "
            f"with m<sub>b</sub> = H/c = <b>{mb:,.0f}</b> (Bildmaßstabszahl)<br>"
            f"GSD = pixel·m<sub>b</sub> = {float(pixel_um):g} µm × {mb:,.0f} = "
            f"<b>{gsd * factor:.3g} {unit}</b><br>footprint of a {SENSOR_PX[0]} × "
            f"{SENSOR_PX[1]} sensor: {width:,.1f} m × {height:,.1f} m</p>")
    return {"distance": H, "scale_number": mb, "gsd": gsd, "footprint": (width, height),
            "configuration": where, "html": html}


def footprint_outlines(fb: ps.FlightBlock, block=BLOCK_M) -> tuple[np.ndarray, np.ndarray]:
    """Outlines (x, y with NaN between rectangles) and centres of a flight block's images.

    Images lie as in :func:`photolib.sensors.flight_block`: the first stereo model starts at
    the block's start (x = 0), the first strip's edge on the block's edge (y = 0).

    >>> fb = ps.flight_block(1000.0, 500.0, 1000.0, 100.0, 0.005, 4000, 4000)
    >>> (x, y), centres = footprint_outlines(fb, (1000.0, 500.0))
    >>> len(centres) == fb.images, bool(np.isnan(x[5]))
    (True, True)
    """
    cx = fb.coverage_along / 2 - fb.base + fb.base * np.arange(fb.images_per_strip)
    cy = fb.coverage_across / 2 + fb.strip_spacing * np.arange(fb.strips)
    centres = np.array([(x, y) for y in cy for x in cx])
    hx, hy = fb.coverage_along / 2, fb.coverage_across / 2
    unit = np.array([[-1, -1], [1, -1], [1, 1], [-1, 1], [-1, -1], [np.nan, np.nan]])
    pts = (centres[:, None, :] + unit[None] * [hx, hy]).reshape(-1, 2)
    return (pts[:, 0], pts[:, 1]), centres


def flight_report(height_m: float, overlap_pct: float, sidelap_pct: float,
                  block=BLOCK_M, camera=None) -> dict:
    """Flight plan of the chapter's block for one flying height, overlap and side lap.

    Returns
    -------
    dict
        ``plan`` (:class:`photolib.sensors.FlightBlock`), ``outlines``, ``centres``, ``html``.

    Examples
    --------
    >>> rep = flight_report(1500.0, 60.0, 30.0)
    >>> rep["plan"].strips, rep["plan"].images_per_strip, rep["plan"].images
    (7, 25, 175)
    """
    cam = dict(FLIGHT_CAMERA if camera is None else camera)
    fb = ps.flight_block(block[0], block[1], float(height_m), cam["c"], cam["pixel"],
                         cam["n_along"], cam["n_across"], float(overlap_pct) / 100.0,
                         float(sidelap_pct) / 100.0)
    outlines, centres = footprint_outlines(fb, block)
    html = (f"<p>block {block[0] / 1e3:g} km × {block[1] / 1e3:g} km, c = {cam['c']:g} mm, "
            f"{cam['n_along']} × {cam['n_across']} pixels of {cam['pixel'] * 1e3:g} µm<br>"
            f"H = {float(height_m):,.0f} m: 1 : {float(height_m) / (cam['c'] / 1e3):,.0f}, GSD = "
            f"{fb.gsd * 100:.1f} cm<br>image on the ground {fb.coverage_along:,.0f} m × "
            f"{fb.coverage_across:,.0f} m<br>base B = {fb.base:,.0f} m, strip spacing "
            f"A = {fb.strip_spacing:,.0f} m<br><b>{fb.strips} strips × "
            f"{fb.images_per_strip} images = {fb.images} images</b> "
            f"({fb.strips * (fb.images_per_strip - 1)} stereo models)</p>")
    return {"plan": fb, "outlines": outlines, "centres": centres, "html": html}


# -- static figures -------------------------------------------------------------------------------

def plot_timeline(events=HISTORY, title="history / Geschichte der Photogrammetrie"):
    """The events of :data:`HISTORY` on a time axis, with the three stages as bands."""
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(7.2, 3.0))
    for start, end, name, colour in ((1900, 1960, "analogue", "#c7e9c0"),
                                     (1960, 1990, "analytical", "#c6dbef"),
                                     (1990, 2030, "digital", "#fdd0a2")):
        ax.axvspan(start, end, color=colour, alpha=0.7, lw=0)
        ax.text((start + end) / 2, 0.93, name, ha="center", fontsize=9)
    for k, (year, label, _, _) in enumerate(events):
        level = 0.15 + 0.12 * (k % 6)
        ax.plot([year, year], [0, level], color="0.4", lw=1)
        ax.plot(year, 0, "o", color="#d62728", ms=4)
        ax.text(year + 1, level, f"{year}: {label}", fontsize=7, va="center")
    ax.set(xlim=(1850, 2030), ylim=(-0.05, 1.0), yticks=[], xlabel="year", title=title)
    ax.grid(False)
    return finished(fig)


def plot_process(title="the photogrammetric process / der photogrammetrische Prozess"):
    """Object → image acquisition → orientation → measurement and reconstruction → products."""
    import matplotlib.pyplot as plt

    steps = ("object\nObjekt", "image acquisition\nBildaufnahme", "orientation\nOrientierung",
             "measurement,\nreconstruction\nAuswertung", "products\nProdukte")
    details = ("shape, size,\nposition", "camera, sensor,\nconfiguration",
               "interior and\nexterior", "points, lines,\nsurfaces", "maps, orthophotos,\nDTM, 3-D models")
    fig, ax = plt.subplots(figsize=(7.2, 2.2))
    for k, (step, detail) in enumerate(zip(steps, details)):
        x = 0.1 + 0.2 * k
        ax.text(x, 0.62, step, ha="center", va="center", fontsize=8,
                bbox={"boxstyle": "round", "fc": "#deebf7", "ec": "#3182bd"})
        ax.text(x, 0.15, detail, ha="center", va="center", fontsize=7, color="0.3")
        if k < len(steps) - 1:
            ax.annotate("", xy=(x + 0.12, 0.62), xytext=(x + 0.08, 0.62),
                        arrowprops={"arrowstyle": "->", "color": "0.3"})
    ax.set(xlim=(0, 1), ylim=(0, 1), title=title)
    ax.axis("off")
    return finished(fig)


# -- widgets --------------------------------------------------------------------------------------

class ImageScaleExplorer(Explorer):
    """Camera constant, distance and pixel → image scale, GSD, footprint; close range to aerial."""

    title = "image scale and GSD explorer"

    def __init__(self, c_mm=100.0, log_distance=3.0, pixel_um=4.0):
        self.controls = {"c_mm": slider("c [mm]", c_mm, 8, 310, 1, fmt=".0f"),
                         "log_distance": slider("log₁₀ H [m]", log_distance, -0.5, 6.2, 0.05,
                                                fmt=".2f"),
                         "pixel_um": slider("pixel [µm]", pixel_um, 1, 15, 0.1, fmt=".1f")}
        self.live = LiveFigure((4.6, 3.2))
        ax = self.live.figure.add_subplot()
        self.live.figure.subplots_adjust(0.16, 0.15, 0.97, 0.9)
        colours = ("#c7e9c0", "#fdd0a2", "#c6dbef", "#dadaeb")
        for (name, lo, hi), colour in zip(CONFIGURATIONS, colours):
            ax.axvspan(lo, hi, color=colour, alpha=0.8, lw=0)
            ax.text(np.sqrt(lo * hi), 3e3 if "UAV" not in name else 3e2,
                    name.split(" / ")[0], ha="center", fontsize=7)
        self._H = np.logspace(-0.5, 6.2, 60)
        ax.set(xscale="log", yscale="log", xlim=(0.3, 3e6), ylim=(1e-5, 1e4),
               xlabel="distance H [m]", ylabel="GSD [m]", title="GSD = pixel · H / c")
        (self._line,) = ax.plot(self._H, self._H, color="#1f77b4", lw=1.5)
        (self._dot,) = ax.plot([], [], "o", color="#d62728", ms=7)
        self.live.animate(self._line)
        self.live.animate(self._dot)
        self.report = None
        self._finish()

    def draw(self, c_mm, log_distance, pixel_um) -> str:
        self.report = rep = scale_report(c_mm, log_distance, pixel_um)
        self._line.set_ydata(ps.ground_sampling_distance(pixel_um / 1000.0, c_mm, self._H))
        self._dot.set_data([rep["distance"]], [rep["gsd"]])
        return rep["html"]


class FlightBlockExplorer(Explorer):
    """Flying height, forward overlap p and side lap q → strips, images, footprints."""

    title = "flight block explorer"

    def __init__(self, height_m=1500.0, overlap_pct=60.0, sidelap_pct=30.0):
        self.controls = {"height_m": slider("H [m]", height_m, 600, 3000, 50, fmt=".0f"),
                         "overlap_pct": slider("overlap p [%]", overlap_pct, 50, 90, 1,
                                               fmt=".0f"),
                         "sidelap_pct": slider("side lap q [%]", sidelap_pct, 0, 60, 1,
                                               fmt=".0f")}
        self.live = LiveFigure((4.8, 3.6))
        ax = self.live.figure.add_subplot()
        self.live.figure.subplots_adjust(0.15, 0.13, 0.97, 0.92)
        L, W = BLOCK_M
        ax.set(xlim=(-1500, L + 1500), ylim=(-1200, W + 1200), aspect="equal",
               xlabel="along the flight [m]", ylabel="across [m]",
               title="block, footprints, one stereo pair")
        (self._frames,) = ax.plot([], [], color="#1f77b4", lw=0.5, alpha=0.6)
        (self._centres,) = ax.plot([], [], ".", color="#1f77b4", ms=2)
        (self._pair,) = ax.plot([], [], color="#ff7f0e", lw=1.8)
        ax.plot([0, L, L, 0, 0], [0, 0, W, W, 0], color="#d62728", lw=2)
        self.live.animate(self._frames)
        self.live.animate(self._centres)
        self.live.animate(self._pair)
        self.report = None
        self._finish()

    def draw(self, height_m, overlap_pct, sidelap_pct) -> str:
        self.report = rep = flight_report(height_m, overlap_pct, sidelap_pct)
        self._frames.set_data(*rep["outlines"])
        self._centres.set_data(rep["centres"][:, 0], rep["centres"][:, 1])
        x, y = rep["outlines"]
        self._pair.set_data(x[:12], y[:12])      # the first stereo pair (model) in orange
        return rep["html"]
