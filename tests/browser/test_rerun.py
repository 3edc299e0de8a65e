"""Issue 14, point 1, in a real browser: Run All on the rotations and bundle-adjustment
exercises, then go back and run task 2's cells (its parameters, its answer, its check) again,
and task 1's check after them: every check prints the verdict it printed the first time and
no cell raises.

Both the solution master (every verdict ✔) and the untouched student copy (every verdict
"not answered yet", with a STUDENT_ID set) are run; before the per-task parameter names, a
later task's ``p`` shadowed task 2's and its answer cell raised ``AttributeError``.
"""

from __future__ import annotations


import pytest

from .test_student_view import _run_all, _with_student_id

pytestmark = [pytest.mark.browser, pytest.mark.slow, pytest.mark.timeout(600)]

#: the texts of the code cells' outputs, per code cell, and the errors they hold
_OUTPUTS = """() => {
    const nb = window.jupyterapp.shell.currentWidget;
    return nb.content.widgets.map((c, i) => ({
        index: i, type: c.model.type, count: c.model.type === 'code' ? c.model.executionCount : null,
        source: c.model.sharedModel.getSource(),
        text: c.model.type === 'code' ? c.model.outputs.toJSON()
            .filter(o => o.output_type === 'stream').map(o => [].concat(o.text).join('')).join('') : '',
        errors: c.model.type === 'code' ? c.model.outputs.toJSON()
            .filter(o => o.output_type === 'error').map(o => o.ename + ': ' + o.evalue) : []}));
}"""

_RUN_CELL = """(i) => {
    const panel = window.jupyterapp.shell.currentWidget;
    panel.content.activeCellIndex = i;
    window.jupyterapp.commands.execute('notebook:run-cell');
    return true;
}"""


def _task_cells(cells, k):
    """Indices of the task() cell, the answer cell and the check() cell of task ``k`` (1-based)."""
    tasks = [c["index"] for c in cells if c["type"] == "code" and "= task(" in c["source"]]
    start = tasks[k - 1]
    checks = [c["index"] for c in cells
              if c["index"] > start and c["type"] == "code" and c["source"].startswith("check(")]
    return list(range(start, checks[0] + 1))


def _run_cell(page, index):
    before = page.evaluate(_OUTPUTS)[index]["count"]
    page.evaluate(_RUN_CELL, index)
    page.wait_for_function(
        "([i, n]) => { const nb = window.jupyterapp.shell.currentWidget;"
        " const c = nb.content.widgets[i].model;"
        " return c.executionCount !== null && c.executionCount !== n"
        " && nb.sessionContext.session.kernel.status === 'idle'; }",
        arg=[index, before], timeout=60_000)


@pytest.mark.parametrize("folder", ["solutions", "exercises"])
@pytest.mark.parametrize("exercise", ["04-rotations", "10-bundle-adjustment"])
def test_rerunning_task_2_after_run_all_keeps_every_verdict(lab_url, lab_root, lab_log, page,
                                                            folder, exercise):
    if folder == "exercises":
        _with_student_id(lab_root, exercise)
    page.goto(f"{lab_url}/lab/tree/{folder}/{exercise}.ipynb?reset")
    _run_all(page, lab_log)
    first = page.evaluate(_OUTPUTS)
    checks = {c["index"]: c["text"] for c in first if c["source"].startswith("check(")}
    assert len(checks) >= 3, f"{folder}/{exercise}: found only {len(checks)} check cells"
    expected = "✔" if folder == "solutions" else "not answered yet"
    assert all(expected in t for t in checks.values()), (folder, exercise, checks)
    assert not [c for c in first if c["errors"]], f"Run All raised: {first}"

    again = _task_cells(first, 2) + [_task_cells(first, 1)[-1]]
    for index in again:
        _run_cell(page, index)
    second = page.evaluate(_OUTPUTS)
    for index in again:
        cell = second[index]
        assert not cell["errors"], f"{folder}/{exercise}: cell {index} raised {cell['errors']}"
        if index in checks:
            assert cell["text"] == checks[index], (
                f"{folder}/{exercise}: cell {index} said {checks[index]!r} after Run All, "
                f"{cell['text']!r} when run again")
