"""Benchmarks of the course (``make bench`` / ``python -m benchmarks``); not part of the tests."""
