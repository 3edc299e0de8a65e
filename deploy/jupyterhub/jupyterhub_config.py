"""JupyterHub for a class on one server: the photolib course, one system user per student.

Run as root (LocalProcessSpawner starts each student's server as that student's Unix user):

    make hub-install          # JupyterHub (PyPI) into .venv, configurable-http-proxy (npm) here
    make hub                  # this file, on http://127.0.0.1:8000 (HUB_IP, HUB_PORT)

What it sets up
---------------
* Accounts: every student is a system user (``useradd -m phs1000001``, or LDAP/SSSD users the
  system already knows); the account name is the student id unless ``collect --roster`` maps
  it. Login with their system password (PAM, JupyterHub's default authenticator); only the
  members of the Unix group ``PHOTOLIB_HUB_GROUP`` (default ``photolib-students``) and the
  accounts in ``PHOTOLIB_HUB_ADMINS`` may log in.
* The course is installed once (the repository and its ``.venv``, owned by root, not writable
  by anyone else: checked when the hub starts, which refuses a course or environment that
  group or others may write to). Every student's server runs ``jupyterhub-singleuser`` of that
  environment, so all of them import the same ``photolib``.
* First login: :func:`copy_exercises` (the spawner's ``pre_spawn_hook``) copies the course's
  ``exercises/`` into ``/home/<user>/exercises`` (owned by the student, 0700; the home made
  0700 too) unless it is there already; a later login never overwrites a student's work, and a
  chapter added to the course later is copied in beside it. ``python -m photolib collect``
  reads exactly this layout, ``return`` writes ``/home/<user>/feedback/``.
* Limits: ``mem_limit``/``cpu_limit`` (``PHOTOLIB_HUB_MEM``, default 2G; ``PHOTOLIB_HUB_CPU``,
  default 1) are set on the spawner. LocalProcessSpawner does NOT enforce them: it only passes
  them to the server as ``MEM_LIMIT`` and ``CPU_LIMIT`` (shown by jupyter-resource-usage).
  To enforce them on one server use ``jupyterhub-systemdspawner`` (systemd as PID 1: a
  transient unit per user with ``MemoryMax``/``CPUQuota``) -- set ``PHOTOLIB_HUB_SPAWNER=systemd``
  -- or Kubernetes (Zero to JupyterHub, ``deploy/z2jh``), whose spawner enforces both.

Environment
-----------
``PHOTOLIB_COURSE``     the course repository (default: two folders up from this file)
``PHOTOLIB_HUB_PYTHON`` the course environment's python (default: ``$PHOTOLIB_COURSE/.hub-venv``,
                        made by ``make hub-install`` from the system's python3: the students
                        must be able to execute it, which pyenv's under ``/root`` is not)
``PHOTOLIB_HUB_STATE``  the hub's database, cookie secret and pid files (default ``.hub-state``
                        in the course; made 0700)
``PHOTOLIB_HUB_IP``, ``PHOTOLIB_HUB_PORT``  where the proxy listens (127.0.0.1:8000)
``PHOTOLIB_HUB_AUTH``   ``pam`` (default) or ``dummy``: the test authenticator (every allowed
                        name, one shared password ``PHOTOLIB_HUB_PASSWORD``) -- tests only
``PHOTOLIB_HUB_USERS``  comma-separated accounts allowed to log in (in addition to the group)
``PHOTOLIB_HUB_API_TOKEN``  when set: a service ``photolib-grader`` with this token and the
                        scopes to create users and start and use their servers (the e2e test)
"""

from __future__ import annotations

import grp
import os
import pwd
import shutil
import stat
import sys
from pathlib import Path

c = get_config()  # noqa: F821 - JupyterHub's config loader defines get_config

HERE = Path(__file__).resolve().parent
COURSE = Path(os.environ.get("PHOTOLIB_COURSE", HERE.parent.parent)).resolve()
PYTHON = Path(os.environ.get("PHOTOLIB_HUB_PYTHON", COURSE / ".hub-venv" / "bin" / "python"))
ENV_BIN = PYTHON.parent
STATE = Path(os.environ.get("PHOTOLIB_HUB_STATE", COURSE / ".hub-state")).resolve()
EXERCISES = COURSE / "exercises"
PROXY = HERE / "node_modules" / ".bin" / "configurable-http-proxy"


def _refuse_writable(path: Path) -> None:
    """The course must be read-only for the students: no folder of it (nor of its Python
    environment) may be writable by group or others, or one student could change the code
    every other student's kernel imports."""
    for folder in [path, *(p for p in path.rglob("*") if p.is_dir() and not p.is_symlink())]:
        mode = folder.stat().st_mode
        if mode & (stat.S_IWGRP | stat.S_IWOTH) and not mode & stat.S_ISVTX:
            raise ValueError(f"the course folder {folder} is writable by group or others "
                             f"(mode {stat.filemode(mode)}); the hub serves the course "
                             f"read-only: chmod -R go-w {path}")


def _refuse_unreachable(python: Path) -> None:
    """Every student runs the environment's python: the interpreter it links to and every
    folder above it must be executable by others (a venv made from pyenv's python under
    ``/root``, mode 0700, is not: every server would fail with "Permission denied")."""
    real = python.resolve()
    for part in [real, *real.parents]:
        if not part.stat().st_mode & stat.S_IXOTH:
            raise ValueError(f"{python} is {real}, and {part} is not executable by others "
                             f"(mode {stat.filemode(part.stat().st_mode)}): the students "
                             f"cannot run it; make the hub's environment from a system "
                             f"python (make hub-install HUB_PYTHON=/usr/bin/python3)")


for _needed, _what in ((PYTHON, "the course environment's python (make hub-install)"),
                       (EXERCISES, "the student copies (python -m photolib assign)"),
                       (PROXY, "configurable-http-proxy (make hub-install)")):
    if not _needed.exists():
        raise ValueError(f"{_needed} does not exist: {_what}")
def _refuse_readable_solutions(course: Path) -> None:
    """The masters in ``solutions/`` hold every answer: others may not read them."""
    solutions = course / "solutions"
    if solutions.exists() and solutions.stat().st_mode & (stat.S_IROTH | stat.S_IXOTH):
        raise ValueError(f"{solutions} is readable by others (mode "
                         f"{stat.filemode(solutions.stat().st_mode)}): every student could "
                         f"read the answers; chmod 700 {solutions}")


def _library_path(env: Path) -> str:
    """The base interpreter's ``lib`` when the environment was made from a copied Python
    (deploy/jupyterhub/hub-python: its RUNPATH still names the original place)."""
    cfg = env / "pyvenv.cfg"
    if not cfg.exists():
        return ""
    home = dict(line.split("=", 1) for line in cfg.read_text().splitlines() if "=" in line)
    lib = Path(home.get("home ", home.get("home", "")).strip()).parent / "lib"
    return str(lib) if any(lib.glob("libpython*.so*")) else ""


_refuse_unreachable(PYTHON)
_refuse_readable_solutions(COURSE)
for _tree in (COURSE / "photolib", EXERCISES, ENV_BIN.parent):
    _refuse_writable(_tree)

STATE.mkdir(mode=0o700, parents=True, exist_ok=True)
os.chmod(STATE, 0o700)

# --- hub and proxy: everything on one machine, the proxy the only public port -------------
c.JupyterHub.ip = os.environ.get("PHOTOLIB_HUB_IP", "127.0.0.1")
c.JupyterHub.port = int(os.environ.get("PHOTOLIB_HUB_PORT", "8000"))
c.JupyterHub.hub_ip = "127.0.0.1"
c.JupyterHub.hub_port = int(os.environ.get("PHOTOLIB_HUB_API_PORT", "8081"))
c.ConfigurableHTTPProxy.command = [str(PROXY)]
c.ConfigurableHTTPProxy.api_url = f"http://127.0.0.1:{os.environ.get('PHOTOLIB_HUB_PROXY_API_PORT', '8001')}"
c.ConfigurableHTTPProxy.pid_file = str(STATE / "proxy.pid")
c.JupyterHub.db_url = f"sqlite:///{STATE / 'jupyterhub.sqlite'}"
c.JupyterHub.cookie_secret_file = str(STATE / "jupyterhub_cookie_secret")
c.JupyterHub.pid_file = str(STATE / "jupyterhub.pid")
c.JupyterHub.cleanup_servers = True
c.JupyterHub.default_url = "/hub/home"

# --- who may log in --------------------------------------------------------------------------
GROUP = os.environ.get("PHOTOLIB_HUB_GROUP", "photolib-students")
USERS = {u for u in os.environ.get("PHOTOLIB_HUB_USERS", "").split(",") if u}
ADMINS = {u for u in os.environ.get("PHOTOLIB_HUB_ADMINS", "").split(",") if u}
if os.environ.get("PHOTOLIB_HUB_AUTH", "pam") == "dummy":
    # tests only: any allowed name, one shared password
    c.JupyterHub.authenticator_class = "dummy"
    if not os.environ.get("PHOTOLIB_HUB_PASSWORD"):
        raise ValueError("PHOTOLIB_HUB_AUTH=dummy needs PHOTOLIB_HUB_PASSWORD")
    c.DummyAuthenticator.password = os.environ["PHOTOLIB_HUB_PASSWORD"]
else:
    c.JupyterHub.authenticator_class = "pam"
    c.PAMAuthenticator.open_sessions = False
    try:
        grp.getgrnam(GROUP)
        c.PAMAuthenticator.allowed_groups = {GROUP}
    except KeyError:
        print(f"photolib hub: no group {GROUP!r}; only PHOTOLIB_HUB_USERS may log in",
              file=sys.stderr)
c.Authenticator.allowed_users = USERS
c.Authenticator.admin_users = ADMINS

TOKEN = os.environ.get("PHOTOLIB_HUB_API_TOKEN")
if TOKEN:
    c.JupyterHub.services = [{"name": "photolib-grader", "api_token": TOKEN}]
    c.JupyterHub.load_roles = [{
        "name": "photolib-grader",
        "scopes": ["admin:users", "admin:servers", "access:servers", "read:users"],
        "services": ["photolib-grader"],
    }]

# --- the students' servers -------------------------------------------------------------------
if os.environ.get("PHOTOLIB_HUB_SPAWNER", "local") == "systemd":
    c.JupyterHub.spawner_class = "systemdspawner.SystemdSpawner"   # enforces the limits
    c.SystemdSpawner.isolate_tmp = True
    c.SystemdSpawner.disable_user_sudo = True
else:
    c.JupyterHub.spawner_class = "jupyterhub.spawner.LocalProcessSpawner"
c.Spawner.cmd = [str(ENV_BIN / "jupyterhub-singleuser")]
c.Spawner.notebook_dir = "~"
c.Spawner.default_url = "/lab/tree/exercises"
c.Spawner.environment = {
    "PATH": f"{ENV_BIN}:/usr/local/bin:/usr/bin:/bin",
    # one BLAS thread per student: 60 kernels on a few cores, not 60 x cores threads
    "OMP_NUM_THREADS": "1",
    "OPENBLAS_NUM_THREADS": "1",
    "MPLBACKEND": "module://matplotlib_inline.backend_inline",
}
if _library_path(ENV_BIN.parent):
    c.Spawner.environment["LD_LIBRARY_PATH"] = _library_path(ENV_BIN.parent)
# not enforced by LocalProcessSpawner (see the module docstring); SystemdSpawner and
# KubeSpawner enforce them
c.Spawner.mem_limit = os.environ.get("PHOTOLIB_HUB_MEM", "2G")
c.Spawner.cpu_limit = float(os.environ.get("PHOTOLIB_HUB_CPU", "1"))
c.Spawner.start_timeout = 60
c.Spawner.http_timeout = 60


def _copy_owned(src: Path, dest: Path, uid: int, gid: int) -> None:
    """Copy one file to ``dest`` (not through a link), owned by the student, mode 0600."""
    fd = os.open(dest, os.O_WRONLY | os.O_CREAT | os.O_EXCL | os.O_NOFOLLOW, 0o600)
    try:
        with open(src, "rb") as fin, os.fdopen(fd, "wb", closefd=False) as fout:
            shutil.copyfileobj(fin, fout)
        os.fchown(fd, uid, gid)
    finally:
        os.close(fd)


def copy_exercises(spawner) -> None:
    """pre_spawn_hook: the student's own ``~/exercises`` (0700, owned by the student).

    Copies every ``exercises/*.ipynb`` of the course that the student does not have yet;
    never overwrites one (a student's answers survive every later login). Also makes the home
    0700, so no other student can read the exercises or the feedback that ``return`` puts in
    ``~/feedback``. Raises ``ValueError`` naming the account when it is no system user or
    its ``exercises`` is a symbolic link or not a folder.
    """
    name = spawner.user.name
    try:
        entry = pwd.getpwnam(name)
    except KeyError:
        raise ValueError(f"the account {name!r} is no system user: useradd -m {name}") from None
    home = Path(entry.pw_dir)
    if not home.is_dir():
        raise ValueError(f"the home {home} of {name!r} does not exist: useradd -m {name}")
    os.chmod(home, 0o700)
    target = home / "exercises"
    if target.is_symlink() or (target.exists() and not target.is_dir()):
        raise ValueError(f"{target} is a symbolic link or not a folder; move it away")
    if not target.exists():
        target.mkdir(mode=0o700)
        os.chown(target, entry.pw_uid, entry.pw_gid)
    for notebook in sorted(EXERCISES.glob("*.ipynb")):
        dest = target / notebook.name
        if not os.path.lexists(dest):
            _copy_owned(notebook, dest, entry.pw_uid, entry.pw_gid)
    spawner.log.info("photolib: %s has the exercises in %s", name, target)


c.Spawner.pre_spawn_hook = copy_exercises
