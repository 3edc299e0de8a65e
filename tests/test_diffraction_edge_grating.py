"""Diffraction at a straight edge and at a grating, each against an independent route.

* the edge: photolib's closed form (SciPy's Fresnel integrals) against the Fresnel–Kirchhoff
  integral over the open half-plane summed numerically here, and against SymPy's derivation;
* the grating: the order directions and the N-slit pattern against the far field computed
  by an FFT of the sampled aperture (Fraunhofer = Fourier transform of the transmission).
"""

from __future__ import annotations

import numpy as np
import pytest
import sympy as sp

import photolib as pl
from photolib.derive import optics as do


def _kirchhoff_edge(w, upper=60.0, n=400_001):
    """|∫_{−w}^{∞} e^{iπt²/2} dt|² / |1 + i|², the tail beyond ``upper`` added analytically."""
    t = np.linspace(-w, upper, n)
    f = np.exp(1j * np.pi * t * t / 2)
    integral = np.sum((f[1:] + f[:-1]) / 2 * np.diff(t))
    # ∫_U^∞ e^{iπt²/2} dt ≈ i·e^{iπU²/2}/(πU) (integration by parts, error O(U⁻³))
    integral += 1j * np.exp(1j * np.pi * upper * upper / 2) / (np.pi * upper)
    return abs(integral) ** 2 / 2


@pytest.mark.parametrize("w", [-2.0, -0.5, 0.0, 0.7, 1.2172, 2.5])
def test_edge_matches_the_kirchhoff_integral(w):
    lam, z = 0.55, 2e5
    x = w * np.sqrt(lam * z / 2)
    assert pl.edge_diffraction(x, lam, z) == pytest.approx(_kirchhoff_edge(w), abs=2e-5)


def test_edge_matches_sympys_derivation():
    expr = do.edge_intensity()
    for w in (-1.3, 0.0, 0.4, 1.9):
        exact = float(expr.subs(do.w_edge, w).evalf(30))
        assert pl.edge_diffraction(w * np.sqrt(0.5 * 100 / 2), 0.5, 100) == pytest.approx(
            exact, rel=1e-12)


def test_edge_shape_and_first_fringe():
    lam, z = 0.55, 1e6
    assert pl.edge_diffraction(0.0, lam, z) == 0.25          # a quarter on the shadow line
    shadow = pl.edge_diffraction(-np.linspace(0, 3000, 50), lam, z)
    assert np.all(np.diff(shadow) < 0)                        # falls monotonically into the shadow
    x = np.linspace(0, 3000, 300_001)
    profile = pl.edge_diffraction(x, lam, z)
    first = x[np.argmax(profile[: len(x) // 2])]              # brightest fringe = the first
    assert first == pytest.approx(pl.edge_first_fringe(lam, z), abs=0.02)
    assert profile.max() == pytest.approx(1.3704, abs=1e-4)   # the classic 1.37 (Born & Wolf)


def test_grating_array_factor_and_maxima_are_derived():
    for n in (2, 3, 6):
        assert do.grating_array_factor(n) == 0
    assert do.grating_maxima() == do.lam_g * do.m_order / do.d_g


def test_grating_against_the_fft_of_the_aperture():
    lam, d, a, n = 0.5, 2.0, 0.6, 12          # µm
    dx, size = 0.01, 2 ** 17                  # samples of the transmission along the grating
    x = (np.arange(size) - size // 2 + 0.5) * dx   # no sample on a slit edge
    t = ((np.abs(((x + d * n / 2) % d) - a / 2) <= a / 2) & (np.abs(x) < d * n / 2)).astype(float)
    spectrum = np.abs(np.fft.fftshift(np.fft.fft(t))) ** 2
    freq = np.fft.fftshift(np.fft.fftfreq(size, dx))          # cycles/µm = sin θ / λ
    keep = np.abs(freq * lam) < 0.9
    theta = np.arcsin(freq[keep] * lam)
    fft_pattern = spectrum[keep] / spectrum[size // 2]
    ours = pl.grating_intensity(theta, lam, d, a, n)
    assert np.max(np.abs(ours - fft_pattern)) < 2e-3          # the sampling of the slit edges
    for m in (1, 2, 3):
        theta_m = pl.grating_angles(d, lam, m)
        window = np.abs(theta - theta_m) < 0.02
        fft_peak = theta[np.argmax(np.where(window, fft_pattern, 0))]
        our_peak = theta[np.argmax(np.where(window, ours, 0))]
        assert fft_peak == our_peak
        # the order lies inside its principal maximum, half-width λ/(N·d·cos θ); the sloping
        # single-slit envelope moves the peak of the product a little off it
        assert abs(fft_peak - theta_m) < 0.2 * lam / (n * d * np.cos(theta_m))


@pytest.mark.parametrize("call, words", [
    (lambda: pl.grating_angles(1.0, 0.55, 2), "order m = 2 does not exist"),
    (lambda: pl.grating_angles(1.0, 0.55, 0.5), "orders must be integers"),
    (lambda: pl.grating_intensity(0.1, 0.55, 1.0, 1.5, 3), "slit width a = 1.5"),
    (lambda: pl.grating_intensity(0.1, 0.55, 1.0, 0.5, 0), "number of slits"),
    (lambda: pl.edge_diffraction(1.0, -0.55, 1e6), "wavelength"),
    (lambda: pl.edge_diffraction(np.nan, 0.55, 1e6), "x"),
])
def test_bad_input_is_named(call, words):
    with pytest.raises(ValueError, match=words):
        call()


def test_sympy_symbols_are_real():
    assert do.w_edge.is_real and isinstance(do.edge_intensity(), sp.Expr)
