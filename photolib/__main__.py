"""Command line of the course: ``python -m photolib COMMAND ...`` (``USAGE`` is its help)."""

from __future__ import annotations

import importlib
import sys

#: what ``python -m photolib --help`` prints: plain text, no reStructuredText markup
USAGE = """\
usage: python -m photolib COMMAND [options]   (python -m photolib COMMAND --help for its options)

commands:
  errata         print the verdict table of the errata catalogue (--id ID, --json)
  check-formula  check a typed formula against a catalogue record
  assign         generate the student copies in exercises/ from solutions/
  grade          grade submitted notebooks into a gradebook
  collect        gather one chapter's notebooks from the students' folders (JupyterHub)
  return         put each feedback file into its student's folder, owned by the student
  export         the gradebook as Moodle's or Canvas's grade-import CSV
  codegen        regenerate photolib/_generated from photolib/derive"""

#: command -> "module:function" taking argv (list of str) and returning an exit code
COMMANDS = {
    "errata": "photolib.errata.cli:errata_main",
    "check-formula": "photolib.errata.cli:check_formula_main",
    "assign": "photolib.grading.cli:assign_main",
    "grade": "photolib.grading.cli:grade_main",
    "collect": "photolib.grading.classroom:collect_main",
    "return": "photolib.grading.classroom:return_main",
    "export": "photolib.grading.classroom:export_main",
    "codegen": "photolib.codegen:main",
}


def main(argv: list[str] | None = None) -> int:
    """Dispatch ``argv`` (default ``sys.argv[1:]``) to a command; return its exit code."""
    try:
        return _dispatch(list(sys.argv[1:] if argv is None else argv))
    except BrokenPipeError:  # e.g. `python -m photolib errata | head`: not an error
        sys.stderr.close()
        return 0


def _dispatch(argv: list[str]) -> int:
    if not argv or argv[0] in ("-h", "--help"):
        print(USAGE)
        return 0
    name, rest = argv[0], argv[1:]
    if name not in COMMANDS:
        print(f"photolib: unknown command {name!r}; choose one of {', '.join(COMMANDS)}",
              file=sys.stderr)
        return 2
    module, func = COMMANDS[name].split(":")
    return int(getattr(importlib.import_module(module), func)(rest) or 0)


if __name__ == "__main__":
    sys.exit(main())
