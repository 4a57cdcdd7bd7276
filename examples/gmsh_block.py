"""A block on a foundation meshed by gmsh, with non-matching meshes along the joint.

The mesh ``data/gmsh_block.msh`` was made from ``data/gmsh_block.geo``; its physical surfaces
are the bodies and its physical curves the supports, the loaded face and the two faces of the
joint.  The model is read from ``data/gmsh_block.toml`` and also built in Python from the same
mesh; both must slide when the push reaches H = f·W, W being the block's weight computed from
the areas of its cells (f = 0.5, 2400 kg/m³, g = 9.81 m/s²).
Run:  python examples/gmsh_block.py
"""

from pathlib import Path

import numpy as np

import stepcontact as sc
from stepcontact.io.meshfile import read_msh
from stepcontact.io.modelfile import load_model, validate_model_file

DATA = Path(__file__).resolve().parent / "data"

# 1. the model file: validate, load, solve
problems = validate_model_file(DATA / "gmsh_block.toml")
assert problems == [], problems
model = load_model(DATA / "gmsh_block.toml")
res = sc.solve_static(model)
print(res.summary())

# 2. the same model in Python, from the mesh file
mf = read_msh(DATA / "gmsh_block.msh")
print("physical groups:", mf.describe())
rock = sc.Material(E=10e9, nu=0.25, density=2600)
concrete = sc.Material(E=30e9, nu=0.2, density=2400)
found, block = mf.body("foundation", rock), mf.body("block", concrete)
m = sc.Model(bodies=[found, block], plane="strain", thickness=1.0, name="gmsh-block-py").add(
    sc.Support("bed", mf.node_set("base"), "xy"),
    sc.Interface("joint", plus=mf.node_set("block_bottom"), minus=mf.node_set("foundation_top"),
                 friction=0.5),
    sc.LoadPattern("weight", [sc.BodyForce(bodies=("block",))]),
    sc.LoadPattern("push", [sc.EdgeLoad(mf.node_set("push_face"), normal=1.0)]),
    sc.Segment("weight", 1.0),
    sc.Segment("push", 1e5),
)
res_py = sc.solve_static(m)

# 3. the check: sliding at H = f·W, W from the cell areas (triangles) of the block
xy = block.points[block.cells[:, :3]]
d1, d2 = xy[:, 1] - xy[:, 0], xy[:, 2] - xy[:, 0]
area = 0.5 * np.abs(d1[:, 0] * d2[:, 1] - d1[:, 1] * d2[:, 0]).sum()  # m²
W = area * 1.0 * 2400 * 9.81  # N per metre run
x_plus = mf.points[mf.node_ids("block_bottom"), 0]
x_minus = mf.points[mf.node_ids("foundation_top"), 0]
assert not np.isin(x_plus, x_minus).all()  # the meshes do not match along the joint
print(f"block area {area:.12g} m², W = {W:.6f} N; joint: {len(x_plus)} block nodes (CFEs), "
      f"{len(x_minus)} foundation nodes")
for r in (res, res_py):
    lost = r.multipliers[-1].equilibrium_lost
    print(f"{r.status.value}: sliding at H = {lost:.6f} N, f·W = {0.5 * W:.6f} N, "
          f"relative error {lost / (0.5 * W) - 1:.1e}")
    assert r.status == sc.Status.EQUILIBRIUM_LOST
    assert abs(lost / (0.5 * W) - 1) < 1e-6
