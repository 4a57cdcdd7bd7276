"""The per-scheme bookkeeping of CoulombLaw (the masks it forms once per state array by one
gather from a table, and the relation blocks written from them) against the definitions.

References: the masks against their definitions written out with the state codes
(``contact/laws.py``, class ``_StateMasks``); the relation blocks against
:meth:`Relations.from_kinds`, an independent constructor that takes the relation kind of each
component (FREE, FIXED, SPRING) and the slip coupling as the class docstring of CoulombLaw
states them.  Both are exact (booleans, and blocks of 0, 1, −C, −σ f): compared with ``==``.
"""

from __future__ import annotations

import numpy as np
import pytest

from stepcontact.contact.laws import (
    CLOSED,
    FIXED,
    FREE,
    OPEN,
    SLIP_NEG,
    SLIP_POS,
    SPRING,
    STICK,
    CoulombLaw,
    Relations,
)
from stepcontact.contact.layout import ContactLayout

M = 40


def _law(rng: np.random.Generator, cohesion: bool) -> CoulombLaw:
    """A law with every kind of CFE: frictionless, rigid and compliant in each direction, held
    by supports, with a residual cohesion (some lost)."""
    law = CoulombLaw(np.arange(M), np.where(rng.random(M) < 0.3, 0.0, 0.6),
                     np.where(rng.random(M) < 0.5, np.inf, 2e9),
                     np.where(rng.random(M) < 0.5, np.inf, 1e9),
                     held_normal=rng.random(M) < 0.15, held_tangent=rng.random(M) < 0.15,
                     cohesion=np.where(rng.random(M) < 0.4, 3.0, 0.0) if cohesion else None)
    law.lose_cohesion(rng.random(M) < 0.5)
    return law


@pytest.mark.parametrize("seed", range(6))
def test_masks_match_their_definitions(seed):
    """Every mask of a random state array (int64 and the recorder's int16) equals its
    definition from the state codes and the CFEs' parameters; asked again, the kept masks
    are returned."""
    rng = np.random.default_rng(seed)
    law = _law(rng, cohesion=bool(seed % 2))
    for dtype in (np.int64, np.int16):
        st = rng.choice([OPEN, STICK, SLIP_POS, SLIP_NEG, CLOSED], M).astype(dtype)
        mk = law._masks(st)
        free = ~law.inert
        closed = (st != OPEN) & free
        slip = (st == SLIP_POS) | (st == SLIP_NEG)
        fric = law.frictional
        want = {
            "open": (st == OPEN) & free, "closed": closed, "not_closed": ~closed,
            "stick": (st == STICK) & closed & fric, "stick_state": st == STICK, "slip": slip,
            "slip_closed": slip & closed, "cl": st == CLOSED,
            "closed_rn": closed & law.rigid_n, "closed_sn": closed & ~law.rigid_n,
            "free_t": ~closed | (st == CLOSED), "held_t": closed & ~slip & fric,
            "held_t_rigid": closed & ~slip & fric & law.rigid_t,
            "couple": slip & closed & fric, "sigma": np.where(st == SLIP_POS, 1.0, -1.0),
        }
        for name, ref in want.items():
            assert np.array_equal(getattr(mk, name), ref), name
        assert mk.any_open == bool(want["open"].any())
        assert mk.any_stick == bool(want["stick"].any())
        assert mk.any_slip == bool(slip.any())
        assert law._masks(st.copy()) is mk


@pytest.mark.parametrize("seed", range(6))
@pytest.mark.parametrize("article", [False, True])
def test_relation_blocks_match_the_kinds(seed, article):
    """The blocks CoulombLaw writes for random schemes equal ``Relations.from_kinds`` of the
    kinds its docstring gives: open or held by supports FREE; stuck FIXED (rigid) or SPRING
    (layer) in both directions; slipping (exact) tangential FREE with coupling −σ f, in the
    article's treatment uncoupled; frictionless (CLOSED) tangential FREE."""
    rng = np.random.default_rng(100 + seed)
    law = _law(rng, cohesion=bool(seed % 2))
    lay = ContactLayout(M)
    st = rng.choice([OPEN, STICK, SLIP_POS, SLIP_NEG, CLOSED], M)
    rel = Relations.empty(lay)
    law.relations(st, rel, lay, article)
    closed = (st != OPEN) & ~law.inert
    slip = closed & ((st == SLIP_POS) | (st == SLIP_NEG))
    held_t = closed & ~slip & law.frictional
    kind_t = np.where(held_t, np.where(law.rigid_t, FIXED, SPRING), FREE)
    kind_n = np.where(closed, np.where(law.rigid_n, FIXED, SPRING), FREE)
    sigma = np.where(st == SLIP_POS, 1.0, -1.0)
    couple_t = np.where(slip & law.frictional & (not article), -sigma * law.f, 0.0)
    ref = Relations.from_kinds(np.r_[kind_t, kind_n], np.r_[law.kt, law.kn],
                               np.r_[couple_t, np.zeros(M)], lay)
    assert np.array_equal(rel.S, ref.S)
    assert np.array_equal(rel.W, ref.W)
