"""Shared fixtures: every example script is run once per test session."""

from __future__ import annotations

import pytest

from test_event_sequences import EXAMPLES_DIR, run_example


@pytest.fixture(scope="session")
def example_calls(tmp_path_factory):
    """Each example script run once per session (on first use, as ``__main__``, so its own
    closed-form assertions run): its ``sc.solve_static`` calls in order (kwargs, result)."""
    cache: dict[str, list[dict]] = {}

    def get(stem: str) -> list[dict]:
        if stem not in cache:
            cache[stem] = run_example(EXAMPLES_DIR / f"{stem}.py", tmp_path_factory.mktemp(stem))
        return cache[stem]

    return get
