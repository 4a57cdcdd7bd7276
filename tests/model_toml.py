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


def block_on_floor(model: str, friction: float = 0.3, layer: str = "") -> str:
    """:func:`concrete_block` resting on a rigid floor line y = 0 through the interface
    "base" (its bottom node set on the obstacle "floor", friction ``friction``, ``layer``: a
    TOML inline table of a compliant layer, or none), with its self-weight as the pattern
    "weight" and a program of that one segment to 1."""
    layer = f"\nlayer = {layer}" if layer else ""
    return concrete_block(model) + f"""
[node_sets.bottom]
body = "block"
y = 0.0

[[obstacles]]
name = "floor"
points = [[-5.0, 0.0], [5.0, 0.0]]

[[interfaces]]
name = "base"
plus = "bottom"
obstacle = "floor"
friction = {friction}{layer}

[patterns.weight]
loads = [{{ type = "gravity" }}]

[[program]]
pattern = "weight"
end = 1.0
"""


def gravity_dam() -> str:
    """The 2D gravity dam of docs/model-file.md without its water: concrete 8 m × 10 m (8 × 10
    cells) on rock 18 m × 5 m (18 × 5), the joint "base" (f = 0.7) between the node sets
    "dam_base" and "rock_top", the rock held at "bed", the upstream face "upstream", and the
    pattern "weight" (the dam's self-weight)."""
    return """
[materials.concrete]
E = 30e9
nu = 0.2
density = 2400
[materials.rock]
E = 10e9
nu = 0.25
[[bodies]]
name = "rock"
corner0 = [-5.0, -5.0]
corner1 = [13.0, 0.0]
nx = 18
ny = 5
material = "rock"
[[bodies]]
name = "dam"
corner0 = [0.0, 0.0]
corner1 = [8.0, 10.0]
nx = 8
ny = 10
material = "concrete"
[node_sets.upstream]
body = "dam"
x = 0.0
[node_sets.dam_base]
body = "dam"
y = 0.0
[node_sets.rock_top]
body = "rock"
y = 0.0
[node_sets.bed]
body = "rock"
y = -5.0
[[supports]]
nodes = "bed"
[[interfaces]]
name = "base"
plus = "dam_base"
minus = "rock_top"
friction = 0.7
[patterns.weight]
loads = [{ type = "gravity", bodies = ["dam"] }]
"""
