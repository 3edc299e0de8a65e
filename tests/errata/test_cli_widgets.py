"""CLI of the errata catalogue and the notebook widget callback."""

import json
import math
import subprocess
import sys

import pytest

from photolib.errata import cli
from photolib.errata import evaluate as widgets
from photolib.nb import errata as nb_errata


def test_json_schema(capsys):
    assert cli.errata_main(["--json"]) == 0
    data = json.loads(capsys.readouterr().out)
    assert isinstance(data, list) and len(data) > 40
    for obj in data:
        assert set(obj) == {"id", "source", "item", "verdicts", "note"}
        assert obj["verdicts"] and set(obj["verdicts"]) <= {"printed", "old", "corrected"}
        for v in obj["verdicts"].values():
            assert v in ("right", "wrong") or v.startswith(("right-under-condition: ",
                                                            "not-checkable: "))


def test_table_and_id(capsys):
    assert cli.errata_main([]) == 0
    out = capsys.readouterr().out
    assert "luhmann:4.18b" in out and "wrong" in out
    assert cli.errata_main(["--id", "luhmann:5.50-p1"]) == 0
    out = capsys.readouterr().out
    assert "step 3" in out and "verdict (corrected): wrong" in out and "counterexample" in out
    assert cli.errata_main(["--id", "nope:1"]) == 2


@pytest.mark.slow
def test_check_formula(capsys):
    right = "z_p/N*(k_y/N*(k_y*sin(kappa) - k_x*cos(kappa)) + N*sin(kappa))"
    old = "z_p/N*(k_y/N*(k_x*cos(kappa) + k_y*sin(kappa)) + N*sin(kappa))"
    assert cli.check_formula_main([right, "--against", "luhmann:4.18b"]) == 0
    assert "equal-under-condition" in capsys.readouterr().out
    assert cli.check_formula_main([old, "--against", "luhmann:4.18b"]) == 1
    assert "counterexample" in capsys.readouterr().out
    assert cli.check_formula_main(["__import__('os').system('true')", "--against",
                                   "luhmann:4.18b"]) == 2
    assert "rejected" in capsys.readouterr().err
    assert cli.check_formula_main(["-(1 - r**2/(2*sigma**2))*exp(-r**2/(2*sigma**2))"
                                   "/(pi*sigma**4)", "--against", "luhmann:5.42"]) == 0


def test_module_entry_point_id():
    res = subprocess.run([sys.executable, "-m", "photolib", "errata", "--id", "luhmann:2.86"],
                         capture_output=True, text=True, timeout=120)
    assert res.returncode == 0, res.stderr
    assert "right-under-condition: A² = 1" in res.stdout


def test_widget_callback_and_builder():
    normalised = 1 / (2 * math.pi)                               # K = 1/(2πσ²) at σ = 1
    vals = widgets.evaluate_versions("luhmann:5.42", {"r": 1.0, "sigma": 1.0, "K": normalised})
    assert vals["corrected"] == pytest.approx(vals["derived"], rel=1e-12)
    # without the normalisation (K = 1) the print is 2πσ² times too small
    unit = widgets.evaluate_versions("luhmann:5.42", {"r": 1.0, "sigma": 1.0, "K": 1.0})
    assert unit["derived"] == pytest.approx(2 * math.pi * unit["corrected"], rel=1e-12)
    assert vals["old"] == pytest.approx(0.0, abs=1e-15)      # old zero crossing at r = σ²
    with pytest.raises(ValueError, match="no value"):
        widgets.evaluate_versions("luhmann:5.42", {"r": 1.0})
    box = nb_errata.build_widget("luhmann:2.86", 0.1, 3.0)
    sliders = [c for c in box.children if hasattr(c, "continuous_update")]
    assert len(sliders) == 4
    before = box.children[-1].value
    sliders[0].value = 2.5
    assert box.children[-1].value != before and "derived" in box.children[-1].value


def test_the_old_widgets_module_still_imports_with_a_deprecation_warning():
    """photolib.errata.widgets moved (callbacks → photolib.errata.evaluate, widgets →
    photolib.nb.errata): the old names still work for one release, with a warning."""
    import photolib.errata.widgets as old
    with pytest.warns(DeprecationWarning, match="photolib.errata.evaluate.evaluate_versions"):
        assert old.evaluate_versions is widgets.evaluate_versions
    with pytest.warns(DeprecationWarning, match="photolib.nb.errata.VerdictExplorer"):
        assert old.VerdictExplorer is nb_errata.VerdictExplorer
    with pytest.raises(AttributeError, match="no_such_name"):
        old.no_such_name  # noqa: B018
