"""Shared pytest configuration: the ``--update-generated`` option of the codegen sync test and
the ``close_figures`` fixture of the notebook-helper tests."""

from __future__ import annotations

import pytest


def pytest_addoption(parser):
    parser.addoption("--update-generated", action="store_true", default=False,
                     help="rewrite photolib/_generated from photolib/derive instead of diffing")


@pytest.fixture
def close_figures():
    """Close every Matplotlib figure after the test (``pytest.mark.usefixtures``)."""
    yield
    import matplotlib.pyplot as plt

    plt.close("all")
