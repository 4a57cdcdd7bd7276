"""Solvers: the condensation to the contact unknowns, the working-scheme solver, the rate
problem (an LCP) at degenerate points, the event engine, and the drivers (static).

Importing the solver provides its field recovery to the result types
(:mod:`stepcontact.solver.recovery`: ``res.recover_fields(model)``)."""

from stepcontact.solver import recovery  # noqa: F401  (provides res.recover_fields)
