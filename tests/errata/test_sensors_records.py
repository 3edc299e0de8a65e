"""The sensor / digital-image records of the errata catalogue, re-checked by other routes.

NumPy/SciPy only (no SymPy derivation reused): ray casting of pixel corners and the shoelace
area, a Monte-Carlo sensor with binomial quantum efficiency, numerical quadrature of the
irradiance cone and of the uniform rounding error, counting a Bayer tile, Bessel zeros from
SciPy, and plain arithmetic for the Hungarian accuracy figures.
"""

import math

import numpy as np
import pytest
import scipy.integrate
import scipy.special

from photolib import errata

NEW_IDS = ("de-summary:pixel-resolution", "de-summary:gain", "de-summary:full-well",
           "de-summary:cmos-dynamic-range", "de-summary:cmos-other-advantages",
           "de-summary:exposure", "de-summary:colour-resolution", "de-summary:fill-factor",
           "de-summary:quantisation", "de-summary:diffraction-airy",
           "hu-wiki:accuracy-analogue", "hu-wiki:accuracy-analytical",
           "hu-wiki:digital-accuracy", "hu-wiki:history")


def kind(rid):
    return errata.get(rid).verdicts["printed"].split(":")[0]


@pytest.mark.parametrize("rid", NEW_IDS)
def test_new_records_registered_cited_and_claimed(rid):
    rec = errata.get(rid)
    assert rec.source.startswith(("000_5cb9d2460e6d5d8e.txt", "001_a18d25e57ee77a17.txt"))
    assert "line" in rec.source
    assert rec.specs["printed"].claim == "right"
    assert rec.verdicts == rec.stated


# -- pixel resolution: ray casting of the four pixel corners -------------------------------------

def _rot(omega, phi, kappa):
    cw, sw, cp, sp_, ck, sk = (math.cos(omega), math.sin(omega), math.cos(phi), math.sin(phi),
                               math.cos(kappa), math.sin(kappa))
    Rw = np.array([[1, 0, 0], [0, cw, -sw], [0, sw, cw]])
    Rp = np.array([[cp, 0, sp_], [0, 1, 0], [-sp_, 0, cp]])
    Rk = np.array([[ck, -sk, 0], [sk, ck, 0], [0, 0, 1]])
    return Rw @ Rp @ Rk


def _footprint_area(p, c, H, R, x, y):
    """Shoelace area of the ground quadrilateral of the pixel [x, x+p] × [y, y+p] (Z = 0)."""
    corners = []
    for u, v in ((x, y), (x + p, y), (x + p, y + p), (x, y + p)):
        D = R @ np.array([u, v, -c])
        lam = -H / D[2]
        corners.append(lam * D[:2])
    P = np.array(corners)
    return 0.5 * abs(np.dot(P[:, 0], np.roll(P[:, 1], -1)) - np.dot(P[:, 1], np.roll(P[:, 0], -1)))


def test_pixel_area_vertical_is_gsd_squared_and_tilt_changes_it():
    p, c, H = 0.006e-3, 0.1, 1000.0                  # 6 µm, c = 100 mm, H = 1000 m (metres)
    gsd = p * H / c
    assert gsd == pytest.approx(0.06)
    for kappa, x, y in ((0.0, 0.0, 0.0), (0.7, 0.01, -0.02), (-2.0, -0.03, 0.015)):
        A = _footprint_area(p, c, H, _rot(0.0, 0.0, kappa), x, y)
        assert A == pytest.approx(gsd**2, rel=1e-6)     # shoelace cancellation ~1e-9
    tilted = _footprint_area(p, c, H, _rot(0.05, 0.2, 0.3), 0.02, 0.01)
    assert abs(tilted / gsd**2 - 1) > 5e-3                 # 0.94 % here, far above 1e-6
    assert kind("de-summary:pixel-resolution") == "right-under-condition"


def test_pixel_area_derivation_agrees_with_ray_casting_when_tilted():
    from photolib.derive import sensors as s
    vals = dict(omega=0.05, phi=0.2, kappa=0.3, x=0.02, y=0.01, p=1e-6, H=1000.0, c=0.1, g=0.0)
    A = float(s.pixel_ground_area().subs({getattr(s, k): v for k, v in vals.items()}))
    ref = _footprint_area(1e-6, 0.1, 1000.0, _rot(0.05, 0.2, 0.3), 0.02, 0.01)
    assert A == pytest.approx(ref, rel=1e-4)       # area element vs finite pixel


# -- gain and full well: a Monte-Carlo sensor ----------------------------------------------------

def _photons_per_dn(eta, K, rng):
    N = np.linspace(1000, 20000, 20)
    dn = np.array([np.mean(np.floor(rng.binomial(int(n), eta, 4000) / K)) for n in N])
    return 1 / np.polyfit(N, dn, 1)[0]


def test_photons_per_grey_level_is_gain_over_qe():
    rng = np.random.default_rng(7)
    K = 5.0
    assert _photons_per_dn(1.0, K, rng) == pytest.approx(K, rel=0.01)
    assert _photons_per_dn(0.5, K, rng) == pytest.approx(K / 0.5, rel=0.01)
    assert kind("de-summary:gain") == "right-under-condition"


def _max_dn_at_saturation(full_well, K, bits):
    electrons = np.arange(0, full_well + 1)
    return int(np.clip(np.round(electrons / K), 0, 2**bits - 1).max())


def test_full_well_matches_gain_times_levels_only_when_set_so():
    fw, bits = 40950, 12
    K = fw / (2**bits - 1)                          # matched: 10 e⁻/DN
    assert _max_dn_at_saturation(fw, K, bits) == 2**bits - 1
    assert K * (2**bits - 1) == pytest.approx(fw)
    half = _max_dn_at_saturation(fw, 2 * K, bits)   # gain doubled: half the codes unused
    assert half == (2**bits - 1 + 1) // 2
    assert 2 * K * (2**bits - 1) != pytest.approx(fw)
    assert kind("de-summary:full-well") == "right-under-condition"


# -- CMOS dynamic range: no general ordering -----------------------------------------------------

def test_dynamic_range_depends_on_device_data_only():
    def dr_db(fw, read):
        return 20 * math.log10(fw / read)
    ccd_sci, cmos_old = dr_db(100_000, 4.0), dr_db(20_000, 10.0)
    ccd_old, cmos_new = dr_db(20_000, 15.0), dr_db(30_000, 1.5)
    assert ccd_sci > cmos_old and cmos_new > ccd_old   # either order occurs
    assert kind("de-summary:cmos-dynamic-range") == "not-checkable"
    assert kind("de-summary:cmos-other-advantages") == "not-checkable"


# -- exposure: quadrature of the irradiance cone -------------------------------------------------

def _irradiance(d, f, L=1.0):
    u = math.asin(d / (2 * f))                       # sine condition
    inner, _ = scipy.integrate.quad(lambda th: L * math.cos(th) * math.sin(th), 0, u)
    return 2 * math.pi * inner


def test_exposure_goes_with_pupil_area_times_time():
    f = 0.05
    E1, E2 = _irradiance(0.01, f), _irradiance(0.02, f)
    assert E2 / E1 == pytest.approx(4.0, rel=1e-9)  # doubling d: 4× (area), not 2× (diameter)
    assert E1 == pytest.approx(math.pi * (0.01 / 2) ** 2 / f**2, rel=1e-9)
    # the f-number form: Q ∝ t/k², one stop (k·√2) halves the light
    k = 4.0
    assert (_irradiance(f / (k * math.sqrt(2)), f) * 2 / _irradiance(f / k, f)
            == pytest.approx(1.0, rel=1e-9))
    rec = errata.get("de-summary:exposure")
    assert kind("de-summary:exposure") == "right-under-condition"
    assert "area" in rec.specs["printed"].condition_text


# -- colour mosaic, fill factor, quantisation ----------------------------------------------------

def test_bayer_tile_fractions_by_counting():
    tile = np.array([["R", "G"], ["G", "B"]])
    mosaic = np.tile(tile, (8, 8))
    fr = {col: np.mean(mosaic == col) for col in "RGB"}
    assert fr == {"R": 0.25, "G": 0.5, "B": 0.25}
    # red pixels sit on every second column and row: sampling pitch 2p
    rows, cols = np.nonzero(mosaic == "R")
    assert set(np.diff(np.unique(cols))) == {2} and set(np.diff(np.unique(rows))) == {2}
    assert kind("de-summary:colour-resolution") == "right-under-condition"


def test_fill_factor_by_monte_carlo():
    rng = np.random.default_rng(11)
    p, a, n = 1.0, 0.6, 400_000
    pts = rng.uniform(0, p, (n, 2))
    frac = np.mean(np.all(pts < a, axis=1))
    assert abs(frac - a**2 / p**2) < 5 * math.sqrt(0.36 * 0.64 / n)
    assert kind("de-summary:fill-factor") == "right"


def test_quantisation_variance_by_quadrature():
    step = 0.7
    var, _ = scipy.integrate.quad(lambda e: e * e / step, -step / 2, step / 2)
    assert var == pytest.approx(step**2 / 12, rel=1e-12)
    assert kind("de-summary:quantisation") == "right"


def test_airy_factor_from_scipy_bessel_zero():
    factor = scipy.special.jn_zeros(1, 1)[0] / math.pi
    assert factor == pytest.approx(1.21967, abs=5e-6) and round(factor, 2) == 1.22
    rec = errata.get("de-summary:diffraction-airy")
    assert float(rec.derived()) == pytest.approx(factor, rel=1e-12)
    assert kind("de-summary:diffraction-airy") == "not-checkable"


# -- Hungarian article: accuracy figures ---------------------------------------------------------

@pytest.mark.parametrize("rid, lo, hi, sigma_um", [
    ("hu-wiki:accuracy-analogue", 5.0, 10.0, (5.0, 10.0)),
    ("hu-wiki:accuracy-analytical", 3.0, 5.0, (3.0, 5.0)),
])
def test_accuracy_figures_are_image_microns_times_a_million(rid, lo, hi, sigma_um):
    # σ_X = m_b·σ': metres equal image micrometres exactly at m_b = 10⁶
    assert 1e6 * sigma_um[0] * 1e-6 == pytest.approx(lo)
    assert 1e6 * sigma_um[1] * 1e-6 == pytest.approx(hi)
    # an aerial camera (c = 153 mm) at 12 km: m_b = 7.8·10⁴, far below the printed figures
    mb_aerial = 12_000 / 0.153
    assert mb_aerial * sigma_um[1] * 1e-6 < hi / 10
    # the scale number the printed upper bound needs at σ' = 10 µm exceeds any aircraft's H/c
    assert hi / 10e-6 > 5 * mb_aerial
    ev = errata.get(rid).evaluate("printed")
    assert ev.verdict.startswith("right-under-condition") and "µm" in ev.verdict
    assert [r[4] for r in ev.table] == [True] * (len(ev.table) - 1) + [False]


def test_digital_accuracy_scales_with_gsd():
    s_px, c, H = 0.3, 0.1, 1000.0
    for p in (3e-6, 6e-6, 12e-6):
        gsd = p * H / c
        assert (H / c) * (s_px * p) == pytest.approx(s_px * gsd)
    assert kind("hu-wiki:digital-accuracy") == "right-under-condition"
    assert kind("hu-wiki:history") == "not-checkable"
