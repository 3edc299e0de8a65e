"""The command-line dispatcher: help, unknown commands, a closed pipe."""

from __future__ import annotations

import subprocess
import sys

from photolib.__main__ import COMMANDS, main


def test_help_lists_every_command(capsys):
    assert main(["--help"]) == 0
    out = capsys.readouterr().out
    for name in COMMANDS:
        assert name in out


def test_unknown_command_is_a_clear_error(capsys):
    assert main(["frobnicate"]) == 2
    assert "unknown command 'frobnicate'" in capsys.readouterr().err


def test_closed_pipe_is_not_a_traceback():
    p = subprocess.Popen([sys.executable, "-m", "photolib", "--help"],
                         stdout=subprocess.PIPE, stderr=subprocess.PIPE)
    p.stdout.close()  # the reader goes away at once, like `| head -0`
    err = p.stderr.read().decode()
    rc = p.wait(timeout=60)
    p.stderr.close()
    assert rc == 0 and err == "", (rc, err)
