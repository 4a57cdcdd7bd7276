"""Pieces of model files (TOML) shared by tests: a concrete block meshed as a rectangle."""

from __future__ import annotations


def concrete_block(model: str, *, material: str = "c", corner1=(1.0, 0.5), nx: int = 2,
                   ny: int = 1) -> str:
    """The [model], one concrete [materials] entry (E = 30 GPa, ν = 0.2, ρ = 2400 kg/m³) and a
    rectangle body "block" from (0, 0) to ``corner1`` (m) meshed nx × ny."""
    return f"""
[model]
name = "{model}"

[materials.{material}]
E = 30e9
nu = 0.2
density = 2400

[[bodies]]
name = "block"
kind = "rectangle"
corner0 = [0.0, 0.0]
corner1 = [{float(corner1[0])}, {float(corner1[1])}]
nx = {nx}
ny = {ny}
material = "{material}"
"""
