"""Ready-made studies and parameter sweeps: the stilling-basin slab (article §7, Figs. 4–5),
its hydraulics, and sweeps of model parameters on a process pool or a dask.distributed
cluster."""
