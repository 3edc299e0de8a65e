"""``make lab`` serves JupyterLab: HTTP 200 on ``/lab`` and on the start page. ``make test-fast``
deselects the tests marked ``slow`` and ``browser``; ``make test`` still runs both."""

from __future__ import annotations

import os
import re
import shlex
import shutil
import signal
import socket
import subprocess
import sys
import time
import tomllib
import urllib.request
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]


def _free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def _status(url: str) -> int | None:
    try:
        with urllib.request.urlopen(url, timeout=5) as response:
            return response.status
    except OSError:
        return None


@pytest.mark.slow
@pytest.mark.timeout(120)
@pytest.mark.skipif(shutil.which("make") is None, reason="make is not installed")
def test_make_lab_serves_jupyterlab(tmp_path):
    venv = Path(sys.prefix)
    if not (venv / "bin" / "python").exists() or not (ROOT / "Makefile").exists():
        pytest.skip("not running from the project's virtual environment")
    # the same target a student runs, in this test's environment. `-o` marks the install
    # stamp as up to date: this test checks serving, and a reinstall from ROOT into the venv
    # the tests run in would repoint its editable install when ROOT is another checkout
    port = _free_port()
    log = tmp_path / "lab.log"
    env = {**os.environ, "JUPYTER_RUNTIME_DIR": str(tmp_path / "runtime"),
           "JUPYTER_CONFIG_DIR": str(tmp_path / "config")}
    with open(log, "w") as out:
        proc = subprocess.Popen(["make", "-s", "-C", str(ROOT), "-o", f"{venv}/.course-installed",
                                 "lab", f"PORT={port}", f"VENV={venv}"],
                                stdout=out, stderr=subprocess.STDOUT,
                                env=env, start_new_session=True)
    try:
        deadline = time.monotonic() + 90
        while _status(f"http://127.0.0.1:{port}/lab") != 200:
            if proc.poll() is not None or time.monotonic() > deadline:
                pytest.fail(f"make lab did not answer on /lab:\n{log.read_text()[-3000:]}")
            time.sleep(0.5)
        assert _status(f"http://127.0.0.1:{port}/lab/tree/notebooks/00-start.ipynb") == 200
        assert _status(f"http://127.0.0.1:{port}/api/contents/notebooks/00-start.ipynb") == 200
    finally:
        _stop(proc)


def _stop(proc: subprocess.Popen) -> None:
    """End make and the JupyterLab server it started (one process group)."""
    for sig in (signal.SIGTERM, signal.SIGKILL):
        try:
            os.killpg(proc.pid, sig)
        except ProcessLookupError:
            return
        try:
            proc.wait(timeout=20)
            return
        except subprocess.TimeoutExpired:
            continue


# -- the lock ------------------------------------------------------------------------------------

def _locked() -> dict[str, str]:
    """``{normalised name: version}`` of constraints.txt."""
    pins = {}
    for line in (ROOT / "constraints.txt").read_text(encoding="utf-8").splitlines():
        line = line.split("#", 1)[0].strip()
        if line:
            name, sep, version = line.partition("==")
            assert sep and version, f"constraints.txt: {line!r} is not an exact pin name==version"
            pins[re.sub(r"[-_.]+", "-", name).lower()] = version
    return pins


def _declared() -> set[str]:
    """Normalised names of every requirement in pyproject.toml (dependencies and extras)."""
    project = tomllib.loads((ROOT / "pyproject.toml").read_text(encoding="utf-8"))["project"]
    reqs = list(project["dependencies"])
    for extra in project["optional-dependencies"].values():
        reqs += extra
    names = {re.sub(r"[-_.]+", "-", re.match(r"[A-Za-z0-9._-]+", r).group()).lower() for r in reqs}
    return names - {"photolib"}


def test_lock_pins_every_declared_requirement():
    missing = _declared() - set(_locked())
    assert not missing, f"constraints.txt has no pin for {sorted(missing)}: run make lock"


def test_installed_versions_are_the_locked_ones():
    """The environment the tests (and the committed outputs) run in is the locked one."""
    from importlib import metadata
    differ = []
    for dist in metadata.distributions():
        name = re.sub(r"[-_.]+", "-", dist.metadata["Name"]).lower()
        locked = _locked().get(name)
        if locked is not None and dist.version != locked:
            differ.append(f"{name} {dist.version} (locked {locked})")
    assert not differ, ("installed versions differ from constraints.txt: " + ", ".join(differ)
                        + "; reinstall with make test, or make lock to refresh the lock")


def test_make_installs_from_the_lock():
    make = (ROOT / "Makefile").read_text(encoding="utf-8")
    installs = [line for line in make.splitlines() if "pip install" in line and "-e '." in line]
    # the course, the test extras, the website's extra and the hub's environment
    assert len(installs) == 4, installs
    assert all("-c $(LOCK)" in line for line in installs), installs
    assert re.search(r"^LOCK\s*:=\s*constraints\.txt$", make, re.M)
    assert re.search(r"^\$\(VENV\)/\.test-installed: pyproject\.toml \$\(LOCK\)", make, re.M)
    assert re.search(r"^lock:", make, re.M) and "pip freeze --exclude photolib" in make


# -- the package: version, data files, the grader's requirements ---------------------------------

def _project() -> dict:
    return tomllib.loads((ROOT / "pyproject.toml").read_text(encoding="utf-8"))


def test_version_is_written_once_and_setuptools_reads_it():
    """pyproject.toml takes the version from photolib.__version__; no second copy to drift."""
    from setuptools.config.expand import read_attr

    import photolib

    project = _project()
    assert "version" not in project["project"] and "version" in project["project"]["dynamic"]
    attr = project["tool"]["setuptools"]["dynamic"]["version"]["attr"]
    # what setuptools writes into the wheel's metadata: the attribute read from the source
    assert read_attr(attr, root_dir=ROOT) == photolib.__version__
    assert re.fullmatch(r"\d+\.\d+\.\d+", photolib.__version__), photolib.__version__
    init = (ROOT / "photolib" / "__init__.py").read_text(encoding="utf-8")
    assert len(re.findall(r"^__version__ = ", init, re.M)) == 1


def test_package_data_globs_match_real_files():
    """Each package-data entry ships something (a glob that matches nothing hid a missing
    py.typed and grading JSON files that never existed); py.typed marks the package typed
    (PEP 561) and is empty."""
    globs = _project()["tool"]["setuptools"]["package-data"]["photolib"]
    for pattern in globs:
        assert list((ROOT / "photolib").glob(pattern)), f"package-data {pattern!r} matches nothing"
    assert "py.typed" in globs and (ROOT / "photolib" / "py.typed").read_bytes() == b""


def _top_level_imports(path: Path) -> set[str]:
    import ast

    names = set()
    for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
        if isinstance(node, ast.Import):
            names |= {a.name.split(".")[0] for a in node.names}
        elif isinstance(node, ast.ImportFrom) and node.module and not node.level:
            names.add(node.module.split(".")[0])
    return names


#: import name -> distribution name where they differ
_DISTRIBUTION = {"zmq": "pyzmq"}


def test_the_graders_imports_are_declared_in_its_extra():
    """Every third-party module that photolib.grading imports is in the ``grading`` extra
    (or a core dependency), and the course installs that extra."""
    project = _project()["project"]
    name = lambda req: re.sub(r"[-_.]+", "-", re.match(r"[A-Za-z0-9._-]+", req).group()).lower()
    extra = {name(r) for r in project["optional-dependencies"]["grading"]}
    core = {name(r) for r in project["dependencies"]}
    imported = set()
    for path in (ROOT / "photolib" / "grading").rglob("*.py"):
        imported |= _top_level_imports(path)
    third_party = {m for m in imported - set(sys.stdlib_module_names) - {"photolib", "__future__"}}
    assert {"zmq", "jupyter_client", "nbformat"} <= third_party, third_party
    missing = {m for m in third_party
               if name(_DISTRIBUTION.get(m, m)) not in extra | core}
    assert not missing, f"photolib.grading imports {sorted(missing)}, not in the grading extra"
    assert "photolib[grading]" in project["optional-dependencies"]["course"]


#: pytest options of the Makefile that take a value (the value is not a path to test)
_VALUE_OPTIONS = {"-n", "-m", "-k", "-p", "--dist", "--nbval-sanitize-with", "--durations"}


def _pytest_runs(target: str) -> list[tuple[str | None, list[str]]]:
    """(``-m`` expression or None, paths) of each pytest run that ``make <target>`` starts, read
    from ``make -n`` (the commands, not run), so that variables and line continuations count."""
    venv = Path(sys.prefix)
    if not (venv / "bin" / "python").exists() or not (ROOT / "Makefile").exists():
        pytest.skip("not running from the project's virtual environment")
    script = subprocess.run(["make", "-n", "-s", "-C", str(ROOT), "-o", f"{venv}/.test-installed",
                             target, f"VENV={venv}"],
                            capture_output=True, text=True, check=True, timeout=60).stdout
    runs = []
    for line in script.replace("\\\n", " ").splitlines():
        words = shlex.split(line)
        for start in (i + 2 for i in range(len(words) - 1) if words[i:i + 2] == ["-m", "pytest"]):
            expr, paths, i = None, [], start
            while i < len(words) and words[i] not in {";", "&&", "||", "|"}:
                word = words[i].rstrip(";")
                if word in _VALUE_OPTIONS:
                    if word == "-m":
                        expr = words[i + 1].rstrip(";")
                    i += 1
                elif not word.startswith("-"):
                    paths.append(word)
                if words[i].endswith(";"):
                    break
                i += 1
            runs.append((expr, paths))
    return runs


def _selects(expr: str | None, markers: set[str]) -> bool:
    """Whether ``pytest -m expr`` runs a test carrying ``markers``."""
    from _pytest.mark.expression import Expression  # pytest's own parser of -m

    return expr is None or Expression.compile(expr).evaluate(lambda name, **kw: name in markers)


@pytest.mark.skipif(shutil.which("make") is None, reason="make is not installed")
def test_make_test_fast_deselects_slow_and_browser_and_make_test_runs_them():
    fast = _pytest_runs("test-fast")
    assert [paths for _, paths in fast] == [["tests", "photolib"]], fast
    expr = fast[0][0]
    assert _selects(expr, set())
    for markers in ({"slow"}, {"browser"}, {"slow", "browser"}):
        assert not _selects(expr, markers), (expr, markers)
    full = [(expr, paths) for expr, paths in _pytest_runs("test") if "tests" in paths]
    for markers in (set(), {"slow"}, {"browser"}, {"slow", "browser"}):
        assert any(_selects(expr, markers) for expr, _ in full), (full, markers)
    # the doctests of photolib run in both
    assert any("photolib" in paths for _, paths in full)
