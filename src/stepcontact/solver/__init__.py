"""Solvers: the condensation to the contact unknowns, the working-scheme solver, the rate
problem (an LCP) at degenerate points, the event engine, and the drivers (static)."""
