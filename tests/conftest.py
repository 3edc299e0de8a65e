"""Shared pytest configuration: the ``--update-generated`` option of the codegen sync test."""

from __future__ import annotations


def pytest_addoption(parser):
    parser.addoption("--update-generated", action="store_true", default=False,
                     help="rewrite photolib/_generated from photolib/derive instead of diffing")
