"""The runnable examples are tests: each asserts its own closed-form or accuracy check.

The scripts run once per session (``conftest.example_calls``), shared with the event-sequence
test that compares their results with recorded data.
"""

from pathlib import Path

import pytest

EXAMPLES = sorted((Path(__file__).parent.parent / "examples").glob("*.py"))


@pytest.mark.parametrize("path", EXAMPLES, ids=[p.stem for p in EXAMPLES])
def test_example_runs(path, example_calls):
    calls = example_calls(path.stem)
    assert calls, f"{path.name} made no solve_static call"
    for call in calls:
        res = call["result"]
        assert res.residual[:-1].max(initial=0) < 1e-9
        assert res.violation.max() < 1e-9
