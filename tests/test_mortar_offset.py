"""Mortar CFEs between 3D faces whose meshes are offset by half a cell (issue 28 §2): pressed and
pushed, the upper box slides at the faceted cone's global limit.

Reference: the sliding load of a block pressed by P and its weight W on a rough face, pushed
along θ: f (P + W) cos(π/k) / cos(θ − θ_f) (``faceted_reference.slip_limit``, pure NumPy), to
1e-9 relative; every state in equilibrium with the contact conditions to 1e-9.  The upper box
either stands inside the lower one's face (its nodes at the lower cells' centres) or overhangs it
by half a cell on two sides (facets faced only in part).
"""

from __future__ import annotations

import math

import numpy as np
import pytest

import faceted_reference as fr
import stepcontact as sc

RHO, G, F, K = 2400.0, 9.81, 0.5, 8
MAT = sc.Material(30e9, 0.25, RHO)


def offset_boxes(variant: str, n: int, element: str, theta: float, P: float) -> sc.Model:
    """Upper box 1 × 1 × 0.5 m, n × n × 1 cells; lower box 0.5 m deep, cells of the same size
    offset by half a cell; mortar CFEs f = 0.5 on the 8-gon; the upper box's weight and a total
    force P (N) pressing its top, then 1 N per unit λ along θ on its top."""
    h = 1.0 / n
    up = sc.box("upper", (0, 0, 0), (1, 1, 0.5), (n, n, 1), MAT, element)
    if variant == "inside":
        lo = sc.box("lower", (-h / 2, -h / 2, -0.5), (1 + h / 2, 1 + h / 2, 0), (n + 1, n + 1, 1),
                    MAT, element)
    else:  # overhanging by half a cell in x and y
        lo = sc.box("lower", (h / 2, h / 2, -0.5), (1 + h / 2, 1 + h / 2, 0), (n, n, 1), MAT,
                    element)
    m = sc.Model(bodies=(lo, up))
    top = m.select("upper", boundary="top")
    return m.add(
        sc.Support("bed", m.select("lower", boundary="bottom"), "xyz"),
        sc.Interface("joint", m.select("upper", boundary="bottom"),
                     m.select("lower", boundary="top"), friction=F, facets=K, cfe="mortar"),
        sc.LoadPattern("press", [sc.BodyForce(bodies=("upper",)), sc.EdgeForce(top, fz=-P)]),
        sc.LoadPattern("push", [sc.EdgeForce(top, fx=math.cos(theta), fy=math.sin(theta))]),
        sc.Segment("press", 1.0), sc.Segment("push", 1e6))


@pytest.mark.parametrize("variant", ["inside", "overhang"])
@pytest.mark.parametrize("element", ["hex8", "tet4"])
def test_half_cell_offset_mortar_slides_at_the_hand_load(variant, element):
    P, theta = 1e5, 0.3
    res = sc.solve_static(offset_boxes(variant, 3, element, theta, P))
    W = RHO * G * 0.5
    assert res.status == sc.Status.EQUILIBRIUM_LOST, res.message
    assert res.multipliers[-1].equilibrium_lost == pytest.approx(
        fr.slip_limit(F * (P + W), K, theta), rel=1e-9)
    assert res.residual.max() < 1e-9 and res.violation.max() < 1e-9
    ends = np.count_nonzero(np.asarray(res.cfe["minus_nodes"]) >= 0, axis=1)
    assert ends.max() > 1  # non-matching: the S− ends are interpolated
