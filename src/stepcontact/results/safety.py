"""Safety of a joint along the load path: resultants, eccentricity, kern, sliding factor.

What a dam engineer reads first, for one interface at every reported state (plain arrays along
the path axis, from the CFE forces of the result — no new solve):

* ΣN and ΣQ, the sums of the CFE forces (N; ΣN ≤ 0 in compression);
* the position of the normal resultant along the joint, s_R = Σ N_k s_k / Σ N_k (m from the
  heel), its eccentricity e = s_R − B/2 from the centre of the joint (B its length, from the
  first to the last CFE) and whether it lies in the middle third (the kern, |e| ≤ B/6);
* the normal stress σ_n = N/A of the CFE at each end (heel and toe, Pa);
* the sliding factor Σ f_k (−N_k) / |ΣQ| (= f·|ΣN|/|ΣQ| for one friction coefficient): ≥ 1,
  and 1 exactly when every CFE in contact slips;
* the open length, the sum of the tributary lengths of the open CFEs (B × the open share of
  the contact area A_k).

Over the path: the load factor λ at which the joint slides and at which the body overturns —
the loss of equilibrium of the run when its mechanism moves a body of this interface (sliding,
or rotation about a point), otherwise the first state where the sliding factor reaches 1 or
the normal resultant reaches an end of the joint — and the factors of safety
FS = λ_limit / λ_d against a design load factor λ_d.

The formulas hold for a straight joint (ΣN and ΣQ are then the resultant's components normal
and tangential to it).  The heel is the first CFE along the interface unless ``heel`` names a
point: the end nearest to it is the heel (order-independent).

Example
-------
>>> s = res.interface_safety("base", design=1.0)           # doctest: +SKIP
>>> s.sliding_factor[-1], s.in_kern[-1], s.fs_sliding       # doctest: +SKIP
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from stepcontact.enums import ContactState, Status

if TYPE_CHECKING:
    from stepcontact.results.result import StaticResult

#: a sliding factor within this of 1 counts as "every CFE in contact slips"
SLIDING_RTOL = 1e-9


@dataclass(frozen=True)
class InterfaceSafety:
    """Safety quantities of one interface along the path (arrays: one entry per state).

    Attributes
    ----------
    interface : str
    lam : (n,) load factor of the active segment's pattern (the result's path axis)
    segment : (n,) segment of each state
    normal_force : (n,) ΣN, N (≤ 0 in compression)
    shear_force : (n,) ΣQ, N (along the CFE tangent t)
    position : (n,) s_R, position of the normal resultant from the heel along the joint, m
        (NaN where ΣN = 0)
    point : (n, 2) coordinates of the normal resultant on S+, m
    eccentricity : (n,) e = s_R − B/2, m (> 0: towards the toe)
    in_kern : (n,) bool, |e| ≤ B/6 (the resultant in the middle third)
    sigma_heel, sigma_toe : (n,) σ_n = N/A of the CFE at the heel and at the toe, Pa
    sliding_factor : (n,) Σ f_k (−N_k) / |ΣQ| (inf where ΣQ = 0 to round-off)
    open_length : (n,) sum of the tributary lengths of the open CFEs, m
    length : B, length of the joint from the first to the last CFE, m
    heel, toe : (2,) coordinates of the end CFEs, m
    friction : friction coefficient (the largest of the interface's CFEs)
    design : design load factor λ_d (None: not given)
    lam_sliding, lam_overturning : λ at which the joint slides / the body overturns (None: not
        reached on the path)
    mechanism : the mode of the interface's bodies when the run lost equilibrium (None if
        it did not, or moved other bodies)
    """

    interface: str
    lam: np.ndarray
    segment: np.ndarray
    normal_force: np.ndarray
    shear_force: np.ndarray
    position: np.ndarray
    point: np.ndarray
    eccentricity: np.ndarray
    in_kern: np.ndarray
    sigma_heel: np.ndarray
    sigma_toe: np.ndarray
    sliding_factor: np.ndarray
    open_length: np.ndarray
    length: float
    heel: np.ndarray
    toe: np.ndarray
    friction: float
    design: float | None = None
    lam_sliding: float | None = None
    lam_overturning: float | None = None
    mechanism: str | None = None

    @property
    def fs_sliding(self) -> float | None:
        """Factor of safety against sliding, λ_sliding / λ_d (None if either is unknown)."""
        return _ratio(self.lam_sliding, self.design)

    @property
    def fs_overturning(self) -> float | None:
        """Factor of safety against overturning, λ_overturning / λ_d."""
        return _ratio(self.lam_overturning, self.design)

    def at(self, i: int = -1) -> dict[str, object]:
        """The quantities of state ``i`` (default the last) and the path's limits, as plain
        Python numbers (what ``stepcontact info`` prints)."""
        n = len(self.lam)
        j = i + n if i < 0 else i

        def num(v) -> float | None:
            v = float(v)
            return v if np.isfinite(v) else None

        return {
            "interface": self.interface, "state": int(j), "lam": float(self.lam[j]),
            "segment": int(self.segment[j]),
            "normal_force": float(self.normal_force[j]),
            "shear_force": float(self.shear_force[j]),
            "position": num(self.position[j]), "eccentricity": num(self.eccentricity[j]),
            "in_kern": bool(self.in_kern[j]), "length": float(self.length),
            "sigma_heel": float(self.sigma_heel[j]), "sigma_toe": float(self.sigma_toe[j]),
            "sliding_factor": num(self.sliding_factor[j]),
            "open_length": float(self.open_length[j]),
            "lam_sliding": self.lam_sliding, "lam_overturning": self.lam_overturning,
            "design": self.design, "fs_sliding": self.fs_sliding,
            "fs_overturning": self.fs_overturning, "mechanism": self.mechanism,
        }


def _ratio(a: float | None, b: float | None) -> float | None:
    return None if a is None or b is None or b == 0 else float(a) / float(b)


def _bodies_of_nodes(res: StaticResult, nodes: np.ndarray) -> set[str]:
    """Names of the bodies the global nodes belong to (from the result's geometry)."""
    nodes = np.unique(nodes[nodes >= 0])
    out = set()
    for b in (res.geometry or {}).get("bodies", []):
        if np.isin(nodes, np.asarray(b["cells"]).ravel()).any():
            out.add(str(b["name"]))
    return out


def interface_safety(res: StaticResult, interface: str, design: float | None = None,
                     heel=None) -> InterfaceSafety:
    """The :class:`InterfaceSafety` of ``interface`` along the path of ``res``.

    Parameters
    ----------
    res : StaticResult
    interface : str
        Interface name.
    design : float, optional
        Design load factor λ_d of the pattern whose λ is read (e.g. 1 for the design flood):
        FS = λ_limit / λ_d.
    heel : (x, y), optional
        A point near the heel: the end of the joint nearest to it is the heel.  Default: the
        first CFE along the interface.
    """
    names = list(res.interface_names)
    if interface not in names:
        raise KeyError(f"no interface '{interface}' (interfaces: "
                       f"{', '.join(map(repr, names)) or 'none'})")
    if design is not None and not (np.isfinite(design) and design != 0):
        raise ValueError(f"design={design}: give a finite, non-zero design load factor")
    j = names.index(interface)
    iface = np.asarray(res.cfe["interface"])
    k = np.flatnonzero(iface == j)
    if k.size == 0:
        raise ValueError(f"interface '{interface}' has no CFE")
    s = np.asarray(res.cfe["s"], dtype=float)[k]
    k, s = k[np.argsort(s, kind="stable")], np.sort(s)
    x = np.asarray(res.cfe["x"], dtype=float).reshape(-1, 2)[k]
    if heel is not None:
        h = np.asarray(heel, dtype=float)
        if np.linalg.norm(x[-1] - h) < np.linalg.norm(x[0] - h):
            k, s, x = k[::-1], s[::-1], x[::-1]
    pos = np.abs(s - s[0])
    length = float(pos.max())
    area = np.asarray(res.cfe["area"], dtype=float)[k]
    fric = np.asarray(res.cfe["friction"], dtype=float)[k]
    N = np.asarray(res.N, dtype=float)[:, k]
    Q = np.asarray(res.Q, dtype=float)[:, k]
    sN, sQ = N.sum(axis=1), Q.sum(axis=1)
    with np.errstate(divide="ignore", invalid="ignore"):
        loaded = sN != 0
        position = np.where(loaded, (N @ pos) / sN, np.nan)
        point = np.where(loaded[:, None], (N @ x) / sN[:, None], np.nan)
        capacity = -(N @ fric)
        no_shear = np.abs(sQ) <= 1e-12 * np.abs(sN)  # round-off of a zero shear
        sliding = np.where(no_shear, np.inf, capacity / np.abs(sQ))
    ecc = position - 0.5 * length
    tol = 1e-12 * max(length, 1.0)
    in_kern = np.abs(np.nan_to_num(ecc, nan=np.inf)) <= length / 6.0 + tol
    is_open = np.asarray(res.state)[:, k] == int(ContactState.OPEN)
    open_length = length * (is_open @ area) / area.sum() if area.sum() > 0 else 0.0 * sN
    lam = np.asarray(res.lam, dtype=float)

    lam_sliding = lam_overturning = None
    mechanism = None
    mech = res.mechanism if res.status == Status.EQUILIBRIUM_LOST else None
    if mech:
        nodes = np.concatenate([np.asarray(res.cfe[key])[k].ravel()
                                for key in ("plus_nodes", "minus_nodes") if key in res.cfe])
        mine = _bodies_of_nodes(res, nodes)
        modes = [str(b["mode"]) for b in mech.get("bodies", []) if str(b["body"]) in mine]
        if modes:
            mechanism = modes[0]
            if mechanism == "sliding":
                lam_sliding = float(mech["lam"])
            elif mechanism.startswith("rotation"):
                lam_overturning = float(mech["lam"])
    if lam_sliding is None:
        hit = np.flatnonzero((sN < 0) & (sliding <= 1.0 + SLIDING_RTOL))
        lam_sliding = float(lam[hit[0]]) if hit.size else None
    if lam_overturning is None and length > 0:
        hit = np.flatnonzero((sN < 0) & (np.abs(np.nan_to_num(ecc)) >= 0.5 * length - tol))
        lam_overturning = float(lam[hit[0]]) if hit.size else None
    return InterfaceSafety(
        interface=interface, lam=lam, segment=np.asarray(res.segment, dtype=np.int64),
        normal_force=sN, shear_force=sQ, position=position, point=point, eccentricity=ecc,
        in_kern=in_kern, sigma_heel=N[:, 0] / area[0], sigma_toe=N[:, -1] / area[-1],
        sliding_factor=sliding, open_length=np.asarray(open_length, dtype=float),
        length=length, heel=x[0].copy(), toe=x[-1].copy(), friction=float(fric.max()),
        design=None if design is None else float(design), lam_sliding=lam_sliding,
        lam_overturning=lam_overturning, mechanism=mechanism,
    )


__all__ = ["InterfaceSafety", "interface_safety"]
