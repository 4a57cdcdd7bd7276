"""The contact law of a system, built in one place for every driver (static and dynamic).

The law of the CFEs (eq. (1), Coulomb friction; compliant layers eq. (11); bonded joints eq.
(12)) takes its inputs from the system's CFEs, or, in a run in construction stages
(:mod:`stepcontact.solver.staging`), from the stage plan: the friction and bond strengths of
the plan (grouted joints included), and the CFEs not active at the stage are inert.  What the
drivers differ in is explicit: the normal stiffness of the law (the dynamic driver's damped
layers carry Ĉ_n = C_n + c_n c₁), whether the components held by supports on both ends are
inert, and whether they are warned about.
"""

from __future__ import annotations

import warnings

import numpy as np

from stepcontact.contact.bond import BondedJointLaw
from stepcontact.contact.faceted import FacetedCoulombLaw
from stepcontact.contact.laws import ContactLaw, CoulombLaw
from stepcontact.errors import ContactHeldWarning, ModelError
from stepcontact.fem.assembly import System
from stepcontact.solver.staging import held_components


def law_inputs(system: System, *, plan=None, stage: int | None = None,
               held_by_supports: bool = True):
    """(friction (m,), bond (m, ≥4) strengths, held normal (m,), held tangential (m,)) of the
    law of ``system``: the CFEs' own, or with ``plan`` (a
    :class:`~stepcontact.solver.staging.StagePlan`; ``system`` its system of stage ``stage``)
    the plan's friction and bonds and the CFEs not active at ``stage`` held (inert).
    ``held_by_supports``: the components held by supports on both ends
    (:func:`~stepcontact.solver.staging.held_components`) are held too — the static driver's
    rule, and the dynamic driver's after stages; a dynamic interval without stages holds none
    (False)."""
    m = system.m
    if held_by_supports:
        held_n, held_t = held_components(system)
    else:
        held_n, held_t = np.zeros(m, bool), np.zeros(m, bool)
    if plan is None:
        return system.cfe.friction, system.cfe.bond, held_n, held_t
    active = plan.active_cfes(stage)
    return plan.friction, plan.bond, held_n | ~active, held_t | ~active


def contact_law(system: System, *, plan=None, stage: int | None = None, kn=None,
                held_by_supports: bool = True, warn: bool = False) -> ContactLaw:
    """The contact law of the CFEs of ``system`` (:func:`law_inputs` for ``plan``, ``stage``
    and ``held_by_supports``): :class:`~stepcontact.contact.laws.CoulombLaw` in 2D,
    :class:`~stepcontact.contact.faceted.FacetedCoulombLaw` for CFEs with two tangential
    components (the system's ``cfe.facets``, ``facet_angle``, ``facet_stagger``), under a
    :class:`~stepcontact.contact.bond.BondedJointLaw` where CFEs are bonded (eq. (12); the
    bond's residual cohesion is the Coulomb law's).  ``kn``: the law's normal stiffness
    C_n (m,), N/m (default the CFEs' own ``cfe.kn``; infinite: rigid).  ``warn``: a
    :class:`~stepcontact.errors.ContactHeldWarning` names the active CFEs whose relative
    motion supports hold (they carry nothing in that component)."""
    cfe = system.cfe
    friction, bond, held_n, held_t = law_inputs(system, plan=plan, stage=stage,
                                                held_by_supports=held_by_supports)
    if warn and held_by_supports:
        if plan is None:
            warn_held(cfe, held_n, held_t)
        else:
            active = plan.active_cfes(stage)
            warn_held(cfe, held_n & active, held_t & active)
    kn = cfe.kn if kn is None else kn
    m = cfe.m
    bond = np.full((m, 4), np.nan) if bond is None else np.asarray(bond, dtype=float)
    bonded = ~np.isnan(bond[:, 0])
    cohesion = (np.where(bonded, np.nan_to_num(bond[:, 4]), 0.0) if bond.shape[1] > 4
                else np.zeros(m))
    if system.layout.n_t > 1:  # two tangential components: Coulomb on a faceted cone
        if np.any(cohesion > 0):
            k = int(np.flatnonzero(cohesion > 0)[0])
            raise ModelError(f"bond[{k}]", "a residual cohesion after the break is not "
                             "available on a faceted cone (3D) yet; give none")
        after = FacetedCoulombLaw(np.arange(m), friction, kn, cfe.kt, facets=cfe.facets,
                                  angle=cfe.facet_angle, stagger=cfe.facet_stagger,
                                  adaptive=getattr(cfe, "facet_adaptive", False),
                                  held_normal=held_n, held_tangent=held_t)
    else:
        after = CoulombLaw(np.arange(m), friction, kn, cfe.kt, held_n, held_t,
                           cohesion=cohesion)
    if not bonded.any():
        return after
    return BondedJointLaw(after, bond)  # eq. (12): bonded until the break, then ``after``


def warn_held(cfe, held_n: np.ndarray, held_t: np.ndarray) -> None:
    """Warn (:class:`~stepcontact.errors.ContactHeldWarning`) about the CFEs whose normal
    (``held_n``) or tangential (``held_t``, frictional ones) relative motion supports on both
    ends hold: the supports carry that force."""
    for mask, what, effect in ((held_n, "normal", "its normal force (the CFE carries "
                                "nothing)"),
                               (held_t & ~held_n & (cfe.friction > 0), "tangential",
                                "its tangential force (the CFE is frictionless)")):
        if mask.any():
            names = [f"{cfe.names[cfe.interface[k]]}[{cfe.local[k]}]"
                     for k in np.flatnonzero(mask)[:8]]
            more = f" and {mask.sum() - 8} more" if mask.sum() > 8 else ""
            warnings.warn(ContactHeldWarning(
                f"CFE {', '.join(names)}{more}: {what} relative motion held by supports on "
                f"both ends; the supports carry {effect}"), stacklevel=4)


__all__ = ["contact_law", "law_inputs", "warn_held"]
