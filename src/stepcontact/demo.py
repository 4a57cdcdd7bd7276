"""Demo models shipped with the package (TOML files in ``stepcontact/data``).

Both are a concrete block (2 m × 1 m, E = 30 GPa, ν = 0.2, 2400 kg/m³) resting on an elastic
foundation block (6 m × 2 m, E = 10 GPa, ν = 0.25, fixed at its base) through a rigid joint
with Coulomb friction f = 0.6; the meshes of the two faces of the joint do not match.  About
400 degrees of freedom and 7 CFEs (mortar, on the coarser foundation), so a run takes seconds.

* :func:`demo_model` (``demo.toml``): self-weight, then a pressure on the block's left face
  growing until the block slides off (equilibrium lost near λ ≈ 2.83 of 5).
* :func:`demo_uplift_model` (``demo_uplift.toml``): self-weight, then uplift pressure in the
  left half of the joint growing until the block tips about its right edge (λ ≈ 3.1 of 5).

Example
-------
>>> from stepcontact.demo import demo_model
>>> model = demo_model()
>>> [p.name for p in model.patterns]
['weight', 'push']
"""

from __future__ import annotations

from importlib.resources import as_file, files

from stepcontact.io.modelfile import load_model
from stepcontact.model import Model

DEMO_FILES: dict[str, str] = {"slide": "demo.toml", "uplift": "demo_uplift.toml"}


def demo_text(variant: str = "slide") -> str:
    """The TOML text of a demo model (``"slide"`` or ``"uplift"``)."""
    return (files("stepcontact") / "data" / DEMO_FILES[variant]).read_text(encoding="utf-8")


def _load(name: str) -> Model:
    with as_file(files("stepcontact") / "data" / name) as path:
        return load_model(path)


def demo_model() -> Model:
    """Block on a foundation pushed sideways until it slides (``data/demo.toml``)."""
    return _load(DEMO_FILES["slide"])


def demo_uplift_model() -> Model:
    """Block on a foundation lifted by uplift in the joint until it tips
    (``data/demo_uplift.toml``)."""
    return _load(DEMO_FILES["uplift"])


__all__ = ["DEMO_FILES", "demo_model", "demo_text", "demo_uplift_model"]
