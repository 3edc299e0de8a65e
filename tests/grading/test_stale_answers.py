"""No stale answers: each task's numbers have a name of their own, and check() does not judge
an answer the notebook did not just compute (cells run in a real IPython shell, in chosen
orders)."""

from __future__ import annotations

import contextlib
import copy
import io
import random
import re
import time

import nbformat
import pytest

from photolib.grading.assign import AssignError, make_student_copy
from photolib.grading.exercises import chapter, chapters
from photolib.grading.notebook import parameters_for
from photolib.grading.spec import Exercise

from .conftest import ROOT, cell_index

SID = "s1000001"


def _filled_copy(name: str, sid: str = SID):
    """The committed student copy of ``name`` with the master's answers and ``sid`` filled in."""
    master = nbformat.read(ROOT / "solutions" / f"{name}.ipynb", as_version=4)
    nb = nbformat.read(ROOT / "exercises" / f"{name}.ipynb", as_version=4)
    answers = {t: c.source for c in master.cells for t in c.metadata.get("tags", [])
               if t.startswith("answer:")}
    for cell in nb.cells:
        tags = cell.metadata.get("tags", [])
        if "student-id" in tags:
            cell.source = f'STUDENT_ID = "{sid}"'
        for tag in tags:
            if tag in answers:
                cell.source = answers[tag]
    return nb


class Cells:
    """A notebook's code cells run one by one in an IPython shell."""

    def __init__(self, shell, nb):
        self.shell = shell
        self.cells = [c for c in nb.cells if c.cell_type == "code"]

    def index(self, needle: str) -> int:
        for i, cell in enumerate(self.cells):
            if needle in cell.source or needle in cell.metadata.get("tags", []):
                return i
        raise LookupError(needle)

    def run_source(self, source: str) -> str:
        out = io.StringIO()
        with contextlib.redirect_stdout(out), contextlib.redirect_stderr(out):
            self.shell.run_cell(source, store_history=True)
        return out.getvalue()

    def run(self, i: int) -> str:
        return self.run_source(self.cells[i].source)

    def check(self, ex_id: str) -> str:
        return self.run(self.index(f'check("{ex_id}")')).strip()

    def run_all(self) -> dict:
        verdicts = {}
        for i, cell in enumerate(self.cells):
            out = self.run(i)
            match = re.search(r'check\("([^"]+)"\)', cell.source)
            if match:
                verdicts[match.group(1)] = out.strip()
        return verdicts


@pytest.fixture
def shell():
    from IPython.core.interactiveshell import InteractiveShell
    from traitlets.config import Config
    InteractiveShell.clear_instance()
    config = Config()
    config.HistoryManager.hist_file = ":memory:"
    sh = InteractiveShell.instance(config=config)
    yield sh
    InteractiveShell.clear_instance()


@pytest.fixture
def ch04(shell):
    return Cells(shell, _filled_copy("04-rotations"))


# -- one name per task -----------------------------------------------------------------------
def test_every_chapter_has_one_parameter_name_per_task():
    for name, exercises in chapters().items():
        names = [ex.params_name for ex in exercises]
        assert len(set(names)) == len(names), name
        assert all(n.isidentifier() and n != "p" for n in names), name
        assert not set(names) & {ex.answer for ex in exercises}, name


def test_shared_or_bad_parameter_names_are_refused():
    from photolib.grading.exercises import _check_names
    kw = dict(points=1, title="t", statement="", kind="number", answer="a",
              parameters=lambda rng: {}, reference=lambda p: 0.0)
    one = Exercise(id="t.one", params_name="p_x", **kw)
    two = Exercise(id="t.two", params_name="p_x", **kw)
    with pytest.raises(ValueError, match="t.two and t.one both keep their parameters in 'p_x'"):
        _check_names("t", (one, two))
    with pytest.raises(ValueError, match="the answer variable of t.one"):
        _check_names("t", (one, Exercise(id="t.three", params_name="a", **{**kw, "answer": "b"})))
    for bad in ("1p", "class", "STUDENT_ID", "p-x"):
        with pytest.raises(ValueError, match="params_name"):
            Exercise(id="t.bad", params_name=bad, **kw)
    assert Exercise(id="t.dlt-vector", **kw).params_name == "p_dlt_vector"


def test_statements_name_only_their_own_parameters():
    for exercises in chapters().values():
        for ex in exercises:
            params = parameters_for(ex, SID)
            for var, key in re.findall(r"\b(p(?:_\w+)?)\.([A-Za-z_]\w*)", ex.statement):
                assert var == ex.params_name, (ex.id, var)
                assert key in params, (ex.id, key)


def test_task_says_where_the_numbers_are(shell):
    cells = Cells(shell, _filled_copy("04-rotations"))
    cells.run_all()
    out = cells.run(cells.index('task("rot.opk-matrix")'))
    assert out.strip().endswith(
        "Your numbers are in p_opk: p_opk.omega_gon, p_opk.phi_gon, p_opk.kappa_gon.")


def test_assign_refuses_a_task_cell_with_another_name(master):
    nb = copy.deepcopy(master)
    i = cell_index(nb, 'task("demo.image-scale")')
    nb.cells[i].source = 'p = task("demo.image-scale")'
    with pytest.raises(AssignError, match=r"is assigned to p; write p_scale = "
                                          r"task\('demo.image-scale'\)"):
        make_student_copy(nb, "00-start")
    nb.cells[i].source = 'task("demo.image-scale")'
    with pytest.raises(AssignError, match="is assigned to no name"):
        make_student_copy(nb, "00-start")
    nb.cells[i].source = "pass"
    with pytest.raises(AssignError, match=r"no task cell for \['demo.image-scale'\]"):
        make_student_copy(nb, "00-start")
    nb = copy.deepcopy(master)
    i = cell_index(nb, "answer:demo.rotation-2d")
    nb.cells[i].source = "p_scale = None\n" + nb.cells[i].source
    with pytest.raises(AssignError, match="assigns p_scale, which holds the parameters of "
                                          "demo.image-scale"):
        make_student_copy(nb, "00-start")


def test_assign_refuses_a_cell_that_overwrites_another_answer(master):
    """A later cell reusing an answer's name (chapter 05's helper variable ``radial``, once)
    would overwrite that answer after its check() said ✔, and the grader reads Run All."""
    from photolib.grading.exercises import chapter

    first, second = chapter("00-start")[:2]
    nb = copy.deepcopy(master)
    i = cell_index(nb, f"answer:{second.id}")
    nb.cells[i].source = f"{first.answer} = 0.0\n" + nb.cells[i].source
    with pytest.raises(AssignError, match=f"assigns {first.answer}, the answer of {first.id}"):
        make_student_copy(nb, "00-start")


def test_every_master_task_cell_assigns_the_declared_name():
    for name, exercises in chapters().items():
        master = nbformat.read(ROOT / "solutions" / f"{name}.ipynb", as_version=4)
        sources = [c.source for c in master.cells if c.cell_type == "code"]
        for ex in exercises:
            line = f'{ex.params_name} = task("{ex.id}")'
            assert sum(line in s.splitlines() for s in sources) == 1, (name, line)


# -- cells in any order, any number of times ---------------------------------------------------
def test_going_back_to_task_2_after_run_all_gives_the_same_verdict(ch04):
    """The issue's scenario: Run All, then task 2's answer and check cells again."""
    first = ch04.run_all()
    assert set(first.values()) == {f"✔ {ex.id}: correct" for ex in chapter("04-rotations")}
    out = ch04.run(ch04.index("answer:rot.angles-from-matrix"))
    assert "Traceback" not in out and "Error" not in out, out
    assert ch04.check("rot.angles-from-matrix") == first["rot.angles-from-matrix"]


def test_any_order_any_number_of_times_same_verdicts(ch04):
    first = ch04.run_all()
    rng = random.Random(4)
    order = [i for i in range(len(ch04.cells)) if "student-id" not in
             ch04.cells[i].metadata.get("tags", [])] * 2
    rng.shuffle(order)
    for i in order:
        out = ch04.run(i)
        assert "Traceback" not in out, (ch04.cells[i].source, out)
    assert {ex_id: ch04.check(ex_id) for ex_id in first} == first


# -- answers the notebook did not just compute -------------------------------------------------
def test_an_answer_cell_that_raises_is_not_judged(ch04):
    ch04.run_all()
    out = ch04.run_source("R = pl.rotation_opk(p_opk.omega, 0.0, 0.0)")     # no such parameter
    assert "AttributeError" in out
    assert ch04.check("rot.opk-matrix") == ("✋ rot.opk-matrix: the cell that sets R raised an "
                                            "error (AttributeError); run it again")
    ch04.run_source("R = pl.rotation_opk(p_opk.omega_gon +")                  # syntax error
    assert ch04.check("rot.opk-matrix") == ("✋ rot.opk-matrix: the cell that sets R raised an "
                                            "error (SyntaxError); run it again")
    ch04.run(ch04.index("answer:rot.opk-matrix"))
    assert ch04.check("rot.opk-matrix") == "✔ rot.opk-matrix: correct"


def test_an_answer_computed_from_a_failed_value_is_not_judged(ch04):
    ch04.run_all()
    ch04.run_source("R_given = np.array(p_angles.R_matrix)")                  # raises
    ch04.run_source("angles_deg = np.degrees(pl.opk_from_rotation(R_given))")
    assert ch04.check("rot.angles-from-matrix") == (
        "✋ rot.angles-from-matrix: angles_deg was computed from R_given after the cell that "
        "sets R_given had raised an error (AttributeError); run that cell again, then the "
        "cells that compute angles_deg from it")
    ch04.run(ch04.index("answer:rot.angles-from-matrix"))
    assert ch04.check("rot.angles-from-matrix") == "✔ rot.angles-from-matrix: correct"


def test_a_changed_student_id_asks_for_the_task_and_answer_cells_again(ch04):
    ch04.run_all()
    ch04.run_source('STUDENT_ID = "s1000002"')
    assert ch04.check("rot.opk-matrix") == (
        "✋ rot.opk-matrix: p_opk holds the numbers issued for STUDENT_ID 's1000001': run the "
        "task cell (p_opk = task('rot.opk-matrix')) again, then the cell that sets R")
    ch04.run(ch04.index('task("rot.opk-matrix")'))
    assert ch04.check("rot.opk-matrix") == (
        "✋ rot.opk-matrix: R was computed from the numbers p_opk held before (issued by "
        "task('rot.opk-matrix') for STUDENT_ID 's1000001'); run the cell that sets R again")
    ch04.run(ch04.index("answer:rot.opk-matrix"))
    assert ch04.check("rot.opk-matrix") == "✔ rot.opk-matrix: correct"
    # a function reads p_ray when it is called: its new numbers need no new definition
    ch04.run(ch04.index('task("rot.ray-direction")'))
    assert ch04.check("rot.ray-direction") == "✔ rot.ray-direction: correct"


def test_numbers_issued_while_the_id_was_empty_ask_for_the_task_cell(shell):
    cells = Cells(shell, _filled_copy("04-rotations", sid=""))
    verdicts = cells.run_all()
    assert verdicts["rot.opk-matrix"] == "… rot.opk-matrix: not answered yet"   # R raised
    cells.run_source(f'STUDENT_ID = "{SID}"')
    assert cells.check("rot.opk-matrix") == (
        "✋ rot.opk-matrix: p_opk holds the numbers issued while STUDENT_ID was empty: run the "
        "task cell (p_opk = task('rot.opk-matrix')) again, then the cell that sets R")


def test_the_cell_log_is_registered_once(ch04):
    ch04.run_all()
    ch04.run_source("import photolib.grading.notebook as nb\nnb.cell_log()\nnb.cell_log()")
    ch04.run(ch04.index("from photolib.grading import check, task"))
    logs = [cb for cb in ch04.shell.events.callbacks["post_run_cell"]
            if getattr(getattr(cb, "__self__", None), "photolib_cell_log", None)]
    assert len(logs) == 1


# -- end to end: a real kernel, the copy filled in, cells interleaved --------------------------
@pytest.mark.slow
def test_kernel_runs_the_filled_copy_interleaved_with_the_same_verdicts(tmp_path):
    from jupyter_client.manager import KernelManager
    nb = _filled_copy("04-rotations")
    cells = [c for c in nb.cells if c.cell_type == "code"]
    setup = [c.source for c in cells[:2]]
    triples = []
    for ex in chapter("04-rotations"):
        triples.append([next(c.source for c in cells if f'task("{ex.id}")' in c.source),
                        next(c.source for c in cells if f"answer:{ex.id}" in c.metadata.get("tags", [])),
                        f'check("{ex.id}")'])
    # every task cell first, then every answer cell, each group shuffled: with one shared
    # ``p`` every answer but one would read another task's numbers
    rng = random.Random(10)
    tasks, answers = [t[0] for t in triples], [t[1] for t in triples]
    rng.shuffle(tasks)
    rng.shuffle(answers)
    order = tasks + answers + rng.sample(tasks + answers, len(tasks + answers))
    started = time.monotonic()
    km = KernelManager(kernel_name="python3", transport="ipc", ip=str(tmp_path / "k"))
    km.start_kernel()
    kc = km.client()
    kc.start_channels()
    try:
        kc.wait_for_ready(timeout=60)
        def run(source):
            text = []
            reply = kc.execute_interactive(
                source, timeout=60,
                output_hook=lambda msg: text.append(msg["content"].get("text", "")
                                                    + msg["content"].get("ename", "")))
            assert reply["content"]["status"] == "ok", (source, "".join(text))
            return "".join(text)

        for source in setup + order:
            run(source)
        verdicts = [run(t[2]).strip() for t in triples]
    finally:
        kc.stop_channels()
        km.shutdown_kernel(now=True)
    assert verdicts == [f"✔ {ex.id}: correct" for ex in chapter("04-rotations")]
    assert time.monotonic() - started < 30
