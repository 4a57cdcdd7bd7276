"""Results as plain data with a path axis, and their netCDF result files."""

from stepcontact.results.file import ResultWriter, load_result, save_result
from stepcontact.results.result import Event, Multipliers, StaticResult, transition_counts

__all__ = ["Event", "Multipliers", "ResultWriter", "StaticResult", "load_result", "save_result",
           "transition_counts"]
