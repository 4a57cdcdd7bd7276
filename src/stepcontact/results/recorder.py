"""Append-only recording of the states of a run: arrays that grow by doubling, so that a
result can be taken at any moment as views (no rebuilding per segment or per state)."""

from __future__ import annotations

import numpy as np

from stepcontact.contact.layout import ContactLayout


class GrowingArray:
    """Rows appended one at a time to a preallocated array; ``view`` is the filled part."""

    def __init__(self, row_shape: tuple[int, ...], dtype=float, capacity: int = 64):
        self._a = np.zeros((capacity, *row_shape), dtype=dtype)
        self.n = 0

    def append(self, row) -> None:
        if self.n == len(self._a):
            self._grow()
        self._a[self.n] = row
        self.n += 1

    def _grow(self) -> None:
        grown = np.zeros((2 * len(self._a), *self._a.shape[1:]), dtype=self._a.dtype)
        grown[: self.n] = self._a[: self.n]
        self._a = grown

    @property
    def view(self) -> np.ndarray:
        return self._a[: self.n]


class Recorder:
    """The reported states of a run (one row each) and the logs that go with them."""

    COLUMNS = ("lam", "segment", "kind", "factors", "s", "w", "state", "residual", "violation",
               "reactions", "water", "pressure", "stage")

    def __init__(self, m: int | ContactLayout, n_patterns: int, n_reactions: int):
        """``m``: the number of CFEs (2D) or the layout of the contact unknowns."""
        layout = m if isinstance(m, ContactLayout) else ContactLayout(m)
        m = layout.m
        self.layout = layout
        self.lam = GrowingArray(())
        self.segment = GrowingArray((), np.int64)
        self.kind = GrowingArray((), "U13")
        self.factors = GrowingArray((n_patterns,))
        self.s = GrowingArray((layout.n,))
        self.w = GrowingArray((layout.n,))
        #: state codes (:mod:`stepcontact.enums`): int16, the faceted-cone codes go beyond
        #: int8 (up to VERTEX_SLIP + MAX_FACETS − 1 = 271)
        self.state = GrowingArray((m,), np.int16)
        self.residual = GrowingArray(())
        self.violation = GrowingArray(())
        self.reactions = GrowingArray((n_reactions,))
        self.water = GrowingArray((m,))  # crack-water forces W (fem.crack), N
        self.pressure = GrowingArray((m,))  # water pressure in opened joints, Pa
        self.stage = GrowingArray((), np.int64)  # construction stage (0 without stages)
        self.fields: dict[int, np.ndarray] = {}
        self.stresses: dict[int, dict[str, np.ndarray]] = {}
        self.events: list = []
        self.multipliers: list = []
        self.nonunique: list[dict] = []
        self._columns = tuple((k, getattr(self, k)) for k in self.COLUMNS)

    def __len__(self) -> int:
        return self.lam.n

    def append(self, **row) -> int:
        i = self.lam.n
        row.setdefault("stage", 0)
        for k, col in self._columns:  # (GrowingArray.append, inline: once per state)
            n = col.n
            if n == len(col._a):
                col._grow()
            col._a[n] = row[k]
            col.n = n + 1
        return i

    def arrays(self) -> dict[str, np.ndarray]:
        return {k: getattr(self, k).view for k in self.COLUMNS}
