"""The command-line interface (typer): thin commands that call the library."""

from stepcontact.cli.commands import ProgressHook, app, events_table, result_summary

__all__ = ["ProgressHook", "app", "events_table", "result_summary"]
