"""Errata catalogue: every checkable formula and example of the four course sources.

Each :class:`~photolib.errata._record.Record` holds the printed versions of one item, the
derivation from :mod:`photolib.derive` it is compared with, and a verdict per printed
version that is recomputed from evidence (never from a printed corrected version).

Examples
--------
>>> rec = get("luhmann:2.86")
>>> sorted(rec.versions)
['corrected', 'old']
>>> rec.verdicts["corrected"]
'right'
"""

from __future__ import annotations

import importlib

from photolib.errata._record import Evidence, Record, VersionSpec

__all__ = ["MODULES", "Evidence", "Record", "VersionSpec", "catalogue", "get"]

#: catalogue modules, in the order of the sources
MODULES = ("luhmann_ch2", "luhmann_ch3", "luhmann_ch4", "luhmann_dlt", "luhmann_ch5",
           "de_summary", "de_summary_optics", "de_summary_sensors", "hu_wiki", "pl_notes")

_CATALOGUE: list | None = None


def catalogue() -> list:
    """All records (built once per process; verdicts are computed on first access)."""
    global _CATALOGUE
    if _CATALOGUE is None:
        out = []
        for name in MODULES:
            out.extend(importlib.import_module(f"photolib.errata.{name}").records())
        ids = [r.id for r in out]
        dup = {i for i in ids if ids.count(i) > 1}
        if dup:
            raise RuntimeError(f"duplicate record ids: {sorted(dup)}")
        _CATALOGUE = out
    return _CATALOGUE


def get(record_id: str) -> Record:
    """The record with this id; ``KeyError`` names the close matches."""
    for r in catalogue():
        if r.id == record_id:
            return r
    near = [r.id for r in catalogue() if record_id.split(":")[-1] in r.id]
    raise KeyError(f"no errata record {record_id!r}" + (f"; did you mean {near}?" if near else ""))
