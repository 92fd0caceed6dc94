"""The safety checks of a search: the registry's state and transition properties, evaluated
by a loop that names none of them (scalars in the reference engine, columns in the bulk one).

Each property is checked until its first witness (the first in BFS order, hence a
shortest one). The bulk engine evaluates a state property once per distinct
(configuration row, idle) pair of its facts table, and a transition property's ``value``
once per row and its ``holds`` once per distinct pair of values: the same definition as
the reference engine, evaluated on the same facts.
"""

from __future__ import annotations

from collections.abc import Callable, Iterable
from dataclasses import dataclass
from typing import Any

import numpy as np

from gather_verify.properties.base import Property
from gather_verify.properties.facts import Facts, StateFacts
from gather_verify.properties.registry import get_property, registered


@dataclass
class Violation:
    """The first (shortest) witness of a safety property: the state it fails in (for a
    transition property, the state the failing transition leaves) and why."""

    property: str
    state: int
    reason: str


def selected(names: Iterable[str] | None) -> list[Property]:
    """The properties a search checks: those named (None: all) and the pseudo-properties."""
    wanted = None if names is None else {get_property(name).name for name in names}
    return [p for p in registered() if p.pseudo or wanted is None or p.name in wanted]


def symmetric(names: Iterable[str] | None) -> bool:
    """Whether the symmetry reduction is sound for every property named (see
    :attr:`~gather_verify.properties.base.Property.symmetric`)."""
    return all(p.symmetric for p in selected(names))


class Checks:
    """The state and transition properties one search checks, and what it found.

    ``names``: the requested properties (None: all; pseudo-properties are always checked);
    ``initial``: the facts of the initial state, on which a property may be ``vacuous``
    (then it is not checked and :attr:`vacuous` says why)."""

    def __init__(self, names: Iterable[str] | None, initial: StateFacts):
        props = [p for p in selected(names) if p.kind != "graph"]
        self.vacuous: dict[str, str] = {}
        for p in props:
            why = p.vacuous(initial) if p.vacuous is not None else None
            if why is not None:
                self.vacuous[p.name] = why
        active = [p for p in props if p.name not in self.vacuous]
        self.halting = [p for p in active if p.halts]
        self.on_expansion = [p for p in active
                             if p.kind == "state" and not p.halts and p.when == "expansion"]
        self.on_discovery = [p for p in active
                             if p.kind == "state" and not p.halts and p.when == "discovery"]
        self.on_transition = [p for p in active if p.kind == "transition"]
        self.violations: dict[str, Violation] = {}

    def _record(self, prop: Property, sid: int, *args: Any) -> None:
        self.violations[prop.name] = Violation(prop.name, sid, prop.message_for(*args))

    def open(self, props: list[Property]) -> list[Property]:
        """Those of ``props`` without a witness yet."""
        return [p for p in props if p.name not in self.violations]

    # -- scalars: the reference engine --------------------------------------------------

    def halt(self, sid: int, s: StateFacts) -> str | None:
        """The first halting property failing in state ``sid`` (recorded), else None."""
        for p in self.halting:
            if not p.holds(s):  # type: ignore[misc]
                self._record(p, sid, s)
                return p.name
        return None

    def state(self, sid: int, s: StateFacts, props: list[Property]) -> None:
        for p in props:
            if p.name not in self.violations and not p.holds(s):  # type: ignore[misc]
                self._record(p, sid, s)

    def transition(self, sid: int, before: Facts, after: Callable[[], Facts]) -> None:
        """The transition properties on one transition out of ``sid`` (``after``: the
        successor's facts, computed only if some property is still open)."""
        got = None
        for p in self.on_transition:
            if p.name in self.violations:
                continue
            got = after() if got is None else got
            b, a = p.value(before), p.value(got)  # type: ignore[misc]
            if not p.holds(b, a):  # type: ignore[misc]
                self._record(p, sid, b, a)


class ColumnChecks:
    """:class:`Checks` over the bulk engine's columns: ``facts(row)`` gives the facts of a
    row of its facts table (computed lazily, attribute by attribute), ``facts(row, idle)``
    those of a state, with an attribute ``read_idle`` (whether a predicate read ``idle``)."""

    def __init__(self, checks: Checks, facts: Callable[..., Any],
                 many: Callable[[np.ndarray, np.ndarray], list[Any]]):
        self.checks = checks
        self.facts = facts
        self.many = many  # (rows, idle) -> the state facts of each pair, in one go
        self.verdicts: dict[str, np.ndarray] = {}  # per (row * 2 + idle): -1 unknown, 0, 1
        self.values: dict[str, tuple[np.ndarray, dict[Any, int], list[Any]]] = {}
        self.pairs: dict[str, dict[tuple[int, int], bool]] = {}

    def fails(self, prop: Property, rows: np.ndarray, idle: np.ndarray) -> np.ndarray:
        """Per state (configuration row, idle flag), whether state property ``prop`` fails."""
        key = rows.astype(np.int64) * 2 + idle
        col = self.verdicts.get(prop.name)
        need = (int(key.max()) | 1) + 1 if len(key) else 0  # both idle values of each row
        if col is None or len(col) < need:
            grown = np.full(max(need, 2 * (0 if col is None else len(col)), 1024), -1,
                            dtype=np.int8)
            if col is not None:
                grown[:len(col)] = col
            self.verdicts[prop.name] = col = grown
        todo = np.unique(key[col[key] < 0])
        if len(todo):
            holds = prop.holds
            assert holds is not None
            for k, s in zip(todo.tolist(), self.many(todo >> 1, (todo & 1).astype(bool)),
                            strict=True):
                if col[k] >= 0:
                    continue  # settled with the other idle value (the predicate did not read it)
                ok = bool(holds(s))
                col[k] = ok
                if not s.read_idle:  # the answer does not depend on idle
                    col[k ^ 1] = ok
        return col[key] == 0

    def first_failure(self, props: list[Property], rows: np.ndarray, idle: np.ndarray
                      ) -> tuple[int, Property] | None:
        """The first state (index) where one of ``props`` fails, and the first such property."""
        best: tuple[int, Property] | None = None
        for p in props:
            hit = np.flatnonzero(self.fails(p, rows, idle))
            if len(hit) and (best is None or int(hit[0]) < best[0]):
                best = (int(hit[0]), p)
        return best

    def record_halt(self, sid: int, row: int, idle: bool, prop: Property) -> None:
        self.checks._record(prop, sid, self.facts(row, idle))

    def states(self, first_id: int, rows: np.ndarray, idle: np.ndarray,
               props: list[Property]) -> None:
        """Check state properties ``props`` on states ``first_id, first_id + 1, ...``."""
        if not len(rows):
            return
        for p in self.checks.open(props):
            hit = np.flatnonzero(self.fails(p, rows, idle))
            if len(hit):
                i = int(hit[0])
                self.checks._record(p, first_id + i, self.facts(int(rows[i]), bool(idle[i])))

    def value_ids(self, prop: Property, rows: np.ndarray) -> tuple[np.ndarray, list[Any]]:
        """Per row, the id of ``prop.value`` of its facts (values numbered as first seen)."""
        col, index, values = self.values.get(prop.name) or (np.empty(0, dtype=np.int32), {}, [])
        need = int(rows.max()) + 1 if len(rows) else 0
        if len(col) < need:
            grown = np.full(max(need, 2 * len(col), 1024), -1, dtype=np.int32)
            grown[:len(col)] = col
            col = grown
        self.values[prop.name] = (col, index, values)
        for r in np.unique(rows[col[rows] < 0]).tolist():
            v = prop.value(self.facts(r))  # type: ignore[misc]
            if v not in index:
                index[v] = len(values)
                values.append(v)
            col[r] = index[v]
        return col[rows], values

    def transitions(self, first_id: int, src: np.ndarray, before: np.ndarray,
                    after: np.ndarray) -> None:
        """Check the transition properties on transitions from states ``first_id + src`` whose
        configurations are the rows ``before`` and ``after`` (in BFS and event order)."""
        if not len(src):
            return
        for p in self.checks.open(self.checks.on_transition):
            vb, values = self.value_ids(p, before)
            va, values = self.value_ids(p, after)
            pairs = self.pairs.setdefault(p.name, {})
            key = vb.astype(np.int64) << 32 | va
            bad = []
            for k in np.unique(key).tolist():
                pair = (k >> 32, k & 0xFFFFFFFF)
                ok = pairs.get(pair)
                if ok is None:
                    pairs[pair] = ok = bool(p.holds(values[pair[0]], values[pair[1]]))  # type: ignore[misc]
                if not ok:
                    bad.append(k)
            if bad:
                hit = np.flatnonzero(np.isin(key, np.array(bad, dtype=np.int64)))
                i = int(hit[0])
                self.checks._record(p, first_id + int(src[i]), values[int(vb[i])],
                                    values[int(va[i])])
