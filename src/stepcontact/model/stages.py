"""Construction in stages (issue 12): one static run through the stages of a construction,
keeping locked-in stresses and contact forces.

A :class:`Stage` lists what enters the structure when it begins (bodies, interfaces made at
once, contacts, supports), what leaves it (supports removed) and joints grouted, and its own
load segments.  Items that no stage lists are in place from the start.  The solver keeps one
assembled system of the whole model; a stage changes which DOFs are held, which CFEs act and
the zero of the CFEs made at once (:mod:`stepcontact.solver.staging`).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import ClassVar

from stepcontact.errors import ModelError
from stepcontact.model.bond import Bond
from stepcontact.model.structure import DynamicInterval, Segment


@dataclass(frozen=True, eq=False)
class Stage:
    """One construction stage.

    Parameters
    ----------
    name : str
    program : tuple of Segment
        The stage's load segments (the model's program is the stages' programs in order).
    bodies : names of the bodies built at this stage (inactive, unloaded and stress-free
        before; their nodes start from zero displacement: they are placed on the deformed
        structure).
    interfaces : names of interfaces made *at once* at this stage: contact established now and
        stress-free (the CFEs' current mutual displacements become their zero).
    contacts : names of interfaces that act from this stage with their geometric gap in the
        current deformed configuration (a CFE closes when its gap does).
    supports : names of supports placed at this stage (they hold the DOFs where they are now).
    remove_supports : names of supports removed at this stage: their reaction is released by
        an automatic segment at the start of the stage (events located).
    grout : {interface name: Bond}: the CFEs of an interface in place become bonded with that
        strength, keeping their current forces (an open CFE is filled: its opening becomes
        its zero).
    dynamics : DynamicInterval, optional
        A dynamic interval at the end of this stage, after its load segments.  On the *last*
        stage it is the model's dynamic interval (``Model.dynamics``, set from it):
        :func:`~stepcontact.solve_dynamic` runs it on the last stage's system from the state
        the stages end in.  On an earlier stage :func:`~stepcontact.solve_static` runs it
        in the run of the stages (on that stage's system, from the state its segments end
        in; the result is ``StaticResult.dynamics[stage name]``), then holds the force out
        of balance at its end, M a + C v (N), as an automatic pattern
        ``"<stage>: settle after dynamics"`` at factor 1 and releases it by an automatic
        segment (events located), so that the static path goes on from the state the motion
        left, with its friction history, at rest.  The factors of the interval's load
        patterns stand at g(T) after it (T its duration), and the next segments start there.
    """

    name: str
    program: tuple = ()
    bodies: tuple[str, ...] = ()
    interfaces: tuple[str, ...] = ()
    contacts: tuple[str, ...] = ()
    supports: tuple[str, ...] = ()
    remove_supports: tuple[str, ...] = ()
    grout: dict = field(default_factory=dict)
    dynamics: object = None
    #: the field of :class:`~stepcontact.model.Model` a stage goes into (``Model.add``)
    model_field: ClassVar[str] = "stages"

    def __post_init__(self):
        item = f"stage '{self.name}'"
        for key in ("program", "bodies", "interfaces", "contacts", "supports",
                    "remove_supports"):
            v = getattr(self, key)
            if isinstance(v, str | Segment):
                v = (v,)
            object.__setattr__(self, key, tuple(v))
        for i, seg in enumerate(self.program):
            if not isinstance(seg, Segment):
                raise ModelError(f"{item}.program[{i}]", f"must be a Segment, got "
                                 f"{type(seg).__name__}")
        g = dict(self.grout.items() if isinstance(self.grout, dict) else self.grout)
        for name, bond in g.items():
            if not isinstance(bond, Bond):
                raise ModelError(f"{item}.grout['{name}']", f"must be a Bond, got "
                                 f"{type(bond).__name__}")
        object.__setattr__(self, "grout", g)
        if self.dynamics is not None and not isinstance(self.dynamics, DynamicInterval):
            raise ModelError(f"{item}.dynamics", f"must be a DynamicInterval, got "
                             f"{type(self.dynamics).__name__}")
        both = set(self.interfaces) & set(self.contacts)
        if both:
            raise ModelError(f"{item}", f"interface '{sorted(both)[0]}' is listed both as made "
                             "at once (interfaces) and as a contact (contacts)")
        both = set(self.supports) & set(self.remove_supports)
        if both:
            raise ModelError(f"{item}", f"support '{sorted(both)[0]}' is both placed and "
                             "removed at this stage")


#: the lists of a stage that name the items it changes: (field, kind of item, what the stage
#: does to it); an item is built, made, placed or removed by one stage at most
STAGE_LISTS: tuple[tuple[str, str, str], ...] = (
    ("bodies", "body", "built"), ("interfaces", "interface", "made"),
    ("contacts", "interface", "made"), ("supports", "support", "placed"),
    ("remove_supports", "support", "removed"))


def _known(names) -> str:
    return ", ".join(repr(n) for n in names) or "none defined"


def list_problems(stages, known: dict, label) -> list[tuple[int, str, str]]:
    """The problems of the names that ``stages`` list, as (stage index, field, message): the
    one place of these rules, for :class:`~stepcontact.solver.staging.StagePlan` (the first
    is raised) and the model file (all are listed, at their field paths).

    ``stages``: :class:`Stage` objects, or the model file's stage tables (the same fields);
    ``known``: the names of each kind of item ("body", "interface", "support");
    ``label(k)``: stage k as the messages name it (``stage 'x'`` or ``stages[2] ('x')``).

    A listed name must exist and be listed once (by one stage, in one of its lists: an
    interface is made at once or acts as a contact); a support is removed at a later stage
    than the one that places it (or, in place from the start, after the first stage); grout
    fills an existing interface in place: not at the first stage (there is no earlier state
    to keep), not before the stage that makes it.
    """
    out: list[tuple[int, str, str]] = []
    claimed: dict[tuple[str, str], tuple[int, str]] = {}  # (what, name) -> (stage, field)
    for k, st in enumerate(stages):
        for key, kind, what in STAGE_LISTS:
            for name in getattr(st, key):
                if name not in known[kind]:
                    out.append((k, key, f"no such {kind} '{name}' (known: "
                                        f"{_known(known[kind])})"))
                    continue
                prev = claimed.setdefault((what, name), (k, key))
                if prev == (k, key) and list(getattr(st, key)).count(name) > 1:
                    text = f"lists {kind} '{name}' twice"
                elif prev == (k, key):
                    continue
                elif prev[0] == k:
                    text = (f"{kind} '{name}' is listed in {prev[1]} too"
                            + (": an interface is made at once (interfaces) or acts as a "
                               "contact with its gap (contacts)" if kind == "interface" else ""))
                else:
                    text = f"{kind} '{name}' is already listed by {label(prev[0])}"
                if (k, key, text) not in out:
                    out.append((k, key, text))
        for name in st.grout:
            if name not in known["interface"]:
                out.append((k, "grout", f"no such interface '{name}' (known: "
                                        f"{_known(known['interface'])})"))
            elif k == 0:
                out.append((k, "grout", f"the first stage cannot grout interface '{name}' "
                            "(there is no earlier state to keep): give the interface its "
                            "strength from the start (its bond: Interface(bond=...), "
                            "[interfaces.bond] in a model file) or grout it at a later stage"))
    for k, st in enumerate(stages):
        for name in st.grout:
            j = claimed.get(("made", name), (0,))[0]
            if j > k:
                out.append((k, "grout", f"interface '{name}' is made later, by {label(j)}: "
                                        "grout joints in place"))
    for (what, name), (k, key) in claimed.items():
        if what != "removed":
            continue
        j = claimed.get(("placed", name), (0, ""))[0]
        if k <= j:
            where = (f"placed by {label(j)}" if ("placed", name) in claimed else
                     "in place from the start")
            out.append((k, key, f"support '{name}' is removed before or when it is placed "
                                f"({where}): remove it at a later stage"))
    return out


__all__ = ["STAGE_LISTS", "Stage", "list_problems"]
