"""Oracles: the model of docs/model.md implemented again, independently of the engine, in plain
Python, so that tests (and the benchmarks) can check the engine against them.

- :mod:`oracle.reference_model`: the whole paper model, step by step (T, S, C of any run);
- :mod:`oracle.geometry`: the paper layout's geometry and the single-robot formula for T.

Nothing here is collected as tests; the tests that use the oracles are ``tests/test_*.py``.
"""
