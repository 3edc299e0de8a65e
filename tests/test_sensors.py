"""photolib.sensors, each function by an independent route.

* grey levels by enumerating bit patterns; the quantisation noise Δ²/12 by SymPy integration
  and by Monte Carlo (tolerance from the sampling error of a variance);
* dynamic range by SymPy's exact logarithms; SNR and gain by a seeded Monte-Carlo sensor
  (Poisson electrons, Gaussian read noise, rounding ADC) and the photon-transfer method;
* GSD and footprint by projecting back with ``photolib.project`` and ``cv2.projectPoints``;
* the flight block by counting, on a grid of ground points, the images that see each point;
* the bilinear demosaic against ``cv2.cvtColor`` (OpenCV names a Bayer pattern by its
  second row and column: our RGGB is OpenCV's ``BayerBG``);
* pixel MTF by the FFT of a finely sampled box and by quadrature; aliasing by the FFT peak
  of the sampled sine.
"""

from __future__ import annotations

import itertools
import math

import cv2
import numpy as np
import pytest
import scipy.integrate
import sympy as sp
from hypothesis import given, settings
from hypothesis import strategies as st

import photolib as pl
from photolib import sensors as s

# OpenCV's conversion code for each of our patterns (named by the 2nd row, 2nd/3rd column)
OPENCV_BAYER = {"RGGB": cv2.COLOR_BayerBG2RGB, "BGGR": cv2.COLOR_BayerRG2RGB,
                "GRBG": cv2.COLOR_BayerGB2RGB, "GBRG": cv2.COLOR_BayerGR2RGB}


# -- grey levels and quantisation ----------------------------------------------------------------

@pytest.mark.parametrize("bits", [1, 2, 3, 8, 10])
def test_grey_levels_count_the_bit_patterns(bits):
    assert s.grey_levels(bits) == sum(1 for _ in itertools.product((0, 1), repeat=bits))


@pytest.mark.parametrize("levels", [2, 3, 4, 5, 255, 256, 257, 4096, 4097])
def test_bits_for_levels_is_the_smallest_sufficient_depth(levels):
    b = s.bits_for_levels(levels)
    assert 2**b >= levels > 2 ** (b - 1)


def test_quantisation_noise_variance_is_the_integral_of_the_uniform_error():
    e, d = sp.symbols("e Delta", positive=True)
    variance = sp.integrate(e**2, (e, -d / 2, d / 2)) / d
    mean = sp.integrate(e, (e, -d / 2, d / 2)) / d
    assert mean == 0
    for step in (0.5, 1.0, 3.0):
        assert math.isclose(s.quantisation_noise_variance(step),
                            float(variance.subs(d, step)), rel_tol=1e-15)


def test_quantisation_error_variance_by_monte_carlo():
    rng = np.random.default_rng(3)
    n, bits = 200_000, 6
    signal = rng.uniform(0.0, 1.0, n)
    step = s.quantisation_step(bits)
    err = s.dequantise(s.quantise(signal, bits), bits) - signal
    expected = step**2 / 12
    # the sample variance of a uniform error has variance (μ4 − σ⁴)/n, μ4 = Δ⁴/80
    se = math.sqrt((step**4 / 80 - expected**2) / n)
    assert abs(err.var() - expected) < 5 * se
    assert np.max(np.abs(err)) <= step / 2 + 1e-12


@settings(max_examples=60, deadline=None)
@given(st.lists(st.floats(0.0, 10.0), min_size=1, max_size=20), st.integers(1, 16))
def test_quantise_round_trip_is_within_half_a_step(values, bits):
    dn = s.quantise(values, bits, 10.0)
    assert dn.dtype == np.int64 and dn.min() >= 0 and dn.max() <= 2**bits - 1
    back = s.dequantise(dn, bits, 10.0)
    assert np.all(np.abs(back - values) <= s.quantisation_step(bits, 10.0) / 2 * (1 + 1e-12))
    np.testing.assert_array_equal(s.quantise(back, bits, 10.0), dn)


def test_quantise_clips_under_and_overexposure_and_keeps_the_shape():
    dn = s.quantise([[-1.0, 0.0], [1.0, 5.0]], 8)
    assert dn.tolist() == [[0, 0], [255, 255]]


# -- gain, dynamic range, SNR --------------------------------------------------------------------

def test_gain_maps_the_full_well_to_the_largest_dn():
    K = s.gain_e_per_dn(30000.0, 12)
    assert s.quantise(30000.0 / K, 12, 4095.0) == 4095
    assert s.quantise((30000.0 - 0.51 * K) / K, 12, 4095.0) == 4094


@pytest.mark.parametrize("fw, rn", [(20000, 5), (100000, 3), (6000, 12)])
def test_dynamic_range_by_exact_logarithms(fw, rn):
    ratio = sp.Rational(fw, rn)
    dr = s.dynamic_range(fw, rn)
    assert math.isclose(dr.ratio, float(ratio), rel_tol=1e-15)
    assert math.isclose(dr.db, float(sp.N(20 * sp.log(ratio, 10), 30)), rel_tol=1e-14)
    assert math.isclose(dr.bits, float(sp.N(sp.log(ratio, 2), 30)), rel_tol=1e-14)
    assert math.isclose(s.decibels(dr.ratio), dr.db, rel_tol=1e-15)


def _simulate_pixel(rng, signal_e, read_e, gain, dark_e=0.0, n=200_000):
    electrons = rng.poisson(signal_e + dark_e, n) + rng.normal(0.0, read_e, n)
    return np.rint(electrons / gain) * gain - dark_e       # ADC, back in electrons


@pytest.mark.parametrize("signal_e, read_e, gain, dark_e",
                         [(50.0, 8.0, 4.0, 0.0), (2000.0, 5.0, 10.0, 30.0), (15.0, 2.0, 6.0, 0.0)])
def test_snr_model_matches_a_simulated_sensor(signal_e, read_e, gain, dark_e):
    rng = np.random.default_rng(11)
    out = _simulate_pixel(rng, signal_e, read_e, gain, dark_e)
    n = out.size
    sd = out.std(ddof=1)
    model_sd = signal_e / s.snr(signal_e, read_e, gain, dark_e)
    # standard error of a standard deviation, from the sample's fourth moment
    m4 = np.mean((out - out.mean()) ** 4)
    se = math.sqrt(max(m4 - sd**4, 0.0) / n) / (2 * sd)
    assert abs(sd - model_sd) < 5 * se, (sd, model_sd, se)


def test_snr_of_pure_shot_noise_is_the_square_root_of_the_signal():
    S = np.array([1.0, 100.0, 1e4])
    np.testing.assert_allclose(s.snr(S), np.sqrt(S), rtol=1e-15)
    assert math.isclose(s.decibels(s.snr(1e4)), 40.0, rel_tol=1e-15)


def test_gain_recovered_by_the_photon_transfer_method():
    # pure shot noise: var(DN) = mean(DN)/K (the photon transfer curve); rounding adds 1/12
    rng = np.random.default_rng(5)
    K = s.gain_e_per_dn(40000.0, 12)
    means, variances = [], []
    for level in (2000.0, 8000.0, 20000.0):
        dn = np.rint(rng.poisson(level, 400_000) / K)
        means.append(dn.mean())
        variances.append(dn.var(ddof=1) - 1 / 12)
    slope = np.polyfit(means, variances, 1)[0]
    assert abs(1 / slope - K) < 0.02 * K        # 3 levels × 4e5 samples: < 0.5 % noise


# -- GSD, footprint, flight block ----------------------------------------------------------------

@pytest.mark.parametrize("pixel, c, H", [(0.006, 100.0, 1000.0), (0.0045, 24.0, 12.0)])
def test_gsd_is_one_pixel_projected_back(pixel, c, H):
    gsd = s.ground_sampling_distance(pixel, c, H)
    xy = pl.project([[0.0, 0.0, 0.0], [gsd, 0.0, 0.0]], [0.0, 0.0, H], np.eye(3), c)
    assert math.isclose(xy[1, 0] - xy[0, 0], pixel, rel_tol=1e-12)
    assert math.isclose(gsd, pixel * s.image_scale_number(c, H), rel_tol=1e-15)


def test_gsd_accepts_an_array_of_heights():
    np.testing.assert_allclose(s.ground_sampling_distance(0.005, 50.0, [100.0, 200.0]),
                               [0.01, 0.02], rtol=1e-15)


@pytest.mark.parametrize("angles_deg", [(0.0, 0.0, 0.0), (3.0, -2.0, 25.0), (10.0, 5.0, -40.0)])
def test_footprint_corners_project_onto_the_image_corners(angles_deg):
    W, H, pixel, c = 1200, 800, 0.005, 35.0
    X0 = np.array([100.0, 200.0, 400.0])
    R = pl.rotation_opk(*np.radians(angles_deg))
    F = s.footprint(W, H, pixel, c, X0, R, Z=10.0)
    assert np.allclose(F[:, 2], 10.0)
    R_cv = np.diag([1.0, -1.0, -1.0]) @ R.T      # our camera (−z, y up) → OpenCV's
    K = np.array([[c / pixel, 0.0, (W - 1) / 2], [0.0, c / pixel, (H - 1) / 2], [0, 0, 1.0]])
    uv, _ = cv2.projectPoints(F.reshape(-1, 1, 3), cv2.Rodrigues(R_cv)[0], -R_cv @ X0, K,
                              np.zeros(5))
    np.testing.assert_allclose(uv.reshape(-1, 2),
                               [[-0.5, -0.5], [W - 0.5, -0.5], [W - 0.5, H - 0.5], [-0.5, H - 0.5]],
                               atol=1e-7)


def _coverage_counts(fb, length, width):
    """For a grid of ground points: images seeing it (per strip, max) and strips seeing it."""
    x = np.linspace(0.0, length, 301)
    y = np.linspace(0.0, width, 101)
    # image i at S/2 − B + i·B: the first stereo model (images 0, 1) starts at x = 0
    centres_x = fb.coverage_along / 2 - fb.base + fb.base * np.arange(fb.images_per_strip)
    centres_y = fb.coverage_across / 2 + fb.strip_spacing * np.arange(fb.strips)
    along = (np.abs(x[:, None] - centres_x[None, :]) <= fb.coverage_along / 2 + 1e-9).sum(1)
    across = (np.abs(y[:, None] - centres_y[None, :]) <= fb.coverage_across / 2 + 1e-9).sum(1)
    return along, across


@pytest.mark.parametrize("length, width, overlap, sidelap",
                         [(3000.0, 2000.0, 0.6, 0.3), (5000.0, 900.0, 0.8, 0.2),
                          (700.0, 4000.0, 0.5, 0.0)])
def test_flight_block_covers_every_point_in_stereo_and_is_minimal(length, width, overlap, sidelap):
    fb = s.flight_block(length, width, 1500.0, 100.0, 0.004, 10000, 15000, overlap, sidelap)
    along, across = _coverage_counts(fb, length, width)
    assert along.min() >= 2 and across.min() >= 1
    fewer = fb._replace(images_per_strip=fb.images_per_strip - 1)
    less = fb._replace(strips=fb.strips - 1)
    if fb.images_per_strip > 2:
        assert _coverage_counts(fewer, length, width)[0].min() < 2
    if fb.strips > 1:
        assert _coverage_counts(less, length, width)[1].min() < 1
    assert fb.images == fb.strips * fb.images_per_strip


def test_line_rate_gives_square_ground_pixels():
    rate = s.line_rate(60.0, 0.05)
    assert math.isclose(60.0 * (1 / rate), 0.05, rel_tol=1e-15)


# -- colour --------------------------------------------------------------------------------------

@pytest.mark.parametrize("pattern", sorted(s.BAYER_PATTERNS))
def test_bayer_masks_partition_the_pixels_with_half_green(pattern):
    m = s.bayer_masks((6, 8), pattern)
    np.testing.assert_array_equal(m.sum(axis=0), np.ones((6, 8)))
    assert m[1].mean() == 0.5 and m[0].mean() == m[2].mean() == 0.25
    assert "RGB"[int(np.argmax(m[:, 0, 0]))] == pattern[0]


@pytest.mark.parametrize("pattern", sorted(s.BAYER_PATTERNS))
def test_demosaic_agrees_with_opencv_in_the_interior(pattern):
    rng = np.random.default_rng(7)
    rgb = 4.0 * rng.integers(0, 64, (12, 14, 3))   # multiples of 4: OpenCV's means exact
    mosaic = s.bayer_mosaic(rgb, pattern)
    ours = s.demosaic_bilinear(mosaic, pattern)
    theirs = cv2.cvtColor(mosaic.astype(np.uint8), OPENCV_BAYER[pattern]).astype(float)
    np.testing.assert_array_equal(ours[1:-1, 1:-1], theirs[1:-1, 1:-1])
    masks = s.bayer_masks(mosaic.shape, pattern)
    for k in range(3):                          # measured values are kept
        np.testing.assert_array_equal(ours[..., k][masks[k]], rgb[..., k][masks[k]])


def test_demosaic_reproduces_a_linear_ramp_exactly_inside():
    r, c = np.mgrid[0:10, 0:12].astype(float)
    rgb = np.stack([r + 2 * c, 3 * r - c, 5.0 + 0 * r], axis=-1)
    out = s.demosaic_bilinear(s.bayer_mosaic(rgb))
    np.testing.assert_allclose(out[1:-1, 1:-1], rgb[1:-1, 1:-1], atol=1e-12)


# -- sampling, aliasing, MTF ---------------------------------------------------------------------

@pytest.mark.parametrize("ff", [1.0, 0.5, 0.3])
def test_pixel_mtf_is_the_fourier_transform_of_the_box(ff):
    p = 0.005
    a = p * math.sqrt(ff)
    dx = a / 200
    n = 2**16
    box = np.zeros(n)
    box[:200] = 1.0                                 # a box of width a, finely sampled
    spectrum = np.abs(np.fft.rfft(box))
    freqs = np.fft.rfftfreq(n, dx)
    keep = freqs < 3.0 / p
    ours = s.pixel_mtf(freqs[keep], p, ff)
    np.testing.assert_allclose(ours, spectrum[keep] / spectrum[0], atol=2e-4)


def test_pixel_mtf_by_quadrature_at_nyquist():
    p, ff = 0.006, 0.64
    a = p * math.sqrt(ff)
    f = s.nyquist_frequency(p)
    integral, _ = scipy.integrate.quad(lambda x: math.cos(2 * math.pi * f * x), -a / 2, a / 2)
    assert math.isclose(s.pixel_mtf(f, p, ff), abs(integral / a), rel_tol=1e-10)


@pytest.mark.parametrize("freq", [13.0, 60.0, 100.0, 140.0, 190.0, 260.0, 400.0])
def test_alias_frequency_is_the_fft_peak_of_the_samples(freq):
    p, n = 0.005, 1000                                # bins of 1/(n·p) = 0.2 per mm
    _, v = s.sample_sine(freq, p, n, phase=0.3)
    spectrum = np.abs(np.fft.rfft(v))
    peak = np.fft.rfftfreq(n, p)[np.argmax(spectrum)]
    assert math.isclose(peak, s.alias_frequency(freq, p), abs_tol=1e-9)
    assert s.alias_frequency(freq, p) <= s.nyquist_frequency(p)


def test_pixel_integration_of_the_sine_by_quadrature():
    p, ff, f = 0.005, 0.5, 70.0
    a = p * math.sqrt(ff)
    x, v = s.sample_sine(f, p, 5, phase=0.4, fill_factor=ff)
    for xk, vk in zip(x, v):
        mean, _ = scipy.integrate.quad(lambda t: math.cos(2 * math.pi * f * t + 0.4),
                                       xk - a / 2, xk + a / 2)
        assert math.isclose(vk, mean / a, rel_tol=1e-9, abs_tol=1e-12)


# -- bad input -----------------------------------------------------------------------------------

@pytest.mark.parametrize("bits", [0, -3, 2.5, True, "8", 33])
def test_bits_must_be_a_positive_integer(bits):
    with pytest.raises(ValueError, match="bits must be a positive integer"):
        s.grey_levels(bits)


@pytest.mark.parametrize("call, match", [
    (lambda: s.quantise([0.1, np.nan], 8), "signal must be finite"),
    (lambda: s.quantise([0.1], 8, full_scale=0.0), "full_scale must be > 0"),
    (lambda: s.dequantise([256], 8), "dn must be integers 0 … 255"),
    (lambda: s.dequantise([1.5], 8), "dn must be integers"),
    (lambda: s.bits_for_levels(1), "levels must be an integer ≥ 2"),
    (lambda: s.gain_e_per_dn(-100.0, 12), "full_well_e must be > 0"),
    (lambda: s.dynamic_range(20000.0, 0.0), "read_noise_e must be > 0"),
    (lambda: s.dynamic_range(float("nan"), 3.0), "full_well_e must be finite"),
    (lambda: s.snr(-5.0), "signal_e must be ≥ 0"),
    (lambda: s.snr(0.0), "SNR undefined"),
    (lambda: s.snr(10.0, gain=0.0), "gain must be > 0"),
    (lambda: s.ground_sampling_distance(0.005, -50.0, 100.0), "c must be > 0"),
    (lambda: s.ground_sampling_distance(0.005, 50.0, [100.0, np.nan]), "distance must be finite"),
    (lambda: s.footprint(100, 100, 0.01, 50.0, [0.0, 0.0]), r"X0 has shape \(2,\)"),
    (lambda: s.flight_block(1e3, 1e3, 1e3, 100.0, 0.005, 1e4, 1e4, overlap=0.3),
     r"overlap must be a fraction in \[0.5, 1\)"),
    (lambda: s.flight_block(1e3, 1e3, 1e3, 100.0, 0.005, 1e4, 1e4, sidelap=1.0),
     r"sidelap must be a fraction in \[0, 1\)"),
    (lambda: s.bayer_mosaic(np.zeros((4, 4))), r"rgb has shape \(4, 4\); expected \(H, W, 3\)"),
    (lambda: s.demosaic_bilinear(np.zeros((4, 4)), "RGBG"), "Bayer pattern 'RGBG' is not one"),
    (lambda: s.demosaic_bilinear(np.zeros((1, 4))), r"mosaic has shape \(1, 4\)"),
    (lambda: s.pixel_mtf(10.0, 0.005, fill_factor=1.2), r"fill_factor must be in \(0, 1\]"),
    (lambda: s.pixel_mtf(-1.0, 0.005), "frequency must be ≥ 0"),
    (lambda: s.alias_frequency(10.0, 0.0), "pixel_pitch must be > 0"),
    (lambda: s.sample_sine(10.0, 0.005, 1), "n must be an integer ≥ 2"),
])
def test_bad_input_names_the_value(call, match):
    with pytest.raises(ValueError, match=match):
        call()


@settings(max_examples=50, deadline=None)
@given(st.floats(0.0, 1000.0), st.integers(-3, 3), st.sampled_from([0.002, 0.005, 0.0065]))
def test_alias_frequency_is_periodic_in_the_sampling_rate(f, k, p):
    fs = 1.0 / p
    if f + k * fs < 0:
        k = -k
    shifted = f + k * fs
    assert math.isclose(s.alias_frequency(shifted, p), s.alias_frequency(f, p),
                        abs_tol=1e-9 * max(1.0, shifted))
    assert 0.0 <= s.alias_frequency(f, p) <= s.nyquist_frequency(p) * (1 + 1e-12)


@settings(max_examples=30, deadline=None)
@given(st.integers(0, 2**31 - 1), st.floats(-3.0, 3.0), st.sampled_from(sorted(s.BAYER_PATTERNS)))
def test_bayer_mosaic_and_demosaic_are_linear(seed, alpha, pattern):
    rng = np.random.default_rng(seed)
    a, b = rng.uniform(0, 1, (2, 6, 8, 3))
    mix = s.demosaic_bilinear(s.bayer_mosaic(a + alpha * b, pattern), pattern)
    parts = (s.demosaic_bilinear(s.bayer_mosaic(a, pattern), pattern)
             + alpha * s.demosaic_bilinear(s.bayer_mosaic(b, pattern), pattern))
    np.testing.assert_allclose(mix, parts, atol=1e-12)


# -- flight_block and bayer_masks name their arguments (audit S1, S2) ------------------------------

@pytest.mark.parametrize("kwargs, match", [
    ({"height": -300.0}, r"height must be > 0, got -300.0"),
    ({"height": np.array([300.0, 400.0])}, r"height must be a real number"),
    ({"height": np.nan}, r"height must be finite"),
    ({"n_along": 8000.7}, r"n_along must be an integer, got 8000.7"),
    ({"n_across": 0}, r"n_across must be an integer ≥ 1, got 0"),
    ({"n_along": "8000"}, r"n_along must be an integer"),
    ({"c": np.array([50.0, 60.0])}, r"c must be a real number"),
    ({"pixel_size": -0.005}, r"pixel_size must be > 0"),
])
def test_flight_block_names_the_bad_argument(kwargs, match):
    args = dict(length=1000.0, width=500.0, height=300.0, c=50.0, pixel_size=0.005,
                n_along=8000, n_across=6000)
    args.update(kwargs)
    with pytest.raises(ValueError, match=match):
        s.flight_block(**args)


def test_flight_block_accepts_integral_float_pixel_counts():
    a = s.flight_block(1000.0, 500.0, 300.0, 50.0, 0.005, 8000, 6000)
    assert s.flight_block(1000.0, 500.0, 300.0, 50.0, 0.005, 8000.0, np.int64(6000)) == a


@pytest.mark.parametrize("shape, match", [
    ((np.nan, 4), r"shape\[0\] must be an integer, got nan"),
    ((4.7, 4), r"shape\[0\] must be an integer, got 4.7"),
    ((4, 1), r"shape\[1\] must be an integer ≥ 2, got 1"),
    ((4, "4"), r"shape\[1\] must be an integer, got '4'"),
    ((4, 4, 3), r"shape must be \(H, W\)"),
    (5, r"shape must be \(H, W\)"),
])
def test_bayer_masks_checks_the_entries_of_shape(shape, match):
    with pytest.raises(ValueError, match=match):
        s.bayer_masks(shape)


def test_bayer_masks_accepts_integral_entries():
    np.testing.assert_array_equal(s.bayer_masks((4.0, np.int64(6))), s.bayer_masks((4, 6)))
