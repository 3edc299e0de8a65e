"""Binder's configuration (binder/): the lock as requirements, the course on top.

``test_requirements_are_the_lock`` (in ``make test``): binder/requirements.txt holds exactly the
pins of constraints.txt, so Binder builds what ``make lab`` installs (``make binder`` rewrites it).
``test_binder_environment_runs_a_chapter`` (marker ``binder``, ``make test-binder``): that
environment built as repo2docker builds it -- ``pip install -r binder/requirements.txt``, then
``binder/postBuild`` -- in a fresh virtual environment, and chapter 00 run in it under strict nbval.
"""

from __future__ import annotations

import os
import subprocess
import sys
import time
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
CHAPTER = "notebooks/00-start.ipynb"


def _pins(path: Path) -> list[str]:
    return [line.strip() for line in path.read_text(encoding="utf-8").splitlines()
            if line.strip() and not line.lstrip().startswith("#")]


def test_requirements_are_the_lock():
    lock, binder = _pins(ROOT / "constraints.txt"), _pins(ROOT / "binder" / "requirements.txt")
    assert binder == lock, ("binder/requirements.txt differs from constraints.txt: run make binder; "
                            f"only in the lock {sorted(set(lock) - set(binder))}, only in binder "
                            f"{sorted(set(binder) - set(lock))}")
    assert all("==" in pin for pin in binder)
    post = (ROOT / "binder" / "postBuild").read_text(encoding="utf-8")
    assert "pip install --no-deps -e ." in post and os.access(ROOT / "binder" / "postBuild", os.X_OK)


@pytest.mark.binder
@pytest.mark.slow
@pytest.mark.timeout(900)
def test_binder_environment_runs_a_chapter(tmp_path):
    venv = tmp_path / "binder-venv"
    t0 = time.monotonic()
    subprocess.run([sys.executable, "-m", "venv", str(venv)], check=True, timeout=120)
    py = venv / "bin" / "python"
    env = {**os.environ, "PATH": f"{venv / 'bin'}:{os.environ['PATH']}", "VIRTUAL_ENV": str(venv)}
    env.pop("PYTHONPATH", None)
    pip = subprocess.run([str(py), "-m", "pip", "install", "--quiet", "-r",
                          str(ROOT / "binder" / "requirements.txt")],
                         capture_output=True, text=True, env=env, cwd=ROOT, timeout=900)
    assert pip.returncode == 0, pip.stderr[-3000:]
    post = subprocess.run(["bash", str(ROOT / "binder" / "postBuild")], capture_output=True,
                          text=True, env=env, cwd=ROOT, timeout=300)
    assert post.returncode == 0, post.stderr[-3000:]
    where = subprocess.run([str(py), "-c", "import photolib, sys; print(photolib.__file__)"],
                           capture_output=True, text=True, env=env, check=True).stdout.strip()
    assert Path(where).is_relative_to(ROOT), where
    built = time.monotonic() - t0
    run = subprocess.run([str(py), "-m", "pytest", "-q", "-p", "no:xdist", "--nbval",
                          "--nbval-sanitize-with", "tests/nbval_sanitize.cfg", CHAPTER],
                         capture_output=True, text=True, env=env, cwd=ROOT, timeout=600)
    assert run.returncode == 0, run.stdout[-3000:] + run.stderr[-2000:]
    print(f"binder: environment built in {built:.0f} s, {CHAPTER} under strict nbval in "
          f"{time.monotonic() - t0 - built:.0f} s: {run.stdout.strip().splitlines()[-1]}")
