"""The exercises of chapter 03 (digital images and sensors), judged as the grader does.

The checks of ``test_chapter08.py`` (reference accepted, every declared mistake recognised
with its hint, variants differ, functions judged on hidden cases, untouched answers not
answered), the master graded to full marks and the untouched copy to zero by the batch
grader, and the references by independent routes: ``photolib.project`` for the GSD, counting
bit patterns, SymPy's integral of the rounding error, a seeded Monte-Carlo pixel for the SNR,
and the Bayer pattern tiled by hand.
"""

from __future__ import annotations

import math
import pickle
import subprocess
import sys

import numpy as np
import pytest
import sympy as sp

import photolib as pl
from photolib.grading.encode import decode_value, encode_value
from photolib.grading.exercises import ch03_digital_images as ch03
from photolib.grading.exercises import chapter
from photolib.grading.judge import judge
from photolib.grading.notebook import function_outputs, parameters_for, reference_outputs
from photolib.grading.variants import rng_for

from .conftest import ROOT

EXERCISES = ch03.EXERCISES
BY_ID = {ex.id: ex for ex in EXERCISES}
STUDENTS = ("s1000001", "s1000002", "s1000003", "s2345678", "s3000005", "s3000006")


def _judge(ex, sid, value):
    params = parameters_for(ex, sid)
    if ex.kind == "function":
        cases = ex.cases(rng_for(sid, ex.id, "hidden"), params)
        return judge(ex, params, function_outputs(value, cases), reference_outputs(cases))
    return judge(ex, params, decode_value(encode_value(value)))


def test_module_is_the_registered_chapter():
    assert ch03.CHAPTER == "03-digital-images"
    assert chapter("03-digital-images") == EXERCISES
    assert len(EXERCISES) >= 4
    assert {"number", "choice", "function"} <= {ex.kind for ex in EXERCISES}


@pytest.mark.parametrize("ex", EXERCISES, ids=lambda ex: ex.id)
@pytest.mark.parametrize("sid", STUDENTS[:2])
def test_reference_is_accepted(ex, sid):
    verdict = _judge(ex, sid, ex.reference(parameters_for(ex, sid)))
    assert verdict.status == "correct", verdict.message
    assert verdict.points == ex.points


@pytest.mark.parametrize("ex", EXERCISES, ids=lambda ex: ex.id)
def test_each_mistake_is_recognised_with_its_hint(ex):
    assert ex.mistakes, f"{ex.id} declares no mistakes"
    for index, mistake in enumerate(ex.mistakes):
        applied = 0
        for sid in STUDENTS:
            wrong = mistake.wrong(parameters_for(ex, sid))
            if wrong is None:
                continue
            applied += 1
            verdict = _judge(ex, sid, wrong)
            assert verdict.status == "wrong", (ex.id, index, sid)
            assert verdict.mistake == mistake.tag, (ex.id, index, sid, verdict.message)
            assert verdict.message == f"not correct: {mistake.message}", (ex.id, index, sid)
        assert applied, f"{ex.id}: mistake {index} ({mistake.tag}) never applies"


@pytest.mark.parametrize("ex", EXERCISES, ids=lambda ex: ex.id)
def test_students_get_different_variants(ex):
    a, b = (parameters_for(ex, sid) for sid in STUDENTS[:2])
    assert a != b
    assert parameters_for(ex, STUDENTS[0]) == a
    assert ex.statement.format(**a) != ex.statement.format(**b)


def test_choice_variants_do_not_carry_the_answer():
    ex = BY_ID["dig.bayer-green"]
    letters = set()
    for sid in STUDENTS:
        p = parameters_for(ex, sid)
        assert set(p) == {"options"}
        letters.add(ex.reference(p))
    assert len(letters) > 1                       # the correct letter moves between students


@pytest.mark.parametrize("ex", [ex for ex in EXERCISES if ex.kind == "function"],
                         ids=lambda ex: ex.id)
def test_hidden_inputs_differ_from_the_public_ones(ex):
    params = parameters_for(ex, STUDENTS[0])
    public = ex.cases(rng_for(STUDENTS[0], ex.id, "public"), params)
    hidden = ex.cases(rng_for(STUDENTS[0], ex.id, "hidden"), params)
    assert len(public) == len(hidden) >= 3
    assert public != hidden
    for case in public + hidden:
        assert all(np.ndim(arg) == 0 and float(arg) == arg for arg in case)


@pytest.mark.parametrize("ex", EXERCISES, ids=lambda ex: ex.id)
def test_untouched_answer_is_not_answered(ex):
    value = (lambda *args: ...) if ex.kind == "function" else ...
    assert _judge(ex, STUDENTS[0], value).status == "not-answered"


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


# -- the notebooks, graded by the batch grader ----------------------------------------------------

_GRADE = """
import pickle, sys
from photolib.grading.batch import grade_batch
from photolib.grading.sandbox import Limits
results = grade_batch(sys.argv[2:], Limits(timeout=60), jobs=1)
with open(sys.argv[1], "wb") as f:
    pickle.dump({r.submission: r for r in results}, f)
"""


@pytest.fixture(scope="module")
def graded(tmp_path_factory):
    out = tmp_path_factory.mktemp("ch03") / "graded.pickle"
    paths = [str(ROOT / "solutions" / "03-digital-images.ipynb"),
             str(ROOT / "exercises" / "03-digital-images.ipynb")]
    proc = subprocess.run([sys.executable, "-c", _GRADE, str(out), *paths],
                          capture_output=True, text=True, timeout=300)
    assert proc.returncode == 0, proc.stderr[-3000:]
    with open(out, "rb") as f:
        return pickle.load(f)


def test_master_gets_full_marks(graded):
    r = graded[str(ROOT / "solutions" / "03-digital-images.ipynb")]
    assert r.status == "ok", r.detail
    assert r.total == r.max_total == sum(ex.points for ex in EXERCISES)


def test_untouched_copy_gets_zero(graded):
    r = graded[str(ROOT / "exercises" / "03-digital-images.ipynb")]
    assert r.status == "no-student-id", r.detail
    assert r.total == 0 and {j.status for j in r.judgements} == {"not-answered"}
    assert r.output.count("not answered yet") == len(EXERCISES)
