"""deploy/jupyterhub/jupyterhub_config.py without a hub: its refusals and its first-login copy.

Runs in ``make test`` (no root, no JupyterHub process): the config file is executed as
JupyterHub's loader does (``get_config`` in its namespace) against a course made in tmp_path.
"""

from __future__ import annotations

import os
import pwd
import shutil
import stat
import types
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
CONFIG = ROOT / "deploy" / "jupyterhub" / "jupyterhub_config.py"
#: an interpreter every user may run (the checks resolve links; pyenv's under /root is not one)
_OPEN = [p for p in ("/usr/bin/python3", "/usr/local/bin/python3")
         if Path(p).exists() and all(d.stat().st_mode & stat.S_IXOTH
                                     for d in [Path(p).resolve(), *Path(p).resolve().parents])]


def _course(tmp_path: Path, python: str) -> Path:
    course = tmp_path / "course"
    (course / "photolib").mkdir(parents=True)
    (course / "exercises").mkdir()
    (course / "exercises" / "04-rotations.ipynb").write_text('{"cells": []}')
    (course / "solutions").mkdir(mode=0o700)
    os.chmod(course / "solutions", 0o700)
    (course / ".hub-venv" / "bin").mkdir(parents=True)
    os.symlink(python, course / ".hub-venv" / "bin" / "python")
    hub = course / "deploy" / "jupyterhub"
    (hub / "node_modules" / ".bin").mkdir(parents=True)
    (hub / "node_modules" / ".bin" / "configurable-http-proxy").write_text("")
    shutil.copy(CONFIG, hub / "jupyterhub_config.py")
    for d in [course, *course.rglob("*")]:
        if d.is_dir() and not d.is_symlink() and d.name != "solutions":
            os.chmod(d, 0o755)
    os.chmod(tmp_path, 0o755)
    return course


def _load(course: Path, monkeypatch, **env):
    from traitlets.config import Config

    monkeypatch.setenv("PHOTOLIB_HUB_STATE", str(course / "state"))
    for k, v in env.items():
        monkeypatch.setenv(k, v)
    cfg = Config()
    ns = {"get_config": lambda: cfg, "__file__": str(course / "deploy/jupyterhub/jupyterhub_config.py")}
    exec(compile((course / "deploy/jupyterhub/jupyterhub_config.py").read_text(),
                 "jupyterhub_config.py", "exec"), ns)
    return cfg, ns


needs_open_python = pytest.mark.skipif(not _OPEN, reason="no Python that every user may run")


@needs_open_python
def test_the_config_sets_up_a_read_only_course(tmp_path, monkeypatch):
    course = _course(tmp_path, _OPEN[0])
    cfg, _ = _load(course, monkeypatch, PHOTOLIB_HUB_AUTH="dummy", PHOTOLIB_HUB_PASSWORD="pw",
                   PHOTOLIB_HUB_USERS="phs1,phs2", PHOTOLIB_HUB_API_TOKEN="t" * 32)
    assert cfg.JupyterHub.ip == "127.0.0.1"
    assert cfg.JupyterHub.spawner_class == "jupyterhub.spawner.LocalProcessSpawner"
    assert cfg.Spawner.cmd == [str(course / ".hub-venv/bin/jupyterhub-singleuser")]
    assert cfg.Authenticator.allowed_users == {"phs1", "phs2"}
    assert cfg.DummyAuthenticator.password == "pw"
    assert cfg.Spawner.mem_limit == "2G" and cfg.Spawner.cpu_limit == 1.0
    assert stat.S_IMODE((course / "state").stat().st_mode) == 0o700
    scopes = cfg.JupyterHub.load_roles[0]["scopes"]
    assert "admin:servers" in scopes and "access:servers" in scopes


@pytest.mark.parametrize("case", ["writable", "solutions", "dummy-without-password"])
@needs_open_python
def test_the_config_refuses_an_unsafe_course(tmp_path, monkeypatch, case):
    course = _course(tmp_path, _OPEN[0])
    env = {"PHOTOLIB_HUB_AUTH": "dummy", "PHOTOLIB_HUB_PASSWORD": "pw"}
    if case == "writable":
        os.chmod(course / "photolib", 0o777)
        match = "photolib is writable by group or others"
    elif case == "solutions":
        os.chmod(course / "solutions", 0o755)
        match = "solutions is readable by others"
    else:
        env["PHOTOLIB_HUB_PASSWORD"] = ""
        match = "needs PHOTOLIB_HUB_PASSWORD"
    with pytest.raises(ValueError, match=match):
        _load(course, monkeypatch, **env)


def test_the_config_refuses_a_python_students_cannot_run(tmp_path, monkeypatch):
    closed = tmp_path / "closed"              # like pyenv's under /root: a folder of mode 0700
    (closed / "bin").mkdir(parents=True)
    (closed / "bin" / "python3").write_text("")
    os.chmod(closed / "bin" / "python3", 0o755)
    os.chmod(closed, 0o700)
    course = _course(tmp_path, str(closed / "bin" / "python3"))
    with pytest.raises(ValueError, match=f"{closed} is not executable by others"):
        _load(course, monkeypatch, PHOTOLIB_HUB_AUTH="dummy", PHOTOLIB_HUB_PASSWORD="pw")


@needs_open_python
def test_first_login_copies_the_exercises_and_never_overwrites(tmp_path, monkeypatch):
    course = _course(tmp_path, _OPEN[0])
    (course / "exercises" / "05-interior-orientation.ipynb").write_text('{"cells": [1]}')
    cfg, ns = _load(course, monkeypatch, PHOTOLIB_HUB_AUTH="dummy", PHOTOLIB_HUB_PASSWORD="pw")
    hook = cfg.Spawner.pre_spawn_hook
    home = tmp_path / "home" / "phs1"
    home.mkdir(parents=True, mode=0o755)
    me = pwd.getpwuid(os.getuid())
    fake = types.SimpleNamespace(pw_dir=str(home), pw_uid=me.pw_uid, pw_gid=me.pw_gid)
    real = pwd.getpwnam
    monkeypatch.setattr(ns["pwd"], "getpwnam", lambda name: fake if name == "phs1" else real(name))
    spawner = types.SimpleNamespace(user=types.SimpleNamespace(name="phs1"),
                                    log=types.SimpleNamespace(info=lambda *a: None))
    hook(spawner)
    copy = home / "exercises" / "04-rotations.ipynb"
    assert copy.read_text() == '{"cells": []}'
    assert stat.S_IMODE(copy.stat().st_mode) == 0o600
    assert stat.S_IMODE((home / "exercises").stat().st_mode) == 0o700
    assert stat.S_IMODE(home.stat().st_mode) == 0o700
    copy.write_text("my answers")
    (course / "exercises" / "06-collinearity.ipynb").write_text('{"cells": [2]}')
    hook(spawner)                                  # the next login: nothing overwritten
    assert copy.read_text() == "my answers"
    assert (home / "exercises" / "06-collinearity.ipynb").exists()
    # a link in place of the folder is refused, naming it
    shutil.rmtree(home / "exercises")
    os.symlink(tmp_path, home / "exercises")
    with pytest.raises(ValueError, match="symbolic link"):
        hook(spawner)
    spawner.user.name = "nosuchaccount-xyz"
    with pytest.raises(ValueError, match="nosuchaccount-xyz"):
        hook(spawner)
