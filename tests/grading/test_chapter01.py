"""The exercises of chapter 01 (what photogrammetry is), judged as the grader does.

The checks of ``ChapterChecks`` (reference accepted, every declared mistake recognised
with its hint, variants differ, functions judged on hidden cases, untouched answers not
answered), the master graded to full marks and the untouched copy to zero by the batch
grader, and the references by independent routes: ``photolib.project`` for the image scale
and the ground size, counting on a grid of ground points the images that see each point for
the flight plan, and the chapter's history table for the history question.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

import photolib as pl
from photolib.grading.exercises import ch01_introduction as ch01
from photolib.grading.notebook import parameters_for
from photolib.grading.variants import rng_for
from photolib.nb import intro as ni

from .chapter_checks import BatchGradedChecks, ChapterChecks
from .chapter_checks import judge_as_grader as _judge

EXERCISES = ch01.EXERCISES
BY_ID = {ex.id: ex for ex in EXERCISES}
STUDENTS = ("s1000001", "s1000002", "s1000003", "s2345678", "s3000005", "s3000006")


class TestChapter01(ChapterChecks, BatchGradedChecks):
    module = ch01
    chapter_name = "01-introduction"
    kinds = {"number", "choice", "function"}
    students = STUDENTS


@pytest.mark.parametrize("eid", ["int.classes", "int.history"])
def test_choice_variants_do_not_carry_the_answer(eid):
    ex = BY_ID[eid]
    letters = set()
    for sid in STUDENTS:
        p = parameters_for(ex, sid)
        assert set(p) <= {"options", "task"}
        letters.add(ex.reference(p))
    assert len(letters) > 1                       # the correct letter moves between students


def test_a_slightly_wrong_scale_number_is_wrong_without_a_hint():
    ex = BY_ID["int.scale-number"]
    ref = ex.reference(parameters_for(ex, STUDENTS[0]))
    verdict = _judge(ex, STUDENTS[0], ref * 1.01)
    assert verdict.status == "wrong" and verdict.mistake == "other"


# -- the references by an independent route -------------------------------------------------------

@pytest.mark.parametrize("sid", STUDENTS)
def test_scale_number_is_ground_length_over_image_length(sid):
    p = parameters_for(BY_ID["int.scale-number"], sid)
    xy = pl.project([[0.0, 0.0, 0.0], [100.0, 0.0, 0.0]], [0.0, 0.0, p["h_m"]], np.eye(3),
                    p["c_mm"])
    image_length_m = (xy[1, 0] - xy[0, 0]) / 1000
    assert math.isclose(ch01._scale_number(p), 100.0 / image_length_m, rel_tol=1e-10)


def _stereo_cover_count(p):
    """Images needed, found by growing the plan until a grid of ground points is covered."""
    gsd = p["pixel_um"] * 1e-3 * p["h_m"] / p["c_mm"]
    S_al, S_ac = p["n_along"] * gsd, p["n_across"] * gsd
    B, A = S_al * (1 - p["overlap_pct"] / 100), S_ac * (1 - p["sidelap_pct"] / 100)
    L, W = p["length_km"] * 1e3, p["width_km"] * 1e3
    x, y = np.linspace(0.0, L, 400), np.linspace(0.0, W, 200)
    # images along a strip, the first stereo model starting at x = 0: add until ≥ 2 see all
    n = 2
    while True:
        cx = S_al / 2 - B + B * np.arange(n)
        if np.all((np.abs(x[:, None] - cx) <= S_al / 2 + 1e-6).sum(axis=1) >= 2):
            break
        n += 1
    k = 1
    while True:
        cy = S_ac / 2 + A * np.arange(k)
        if np.all((np.abs(y[:, None] - cy) <= S_ac / 2 + 1e-6).sum(axis=1) >= 1):
            break
        k += 1
    return float(n * k)


@pytest.mark.parametrize("sid", STUDENTS)
def test_images_reference_by_counting_the_cover(sid):
    p = parameters_for(BY_ID["int.images"], sid)
    assert ch01._images(p) == _stereo_cover_count(p) == ch01._by_hand(p)


@pytest.mark.parametrize("sid", STUDENTS[:3])
def test_ground_size_reference_by_the_library_footprint(sid):
    ex = BY_ID["int.ground-size"]
    p = parameters_for(ex, sid)
    f = ex.reference(p)
    n = 1000                                     # any pixel count: pitch = format / n
    for (H,) in ex.cases(rng_for(sid, ex.id, "public"), p):
        F = pl.footprint(n, n, p["format_mm"] / n, p["c_mm"], [0.0, 0.0, H])
        assert math.isclose(f(H), F[1, 0] - F[0, 0], rel_tol=1e-10)


def test_history_answer_is_the_chapter_history():
    year_city = {event[0]: event[2] for event in ni.HISTORY}
    assert "Vienna" in year_city[1910] and "ISP" in year_city[1910]
    assert "Meydenbauer" in year_city[1858] and "word" in year_city[1867]
    ex = BY_ID["int.history"]
    p = parameters_for(ex, STUDENTS[0])
    assert f"({ex.reference(p)}) 1910 in Vienna" in p["options"]


@pytest.mark.parametrize("sid", STUDENTS)
def test_classes_reference_matches_the_number_of_images_in_the_task(sid):
    ex = BY_ID["int.classes"]
    p = parameters_for(ex, sid)
    chosen = next(item[4:] for item in p["options"].split("; ") if item[1] == ex.reference(p))
    if "one photograph" in p["task"]:
        assert chosen.startswith("single-image")
    elif "pairs" in p["task"]:
        assert chosen.startswith("stereo")
    else:
        assert "40" in p["task"] and chosen.startswith("multi-image")



@pytest.mark.parametrize("sid", STUDENTS[:3])
def test_ground_size_accepts_float32(sid):
    ex = BY_ID["int.ground-size"]
    p = parameters_for(ex, sid)
    f = np.float32
    assert _judge(ex, sid, lambda H: f(p["format_mm"]) * f(H) / f(p["c_mm"])).status == "correct"
