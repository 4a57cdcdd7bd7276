"""Results as plain data with a path axis, and their netCDF result files."""

from stepcontact.results.file import ResultWriter, save_result
from stepcontact.results.result import (
    DynamicResult,
    Event,
    Multipliers,
    StaticResult,
    load_result,
    transition_counts,
)

__all__ = ["DynamicResult", "Event", "Multipliers", "ResultWriter", "StaticResult",
           "load_result", "save_result", "transition_counts"]
