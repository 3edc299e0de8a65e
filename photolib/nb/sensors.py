"""Chapter 03 pictures and widgets: digital images and sensors (Digitale Bilder und Sensoren).

* :class:`QuantisationExplorer`: bit depth (Bittiefe) → staircase, rounding error, σ_q = Δ/√12
  and a quantised test image;
* :class:`AliasingExplorer`: a sine pattern on a 5 µm pixel grid: frequency and fill factor →
  samples, the alias the samples show, and the pixel MTF;
* :class:`BayerExplorer`: stripe frequency of a grey test chart → the false colours of the
  bilinear demosaic (Farbinterpolation);
* :func:`exposure_report`, :func:`plot_exposure`: a scene under-, well and over-exposed
  (Unter- / Überbelichtung): clipped pixels, grey values used, SNR;
* :func:`pyramid_shapes`, :func:`image_pyramid`, :func:`plot_pyramid`: an image pyramid
  (Bildpyramide) of 2 × 2 block means, as VSD builds it (Polish notes).

All numbers come from :mod:`photolib.sensors`.
"""

from __future__ import annotations

import numpy as np

from photolib import sensors as ps
from photolib.nb.live import Explorer, LiveFigure, finished, slider

__all__ = [
    "PITCH_MM",
    "AliasingExplorer",
    "BayerExplorer",
    "QuantisationExplorer",
    "aliasing_report",
    "bayer_report",
    "demo_image",
    "demo_profile",
    "exposure_report",
    "image_pyramid",
    "plot_bayer",
    "plot_exposure",
    "plot_mtf",
    "plot_pyramid",
    "plot_snr",
    "pyramid_shapes",
    "quantisation_report",
    "siemens_star",
    "stripe_chart",
]

#: pixel pitch of the chapter's sensor, mm (5 µm: Nyquist 100 line pairs per mm)
PITCH_MM = 0.005
_N_PROFILE = 400


def demo_profile(n: int = _N_PROFILE) -> tuple[np.ndarray, np.ndarray]:
    """A smooth brightness profile along an image row, values in [0, 1].

    >>> x, s = demo_profile(5)
    >>> float(s.min()) >= 0.0 and float(s.max()) <= 1.0
    True
    """
    x = np.linspace(0.0, 1.0, n)
    return x, 0.5 + 0.38 * np.sin(2 * np.pi * 1.3 * x) * np.exp(-0.8 * x) + 0.1 * x - 0.05


def demo_image(size: int = 96) -> np.ndarray:
    """A grey test image in [0, 1]: a radial gradient with a soft bright spot.

    >>> demo_image(8).shape
    (8, 8)
    """
    r, c = np.mgrid[0:size, 0:size] / (size - 1)
    return np.clip(0.15 + 0.6 * c + 0.3 * np.exp(-((r - 0.35) ** 2 + (c - 0.6) ** 2) / 0.02)
                   - 0.1 * r, 0.0, 1.0)


def quantisation_report(bits: int) -> dict:
    """Quantise the test profile and the test image to ``bits`` bits.

    Returns
    -------
    dict
        ``x``, ``signal``, ``quantised`` (back in signal units), ``error_steps`` (error / Δ),
        ``step``, ``sigma_model`` (Δ/√12), ``sigma_measured`` (RMS of the profile's error),
        ``image`` (quantised test image), ``html``.

    Examples
    --------
    >>> rep = quantisation_report(3)
    >>> rep["step"] == 1 / 7, bool(np.max(np.abs(rep["error_steps"])) <= 0.5 + 1e-12)
    (True, True)
    """
    b = int(round(bits))
    x, s = demo_profile()
    step = ps.quantisation_step(b)
    q = ps.dequantise(ps.quantise(s, b), b)
    err = q - s
    sigma_model = float(np.sqrt(ps.quantisation_noise_variance(step)))
    sigma = float(np.sqrt(np.mean(err**2)))
    image = ps.dequantise(ps.quantise(demo_image(), b), b)
    sine_db = 6.02 * b + 1.76
    html = (f"<p><b>{b} bit</b>: 2<sup>{b}</sup> = {ps.grey_levels(b)} grey values "
            f"(Grauwerte) 0 … {ps.grey_levels(b) - 1}<br>step Δ = 1/{ps.grey_levels(b) - 1} "
            f"= {step:.4g}<br>σ<sub>q</sub> = Δ/√12 = <b>{sigma_model:.4g}</b><br>"
            f"RMS error of this profile: {sigma:.4g}<br>"
            f"SNR of a full-scale sine ≈ 6.02·b + 1.76 = {sine_db:.1f} dB</p>")
    return {"x": x, "signal": s, "quantised": q, "error_steps": err / step, "step": step,
            "sigma_model": sigma_model, "sigma_measured": sigma, "image": image, "html": html}


def aliasing_report(frequency: float, fill_factor: float = 1.0, n: int = 16,
                    pitch: float = PITCH_MM) -> dict:
    """A sine of ``frequency`` (cycles/mm) seen by ``n`` pixels of pitch ``pitch`` (mm).

    Returns
    -------
    dict
        ``x_um`` fine positions (µm) and ``pattern`` (the sine on the sensor), ``pixel_um``
        and ``samples`` (pixel values, integrated over the sensitive area), ``alias`` (the
        sine of the alias frequency through the samples, on ``x_um``), ``f_alias``,
        ``mtf`` (signed amplitude factor sinc(f·a)), ``nyquist``, ``aliased``, ``html``.

    Examples
    --------
    >>> rep = aliasing_report(150.0)
    >>> rep["f_alias"], rep["aliased"]
    (50.0, True)
    """
    f = float(frequency)
    ff = float(fill_factor)
    fn = ps.nyquist_frequency(pitch)
    x_mm, samples = ps.sample_sine(f, pitch, n, fill_factor=ff)
    fine = np.linspace(-0.5 * pitch, (n - 0.5) * pitch, 8 * n * 4)
    pattern = np.cos(2 * np.pi * f * fine)
    fa = ps.alias_frequency(f, pitch)
    amp = float(np.sinc(f * pitch * np.sqrt(ff)))
    # the alias through the samples: f = k/p ± f_a, so cos(2πf·kp) = cos(2πf_a·kp)
    alias = amp * np.cos(2 * np.pi * fa * fine)
    aliased = bool(f > fn + 1e-12)
    verdict = ("<b style='color:#b00'>aliased</b>: the pixels show a false, lower frequency"
               if aliased else "below Nyquist: the samples show the true frequency")
    html = (f"<p>pixel pitch p = {pitch * 1e3:g} µm, Nyquist f<sub>N</sub> = 1/(2p) = "
            f"{fn:g} /mm<br>pattern f = {f:g} /mm → seen as f<sub>a</sub> = <b>{fa:g} /mm</b>"
            f"<br>{verdict}<br>fill factor {ff:.2f}: sensitive width a = p·√FF = "
            f"{pitch * np.sqrt(ff) * 1e3:.2f} µm<br>pixel MTF |sinc(f·a)| = <b>{abs(amp):.3f}</b>"
            "</p>")
    return {"x_um": fine * 1e3, "pattern": pattern, "pixel_um": x_mm * 1e3, "samples": samples,
            "alias": alias, "f_alias": float(fa), "mtf": amp, "nyquist": fn, "aliased": aliased,
            "html": html}


def stripe_chart(period_px: float, size: int = 48) -> np.ndarray:
    """A grey test chart (R = G = B) of vertical stripes with ``period_px`` pixels per cycle.

    >>> chart = stripe_chart(4.0, 8)
    >>> chart.shape, bool(np.all(chart[..., 0] == chart[..., 2]))
    ((8, 8, 3), True)
    """
    c = np.arange(size)
    grey = 0.5 + 0.5 * np.cos(2 * np.pi * c / float(period_px))
    return np.repeat(np.tile(grey, (size, 1))[..., None], 3, axis=-1)


def bayer_report(period_px: float, pattern: str = "RGGB", size: int = 48) -> dict:
    """Grey stripes through a Bayer sensor and the bilinear demosaic: how much false colour?

    Returns
    -------
    dict
        ``scene``, ``mosaic``, ``rgb`` (demosaiced, clipped to [0, 1]), ``false_colour``
        (RMS of the channel differences inside the border: 0 for a grey result), ``html``.

    Examples
    --------
    >>> bayer_report(40.0)["false_colour"] < bayer_report(2.5)["false_colour"]
    True
    """
    scene = stripe_chart(period_px, size)
    mosaic = ps.bayer_mosaic(scene, pattern)
    rgb = np.clip(ps.demosaic_bilinear(mosaic, pattern), 0.0, 1.0)
    inner = rgb[1:-1, 1:-1]
    grey = inner.mean(axis=-1, keepdims=True)
    false = float(np.sqrt(np.mean((inner - grey) ** 2)))
    html = (f"<p>stripes: {period_px:g} px per cycle (Nyquist: 2 px; green Nyquist along a "
            f"row: 2 px, red and blue: 4 px)<br>{pattern}: ½ of the pixels green, ¼ red, "
            f"¼ blue<br>false colour (RMS of R, G, B about their mean): <b>{false:.3f}</b></p>")
    return {"scene": scene, "mosaic": mosaic, "rgb": rgb, "false_colour": false, "html": html}


def siemens_star(size: int = 128, spokes: int = 24) -> np.ndarray:
    """A grey Siemens star in [0, 1]: black and white sectors that get finer towards the centre.

    Parameters
    ----------
    size : int
        Rows and columns of the image, pixels, ≥ 2.
    spokes : int
        Number of white sectors, ≥ 1.

    Returns
    -------
    ndarray, shape (size, size)
        0.5 + 0.5·sign(cos(spokes·θ)) with θ the angle about the image centre; 0.5 outside
        the inscribed circle.

    Examples
    --------
    >>> star = siemens_star(8, 4)
    >>> star.shape, sorted(set(star.ravel().tolist()))
    ((8, 8), [0.0, 0.5, 1.0])
    """
    n, m = int(size), int(spokes)
    if n < 2 or m < 1:
        raise ValueError(f"siemens_star needs size ≥ 2 and spokes ≥ 1, got size={size!r}, "
                         f"spokes={spokes!r}")
    r, c = (np.mgrid[0:n, 0:n] - (n - 1) / 2) / ((n - 1) / 2)
    star = 0.5 + 0.5 * np.sign(np.cos(m * np.arctan2(r, c)))
    return np.where(np.hypot(r, c) <= 1.0, star, 0.5)


def exposure_report(factor: float, scene=None, full_well_e: float = 20000.0,
                    read_noise_e: float = 5.0, bits: int = 12) -> dict:
    """A scene exposed at ``factor`` times the nominal exposure: what the sensor makes of it.

    At ``factor = 1`` the brightest point of the scene just fills the full well. The exposure
    H = E·t ∝ t/k² (chapter 02), so ``factor`` is the change of t/k²: 1/4 is two stops
    less light (under-exposure, Unterbelichtung), 4 two stops more (over-exposure,
    Überbelichtung).

    Parameters
    ----------
    factor : float
        Exposure relative to the nominal one, dimensionless, > 0.
    scene : array_like, optional
        Relative radiance of the scene, any shape, values ≥ 0; scaled so that its largest
        value is 1. Default: :func:`demo_image`.
    full_well_e : float
        Full well FW (Fassungsvermögen), electrons, > 0.
    read_noise_e : float
        Read noise σ_r, electrons, ≥ 0.
    bits : int
        Bit depth b of the converter; the gain is K = FW/(2^b − 1) e⁻/DN.

    Returns
    -------
    dict
        ``electrons`` S = factor·scene·FW (before clipping), ``dn`` (digital numbers, the
        scene's shape), ``clipped`` (share of the pixels with S > FW: they all read the top DN
        2^b − 1 and their detail is lost), ``levels_used`` (number of distinct DN),
        ``snr_median`` (model SNR S/√(S + σ_r² + K²/12) of the median pixel, clipped at FW),
        ``html``.

    Examples
    --------
    >>> under, nominal, over = (exposure_report(f) for f in (0.125, 1.0, 4.0))
    >>> nominal["clipped"], over["clipped"] > 0.5
    (0.0, True)
    >>> under["levels_used"] < nominal["levels_used"], under["snr_median"] < nominal["snr_median"]
    (True, True)
    """
    f = float(factor)
    if not np.isfinite(f) or f <= 0:
        raise ValueError(f"exposure factor must be finite and > 0, got {factor!r}")
    img = demo_image() if scene is None else np.asarray(scene, dtype=float)
    if img.size == 0 or not np.all(np.isfinite(img)) or np.min(img) < 0 or np.max(img) <= 0:
        raise ValueError("scene must be non-empty, finite, ≥ 0 and not all zero")
    img = img / np.max(img)
    electrons = f * img * full_well_e
    gain = ps.gain_e_per_dn(full_well_e, bits)
    dn = ps.quantise(electrons, bits, full_well_e)
    clipped = float(np.mean(electrons > full_well_e))
    levels = int(np.unique(dn).size)
    snr_med = float(ps.snr(min(float(np.median(electrons)), full_well_e), read_noise_e, gain))
    html = (f"<p>exposure × {f:g} ({np.log2(f):+.1f} stops): {100 * clipped:.1f} % of the "
            f"pixels clipped at DN {2 ** int(bits) - 1}, {levels} grey values used, SNR of the "
            f"median pixel {snr_med:.0f}</p>")
    return {"electrons": electrons, "dn": dn, "clipped": clipped, "levels_used": levels,
            "snr_median": snr_med, "html": html}


def pyramid_shapes(shape, min_size: int = 1) -> list[tuple[int, int]]:
    """Image sizes of the levels of an image pyramid (Bildpyramide).

    Each level halves the rows and columns of the one before, rounding up (an odd last row or
    column is kept), until the larger side is at most ``min_size``.

    Parameters
    ----------
    shape : tuple of int
        (rows, columns) of the original image, pixels, each ≥ 1 (further entries, e.g.
        colour channels, are ignored).
    min_size : int
        The pyramid stops at the first level whose larger side is ≤ ``min_size``, pixels, ≥ 1.

    Returns
    -------
    list of (int, int)
        Level 0 (the original) first; level i + 1 has ⌈n_i/2⌉ rows and columns.

    Examples
    --------
    >>> pyramid_shapes((10, 7))
    [(10, 7), (5, 4), (3, 2), (2, 1), (1, 1)]
    >>> pyramid_shapes((10_000, 10_000), min_size=512)[-1]
    (313, 313)
    """
    try:
        rows, cols = (int(v) for v in tuple(shape)[:2])
    except (TypeError, ValueError):
        raise ValueError(f"shape must start with (rows, columns), got {shape!r}") from None
    if rows < 1 or cols < 1 or int(min_size) < 1:
        raise ValueError(f"pyramid_shapes needs rows, columns and min_size ≥ 1, got "
                         f"shape={shape!r}, min_size={min_size!r}")
    out = [(rows, cols)]
    while max(out[-1]) > int(min_size):
        r, c = out[-1]
        out.append((-(-r // 2), -(-c // 2)))
    return out


def image_pyramid(image, min_size: int = 1) -> list[np.ndarray]:
    """An image pyramid (Bildpyramide): each level the 2 × 2 block means of the one before.

    Averaging the block before keeping one pixel per block is a low-pass filter: a pattern
    finer than the new Nyquist frequency is smoothed out instead of aliased (section 'Sampling
    and aliasing'). An odd last row or column is repeated before averaging, so the sizes are
    those of :func:`pyramid_shapes`.

    Parameters
    ----------
    image : array_like, shape (rows, cols) or (rows, cols, channels)
        Grey values (any unit; the levels keep it).
    min_size : int
        Stop at the first level whose larger side is ≤ ``min_size`` pixels, ≥ 1.

    Returns
    -------
    list of ndarray
        Level 0 is the image (as float); level i + 1 is, for every block,

        .. math:: g_{i+1}(r, c) = \\tfrac14 \\sum_{u, v \\in \\{0, 1\\}} g_i(2r + u, 2c + v)

    Examples
    --------
    >>> img = np.arange(16.0).reshape(4, 4)
    >>> levels = image_pyramid(img)
    >>> [level.shape for level in levels]
    [(4, 4), (2, 2), (1, 1)]
    >>> levels[1]
    array([[ 2.5,  4.5],
           [10.5, 12.5]])

    The same blocks summed one by one (an independent route):

    >>> loop = [[sum(img[2 * r + u, 2 * c + v] for u in (0, 1) for v in (0, 1)) / 4
    ...          for c in range(2)] for r in range(2)]
    >>> bool(np.array_equal(levels[1], loop)), float(levels[2][0, 0]) == float(img.mean())
    (True, True)
    """
    g = np.asarray(image, dtype=float)
    if g.ndim not in (2, 3) or g.shape[0] < 1 or g.shape[1] < 1:
        raise ValueError(f"image must have shape (rows, cols) or (rows, cols, channels), "
                         f"got {g.shape}")
    levels = [g]
    for _ in pyramid_shapes(g.shape, min_size)[1:]:
        g = levels[-1]
        pad = [(0, g.shape[0] % 2), (0, g.shape[1] % 2)] + [(0, 0)] * (g.ndim - 2)
        g = np.pad(g, pad, mode="edge")
        levels.append(0.25 * (g[0::2, 0::2] + g[1::2, 0::2] + g[0::2, 1::2] + g[1::2, 1::2]))
    return levels


# -- static figures -------------------------------------------------------------------------------

def plot_snr(full_well_e: float = 20000.0, read_noise_e: float = 5.0, gain: float = 5.0):
    """SNR over the signal (log–log): read-noise-limited, shot-noise-limited, full well."""
    import matplotlib.pyplot as plt

    S = np.logspace(0, np.log10(full_well_e), 200)
    fig, ax = plt.subplots(figsize=(5.6, 3.4))
    ax.loglog(S, ps.snr(S, read_noise_e, gain), lw=2, label="shot + read + quantisation")
    ax.loglog(S, np.sqrt(S), "--", lw=1, label="shot noise only: √S")
    ax.loglog(S, S / read_noise_e, ":", lw=1, label=f"read noise only: S/{read_noise_e:g}")
    ax.axvline(full_well_e, color="0.4", lw=1)
    ax.text(full_well_e, 1.5, " full well", rotation=90, va="bottom", ha="right", fontsize=8)
    ax.set(xlabel="signal S [e⁻]", ylabel="SNR", ylim=(0.1, 1000),
           title="signal-to-noise ratio / Signal-Rausch-Verhältnis")
    ax.legend(fontsize=8, loc="upper left")
    return finished(fig)


def plot_mtf(pitch: float = PITCH_MM, fill_factors=(1.0, 0.5, 0.25)):
    """Pixel MTF over the frequency for several fill factors, with the Nyquist frequency."""
    import matplotlib.pyplot as plt

    f = np.linspace(0.0, 3.0 / pitch, 400)
    fig, ax = plt.subplots(figsize=(5.6, 3.2))
    for ff in fill_factors:
        ax.plot(f, ps.pixel_mtf(f, pitch, ff), label=f"FF = {ff:g}")
    ax.axvline(ps.nyquist_frequency(pitch), color="0.4", ls="--", lw=1)
    ax.text(ps.nyquist_frequency(pitch), 1.02, "Nyquist", ha="center", fontsize=8)
    ax.set(xlabel="frequency [cycles/mm]", ylabel="MTF", ylim=(0, 1.1),
           title=f"MTF of a square pixel, p = {pitch * 1e3:g} µm")
    ax.legend(fontsize=8)
    return finished(fig)


def plot_bayer(rgb, pattern: str = "RGGB", title: str = "Bayer mosaic and bilinear demosaic"):
    """Scene, the mosaic in its filter colours, and the demosaiced image, side by side."""
    import matplotlib.pyplot as plt

    rgb = np.asarray(rgb, float)
    mosaic = ps.bayer_mosaic(rgb, pattern)
    masks = ps.bayer_masks(mosaic.shape, pattern)
    coloured = np.moveaxis(masks, 0, -1) * mosaic[..., None]
    out = np.clip(ps.demosaic_bilinear(mosaic, pattern), 0.0, 1.0)
    fig, axes = plt.subplots(1, 3, figsize=(7.2, 2.7))
    for ax, img, name in zip(axes, (rgb, coloured, out),
                             ("scene", f"sensor ({pattern})", "bilinear demosaic")):
        ax.imshow(np.clip(img, 0.0, 1.0), interpolation="nearest")
        ax.set(title=name, xticks=[], yticks=[])
        ax.grid(False)
    fig.suptitle(title, fontsize=10)
    return finished(fig)


def plot_exposure(factors=(0.125, 1.0, 2.0), scene=None, full_well_e: float = 20000.0,
                  bits: int = 12):
    """The scene of :func:`exposure_report` at several exposures; clipped pixels in red."""
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(1, len(factors), figsize=(2.4 * len(factors), 2.9))
    for ax, f in zip(np.atleast_1d(axes), factors):
        rep = exposure_report(f, scene, full_well_e=full_well_e, bits=bits)
        rgb = _rgb8(rep["dn"] / (2 ** int(bits) - 1))
        rgb[rep["electrons"] > full_well_e] = (214, 39, 40)
        ax.imshow(rgb, interpolation="nearest")
        ax.set(xticks=[], yticks=[], title=f"exposure × {f:g}\n{100 * rep['clipped']:.0f} % "
               f"clipped, {rep['levels_used']} DN")
        ax.title.set_fontsize(9)
        ax.grid(False)
    fig.suptitle("under-, well, over-exposed / unter-, richtig, überbelichtet", fontsize=10)
    fig.subplots_adjust(0.02, 0.02, 0.98, 0.78, wspace=0.08)
    return finished(fig)


def plot_pyramid(image, levels: int = 4):
    """The first ``levels`` + 1 levels of :func:`image_pyramid`, each at the same display size."""
    import matplotlib.pyplot as plt

    pyr = image_pyramid(image)[: int(levels) + 1]
    fig, axes = plt.subplots(1, len(pyr), figsize=(1.75 * len(pyr), 2.2))
    for i, (ax, g) in enumerate(zip(np.atleast_1d(axes), pyr)):
        ax.imshow(_rgb8(g), interpolation="nearest")
        ax.set(xticks=[], yticks=[], title=f"level {i}: {g.shape[1]} × {g.shape[0]}")
        ax.title.set_fontsize(9)
        ax.grid(False)
    fig.suptitle("image pyramid / Bildpyramide: 2 × 2 pixels → 1 per level", fontsize=10)
    fig.subplots_adjust(0.01, 0.02, 0.99, 0.78, wspace=0.06)
    return finished(fig)


# -- widgets --------------------------------------------------------------------------------------

def _rgb8(img) -> np.ndarray:
    """An image in [0, 1] (grey (H, W) or (H, W, 3)) as uint8 RGB: imshow draws it fastest."""
    img = np.clip(np.asarray(img, float), 0.0, 1.0)
    if img.ndim == 2:
        img = np.repeat(img[..., None], 3, axis=-1)
    return np.rint(255.0 * img).astype(np.uint8)


class QuantisationExplorer(Explorer):
    """Bit depth → quantised profile, rounding error in steps, quantised test image."""

    title = "quantisation explorer"

    def __init__(self, bits=3.0):
        self.controls = {"bits": slider("bits b", bits, 1, 10, 1, fmt=".0f")}
        self.live = LiveFigure((7.4, 3.2))
        fig = self.live.figure
        ax = fig.add_subplot(2, 2, 1)
        ex = fig.add_subplot(2, 2, 3, sharex=ax)
        im = fig.add_subplot(1, 2, 2)
        fig.subplots_adjust(0.08, 0.14, 0.98, 0.9, wspace=0.2, hspace=0.35)
        x, s = demo_profile()
        ax.plot(x, s, color="0.6", lw=1)
        ax.set(ylim=(-0.05, 1.05), title="signal and grey values", xticks=[])
        ex.set(ylim=(-0.6, 0.6), xlabel="position along the row", title="error / Δ")
        ex.axhline(0.5, color="0.6", lw=0.8, ls="--")
        ex.axhline(-0.5, color="0.6", lw=0.8, ls="--")
        (self._stairs,) = ax.plot(x, s, color="#d62728", lw=1.3, drawstyle="steps-mid")
        (self._error,) = ex.plot(x, 0 * x, color="#1f77b4", lw=0.8)
        self._image = im.imshow(_rgb8(demo_image()), interpolation="nearest")
        im.set(xticks=[], yticks=[], title="quantised image")
        im.grid(False)
        for artist in (self._stairs, self._error, self._image):
            self.live.animate(artist)
        self.report = None
        self._finish()

    def draw(self, bits) -> str:
        self.report = rep = quantisation_report(bits)
        self._stairs.set_ydata(rep["quantised"])
        self._error.set_ydata(rep["error_steps"])
        self._image.set_data(_rgb8(rep["image"]))
        return rep["html"]


class AliasingExplorer(Explorer):
    """Pattern frequency and fill factor → pixel samples, alias, pixel MTF."""

    title = "sampling and aliasing explorer"

    def __init__(self, frequency=60.0, fill_factor=1.0):
        self.controls = {"frequency": slider("f [1/mm]", frequency, 0, 400, 5, fmt=".0f"),
                         "fill_factor": slider("fill factor", fill_factor, 0.05, 1.0, 0.05,
                                               fmt=".2f")}
        self.live = LiveFigure((7.4, 3.0))
        fig = self.live.figure
        ax = fig.add_subplot(1, 2, 1)
        mx = fig.add_subplot(1, 2, 2)
        fig.subplots_adjust(0.08, 0.16, 0.98, 0.9, wspace=0.28)
        n = 16
        for k in range(n + 1):
            ax.axvline((k - 0.5) * PITCH_MM * 1e3, color="0.85", lw=0.6)
        ax.set(xlim=(-0.5 * PITCH_MM * 1e3, (n - 0.5) * PITCH_MM * 1e3), ylim=(-1.2, 1.2),
               xlabel="x [µm]", title="pattern, pixel values, alias")
        (self._pattern,) = ax.plot([], [], color="0.55", lw=1)
        (self._alias,) = ax.plot([], [], color="#d62728", lw=1.2, ls="--")
        (self._samples,) = ax.plot([], [], "o", color="#1f77b4", ms=4)
        f = np.linspace(0, 400, 300)
        self._f = f
        fn = ps.nyquist_frequency(PITCH_MM)
        mx.axvline(fn, color="0.4", ls="--", lw=1)
        mx.text(fn, 1.03, "Nyquist", ha="center", fontsize=8)
        mx.set(xlim=(0, 400), ylim=(0, 1.1), xlabel="f [1/mm]", title="pixel MTF")
        (self._mtf,) = mx.plot(f, 0 * f, color="#2ca02c", lw=1.5)
        (self._marker,) = mx.plot([], [], "o", color="#d62728", ms=6)
        for artist in (self._pattern, self._alias, self._samples, self._mtf, self._marker):
            self.live.animate(artist)
        self.report = None
        self._finish()

    def draw(self, frequency, fill_factor) -> str:
        self.report = rep = aliasing_report(frequency, fill_factor)
        self._pattern.set_data(rep["x_um"], rep["pattern"])
        self._alias.set_data(rep["x_um"], rep["alias"])
        self._samples.set_data(rep["pixel_um"], rep["samples"])
        self._mtf.set_ydata(ps.pixel_mtf(self._f, PITCH_MM, fill_factor))
        self._marker.set_data([frequency], [abs(rep["mtf"])])
        return rep["html"]


class BayerExplorer(Explorer):
    """Stripe period of a grey chart → Bayer mosaic → bilinear demosaic and its false colour."""

    title = "Bayer demosaic explorer"
    _gap = 4

    def __init__(self, period_px=8.0):
        self.controls = {"period_px": slider("period [px]", period_px, 2, 24, 0.25, fmt=".2f")}
        self.live = LiveFigure((7.0, 2.6))
        ax = self.live.figure.add_subplot()
        self.live.figure.subplots_adjust(0.01, 0.02, 0.99, 0.88)
        rep = bayer_report(period_px)
        self._masks = np.moveaxis(ps.bayer_masks(rep["mosaic"].shape), 0, -1)
        # one image of three panels: one resampling per update instead of three
        self._image = self.live.animate(ax.imshow(self._panels(rep), interpolation="nearest"))
        size = rep["mosaic"].shape[1]
        for k, name in enumerate(("scene (grey)", "sensor RGGB", "bilinear demosaic")):
            ax.text(k * (size + self._gap) + size / 2, -2, name, ha="center", fontsize=9)
        ax.set(xticks=[], yticks=[])
        ax.axis("off")
        self.report = None
        self._finish()

    def _panels(self, rep) -> np.ndarray:
        size = rep["mosaic"].shape[0]
        gap = np.ones((size, self._gap, 3))
        coloured = self._masks * rep["mosaic"][..., None]
        return _rgb8(np.concatenate([rep["scene"], gap, coloured, gap, rep["rgb"]], axis=1))

    def draw(self, period_px) -> str:
        self.report = rep = bayer_report(period_px)
        self._image.set_data(self._panels(rep))
        return rep["html"]
