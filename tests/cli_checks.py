"""Shared assertions for command-line tests."""

from __future__ import annotations


def assert_one_line_error(result, fragment: str) -> None:
    """A user error: exit code 2, one line ``error: …`` on stderr containing ``fragment``."""
    assert result.exit_code == 2, result.output
    lines = result.stderr.strip().splitlines()
    assert len(lines) == 1, result.stderr
    assert lines[0].startswith("error: ")
    assert fragment in lines[0], lines[0]
    assert "Traceback" not in result.output
