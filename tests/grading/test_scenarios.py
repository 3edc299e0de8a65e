"""Multi-step exercises (``Exercise.scenario``): steps share the draw, each is graded alone."""

import pytest

from photolib.grading.exercises import _check_scenarios, chapters, scenarios
from photolib.grading.notebook import parameters_for
from photolib.grading.spec import Exercise


def _step(id_, title, scenario="demo.chain"):
    return Exercise(id=id_, points=1, title=title, kind="number", answer=id_.replace(".", "_").replace("-", "_"),
                    statement="a = {a}", scenario=scenario,
                    parameters=lambda rng: {"a": float(rng.uniform())},
                    reference=lambda p: p["a"])


def test_steps_share_the_students_numbers():
    one = _step("demo.chain", "Step 1 of 2: a")
    two = _step("demo.chain-2", "Step 2 of 2: b")
    single = _step("demo.alone", "alone", scenario="")
    assert parameters_for(one, "s1") == parameters_for(two, "s1")
    assert parameters_for(one, "s1") != parameters_for(one, "s2")
    assert parameters_for(single, "s1") != parameters_for(one, "s1")
    _check_scenarios("demo", (one, two, single))
    assert list(scenarios((one, two, single))) == ["demo.chain"]


@pytest.mark.parametrize("titles, message", [
    (("Step 1 of 2: a",), "at least two"),
    (("Step 1 of 2: a", "Step 3 of 2: b"), "must begin 'Step 2 of 2'"),
    (("a", "Step 2 of 2: b"), "must begin 'Step 1 of 2'"),
])
def test_badly_declared_scenarios_are_refused(titles, message):
    steps = [_step("demo.chain" if k == 0 else f"demo.chain-{k + 1}", t)
             for k, t in enumerate(titles)]
    with pytest.raises(ValueError, match=message):
        _check_scenarios("demo", steps)


def test_scenario_must_name_an_exercise_of_the_chapter():
    steps = [_step("demo.x", "Step 1 of 2: a", "demo.y"), _step("demo.z", "Step 2 of 2: b", "demo.y")]
    with pytest.raises(ValueError, match="not an exercise of this chapter"):
        _check_scenarios("demo", steps)


def test_course_scenarios_are_well_formed():
    for name, exercises in chapters().items():
        _check_scenarios(name, exercises)
