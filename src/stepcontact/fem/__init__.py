"""Finite elements: scikit-fem glue for continua, frame elements, the DOF map and the assembly
of the stiffness matrix, load vectors and the contact operator B (model → matrices)."""

from stepcontact.fem.assembly import DofMap, LoadVectors, System, assemble

__all__ = ["DofMap", "LoadVectors", "System", "assemble"]
