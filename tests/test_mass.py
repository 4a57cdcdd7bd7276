"""Mass matrices and Rayleigh damping (groundwork of the dynamics): total mass, HRZ lumping that
stays positive on quadratic elements, the first natural frequency of a bar against the closed
form, and the Rayleigh coefficients against their defining equations."""

from __future__ import annotations

import numpy as np
import pytest
import scipy.linalg as sla

import stepcontact as sc
from stepcontact.errors import ModelError
from stepcontact.fem.assembly import dof_map, stiffness
from stepcontact.fem.mass import continuum_mass, mass, rayleigh_coefficients

RHO = 2500.0


@pytest.mark.parametrize("element", ["tri3", "quad4", "tri6", "quad8"])
@pytest.mark.parametrize("lumped", [False, True])
def test_total_mass_is_rho_t_area_in_each_direction(element, lumped):
    body = sc.rectangle("b", (0, 0), (3.0, 2.0), 3, 2, sc.Material(E=1e9, nu=0.2,
                                                                  density=RHO),
                        element=element)
    M = continuum_mass(body, 0.5, lumped)
    total = RHO * 0.5 * 6.0
    for c in (0, 1):  # a unit rigid translation in x (or y)
        e = np.zeros(M.shape[0])
        e[c::2] = 1.0
        assert e @ (M @ e) == pytest.approx(total, rel=1e-12)
    assert abs(M - M.T).max() <= 1e-14 * total  # symmetric (round-off of the assembly)
    if lumped:
        assert np.all(M.diagonal() > 0)
        assert np.count_nonzero(M.toarray() - np.diag(M.diagonal())) == 0


def test_hrz_is_positive_where_row_sum_lumping_is_not():
    body = sc.rectangle("b", (0, 0), (1.0, 1.0), 2, 2, sc.Material(E=1e9, nu=0.2,
                                                                  density=RHO),
                        element="tri6")
    Mc = continuum_mass(body, 1.0)
    row_sum = np.asarray(Mc.sum(axis=1)).ravel()
    assert row_sum.min() <= 1e-12 * row_sum.max()  # tri6 corners: zero row sums
    assert continuum_mass(body, 1.0, lumped=True).diagonal().min() > 0


@pytest.mark.parametrize("lumped", [False, True])
def test_first_axial_frequency_of_a_fixed_free_bar(lumped):
    """Plane stress, ν = 0: a bar fixed at x = 0 vibrates axially at f₁ = c / (4L),
    c = sqrt(E/ρ); consistent mass converges from above, lumped from below (1 % here)."""
    E, L = 2e10, 10.0
    bar = sc.rectangle("bar", (0, 0), (L, 0.5), 40, 1, sc.Material(E=E, nu=0.0, density=RHO))
    m = sc.Model(bodies=[bar], plane="stress")
    m = m.add(sc.Support("root", m.select("bar", x=0.0), "xy"))
    dofs = dof_map(m)
    K, M = stiffness(m, dofs), mass(m, dofs, lumped)
    ids = np.arange(bar.n_nodes)
    fixed = np.zeros(dofs.ndof, bool)
    fixed[dofs.of[ids[np.isclose(bar.points[:, 0], 0.0)], :2].ravel()] = True
    # axial motion only (uy held): the first mode of the free DOFs in x
    free = ~fixed & np.isin(np.arange(dofs.ndof), dofs.of[ids, 0])
    Kf = K[free][:, free].toarray()
    Mf = M[free][:, free].toarray()
    w2 = sla.eigh(Kf, Mf, eigvals_only=True, subset_by_index=[0, 0])[0]
    f1 = np.sqrt(w2) / (2 * np.pi)
    exact = np.sqrt(E / RHO) / (4 * L)
    assert f1 == pytest.approx(exact, rel=1e-2)
    assert (f1 > exact) if not lumped else (f1 < exact)


def test_frame_mass_is_rho_a_l():
    beam = sc.Frame("beam", np.array([[0.0, 0.0], [2.0, 0.0], [5.0, 0.0]]),
                    np.array([[0, 1], [1, 2]]), E=2e11, A=0.01, I=1e-5, density=7850)
    m = sc.Model(bodies=[beam])
    dofs = dof_map(m)
    M = mass(m, dofs)
    e = np.zeros(dofs.ndof)
    e[dofs.of[:, 1]] = 1.0
    assert e @ (M @ e) == pytest.approx(7850 * 0.01 * 5.0, rel=1e-12)


def test_rayleigh_coefficients_give_the_two_ratios():
    a0, a1 = rayleigh_coefficients(0.05, 2.0, 0.03, 15.0)
    for zeta, f in ((0.05, 2.0), (0.03, 15.0)):
        w = 2 * np.pi * f
        assert a0 / (2 * w) + a1 * w / 2 == pytest.approx(zeta, rel=1e-12)
    with pytest.raises(ModelError, match="differ"):
        rayleigh_coefficients(0.05, 2.0, 0.05, 2.0)
    with pytest.raises(ModelError, match="f1"):
        rayleigh_coefficients(0.05, 0.0, 0.05, 2.0)
