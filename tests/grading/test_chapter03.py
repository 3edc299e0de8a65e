"""The exercises of chapter 03 (digital images and sensors), judged as the grader does.

The checks of ``ChapterChecks`` (reference accepted, every declared mistake recognised
with its hint, variants differ, functions judged on hidden cases, untouched answers not
answered), the master graded to full marks and the untouched copy to zero by the batch
grader, and the references by independent routes: ``photolib.project`` for the GSD, counting
bit patterns, SymPy's integral of the rounding error, a seeded Monte-Carlo pixel for the SNR,
and the Bayer pattern tiled by hand.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
import sympy as sp

import photolib as pl
from photolib.grading.exercises import ch03_digital_images as ch03
from photolib.grading.notebook import parameters_for
from photolib.grading.variants import rng_for

from .chapter_checks import BatchGradedChecks, ChapterChecks
from .chapter_checks import judge_as_grader as _judge

EXERCISES = ch03.EXERCISES
BY_ID = {ex.id: ex for ex in EXERCISES}
STUDENTS = ("s1000001", "s1000002", "s1000003", "s2345678", "s3000005", "s3000006")


class TestChapter03(ChapterChecks, BatchGradedChecks):
    module = ch03
    chapter_name = "03-digital-images"
    kinds = {"number", "choice", "function"}
    students = STUDENTS


def test_choice_variants_do_not_carry_the_answer():
    ex = BY_ID["dig.bayer-green"]
    letters = set()
    for sid in STUDENTS:
        p = parameters_for(ex, sid)
        assert set(p) == {"options"}
        letters.add(ex.reference(p))
    assert len(letters) > 1                       # the correct letter moves between students


def test_a_slightly_wrong_gsd_is_wrong_without_a_hint():
    ex = BY_ID["dig.gsd"]
    ref = ex.reference(parameters_for(ex, STUDENTS[0]))
    verdict = _judge(ex, STUDENTS[0], ref * 1.01)
    assert verdict.status == "wrong" and verdict.mistake == "other"


# -- the references by an independent route -------------------------------------------------------

@pytest.mark.parametrize("sid", STUDENTS)
def test_gsd_reference_is_one_pixel_projected_back(sid):
    p = parameters_for(BY_ID["dig.gsd"], sid)
    gsd_m = ch03._gsd_cm(p) / 100
    xy = pl.project([[0.0, 0.0, 0.0], [gsd_m, 0.0, 0.0]], [0.0, 0.0, p["h_m"]], np.eye(3),
                    p["c_mm"])
    assert math.isclose(xy[1, 0] - xy[0, 0], p["pixel_um"] / 1000, rel_tol=1e-10)


@pytest.mark.parametrize("sid", STUDENTS)
def test_bits_reference_is_the_smallest_sufficient_depth(sid):
    p = parameters_for(BY_ID["dig.bits"], sid)
    dr = p["full_well"] / p["read_noise"]
    b = next(k for k in range(1, 40) if 2**k >= dr)      # count up, no logarithm
    assert ch03._bits(p) == b


@pytest.mark.parametrize("sid", STUDENTS[:3])
def test_quantisation_noise_reference_by_integration(sid):
    p = parameters_for(BY_ID["dig.quant-noise"], sid)
    e = sp.Symbol("e", real=True)
    K = sp.Rational(p["full_well"], 2 ** p["bits"] - 1)        # electrons per DN
    variance = sp.integrate(e**2, (e, -K / 2, K / 2)) / K
    assert math.isclose(ch03._sigma_q(p), float(sp.sqrt(variance)), rel_tol=1e-14)


@pytest.mark.parametrize("sid", STUDENTS[:3])
def test_snr_reference_by_a_simulated_pixel(sid):
    p = parameters_for(BY_ID["dig.snr-db"], sid)
    rng = np.random.default_rng(17)
    n = 400_000
    electrons = rng.poisson(p["signal"], n) + rng.normal(0.0, p["read_noise"], n)
    out = np.rint(electrons / p["gain"]) * p["gain"]
    sd = out.std(ddof=1)
    m4 = np.mean((out - out.mean()) ** 4)
    se_sd = math.sqrt(max(m4 - sd**4, 0.0) / n) / (2 * sd)
    se_db = 20 / math.log(10) * se_sd / sd                 # dB error from the SD's error
    simulated_db = 20 * math.log10(p["signal"] / sd)
    assert abs(ch03._snr_db(p) - simulated_db) < 5 * se_db + 1e-3


def test_bayer_reference_by_the_tiled_pattern():
    tile = np.array([["R", "G"], ["G", "B"]])
    mosaic = np.tile(tile, (50, 75))
    share = float(np.mean(mosaic == "G"))
    assert share == 0.5 == float(pl.bayer_masks(mosaic.shape)[1].mean())
    ex = BY_ID["dig.bayer-green"]
    p = parameters_for(ex, STUDENTS[0])
    key = ex.reference(p)
    assert f"({key}) one half" in p["options"]


@pytest.mark.parametrize("sid", STUDENTS[:2])
def test_gsd_function_agrees_with_the_library(sid):
    ex = BY_ID["dig.gsd-function"]
    p = parameters_for(ex, sid)
    f = ex.reference(p)
    for (H,) in ex.cases(rng_for(sid, ex.id, "public"), p):
        assert math.isclose(f(H), 100 * pl.ground_sampling_distance(p["pixel_um"] / 1000,
                                                                    p["c_mm"], H), rel_tol=1e-12)



# -- dig.snr-db: the quantisation noise must count -------------------------------------------------

def _snr_by_hand(p, quant=True):
    # S/σ with σ² = S (Poisson) + σ_r² + K²/12, written out again from the statement
    var = p["signal"] + p["read_noise"] ** 2 + (p["gain"] ** 2 / 12 if quant else 0)
    return 20 * math.log10(p["signal"] / math.sqrt(var))


def test_snr_without_quantisation_noise_is_wrong_for_every_id():
    ex = BY_ID["dig.snr-db"]
    rtol, atol = ex.tolerances(parameters_for(ex, "s0"))
    assert atol <= 1e-3 and rtol == 0.0
    for i in range(2000):
        p = parameters_for(ex, f"s{5000000 + i}")
        full, without = _snr_by_hand(p), _snr_by_hand(p, quant=False)
        assert abs(ex.reference(p) - full) <= 1e-9
        assert abs(without - full) > 100 * atol, (p, without - full)


@pytest.mark.parametrize("sid", STUDENTS)
def test_snr_missing_quantisation_noise_gets_its_hint(sid):
    ex = BY_ID["dig.snr-db"]
    p = parameters_for(ex, sid)
    verdict = _judge(ex, sid, _snr_by_hand(p, quant=False))
    assert verdict.status == "wrong" and verdict.mistake == "quant-noise"
    assert "K²/12" in verdict.message


@pytest.mark.parametrize("sid", STUDENTS[:3])
def test_snr_tolerance_allows_rounding_and_float32(sid):
    ex = BY_ID["dig.snr-db"]
    p = parameters_for(ex, sid)
    exact = _snr_by_hand(p)
    assert _judge(ex, sid, round(exact, 4)).status == "correct"
    f32 = {k: np.float32(v) for k, v in p.items()}
    snr32 = np.float32(20) * np.log10(f32["signal"] / np.sqrt(
        f32["signal"] + f32["read_noise"] ** 2 + f32["gain"] ** 2 / np.float32(12)))
    assert _judge(ex, sid, float(snr32)).status == "correct"
    # five times the tolerance off is wrong; the tolerance is the rounding of the printed
    # σ_r and K (some 5e-4 dB, docs/instructors.md), no longer the fixed atol of 1e-4 dB
    assert _judge(ex, sid, exact + 5 * ex.tolerances(p)[1]).status == "wrong"
