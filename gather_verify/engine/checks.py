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
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from gather_verify.properties.base import Property
from gather_verify.properties.facts import Facts, StateFacts
from gather_verify.properties.registry import get_property, registered
from schedulers import Event, State

DENSE_VALUES = 256
"""A transition property with at most this many distinct values keeps its verdicts of value
pairs in a matrix (one lookup per transition); more values: a sorted set of pairs."""


@dataclass
class Violation:
    """The first (shortest) witness of a safety property: the state it fails in (for a
    transition property, the state the failing transition leaves, and the ``event`` and
    ``successor`` of that transition, as the scheduler's ``successors`` gives them), why, and
    the property's ``detail`` there."""

    property: str
    state: int
    reason: str
    event: Event | None = None
    successor: State | None = None
    detail: dict[str, Any] = field(default_factory=dict)


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
        every = selected(names)
        props = [p for p in every if p.kind != "graph"]
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
        requested = [p for p in every if not p.pseudo]
        self._settles = None if names is None or any(p.kind == "graph" for p in requested) \
            else [p.name for p in requested if p.name not in self.vacuous]
        """The requested properties whose counterexamples settle the search (None: a graph
        property is requested, which needs the whole space)."""

    def settled(self) -> bool:
        """Whether every requested property has its counterexample: the search may stop
        there (the shortest witnesses are kept), as SPIN stops at its first error."""
        settles = self._settles or ()
        return bool(settles) and all(name in self.violations for name in settles)

    def _record(self, prop: Property, sid: int, *args: Any,
                step: tuple[Event, State] | None = None) -> None:
        event, succ = (None, None) if step is None else step
        self.violations[prop.name] = Violation(prop.name, sid, prop.message_for(*args), event,
                                               succ, prop.detail_for(*args))

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

    def transition(self, sid: int, before: Facts, after: Callable[[], Facts],
                   step: tuple[Event, State]) -> None:
        """The transition properties on one transition out of ``sid`` (``after``: the
        successor's facts, computed only if some property is still open; ``step``: its event
        and successor)."""
        got = None
        for p in self.on_transition:
            if p.name in self.violations:
                continue
            got = after() if got is None else got
            b, a = p.value(before), p.value(got)  # type: ignore[misc]
            if not p.holds(b, a):  # type: ignore[misc]
                self._record(p, sid, b, a, step=step)


class ColumnChecks:
    """:class:`Checks` over the bulk engine's columns: ``facts(row)`` gives the facts of a
    row of its facts table (computed lazily, attribute by attribute), ``facts(row, idle)``
    those of a state, with an attribute ``read_idle`` (whether a predicate read ``idle``)
    and, when ``shared`` is given, ``read_row`` (whether it read a fact of its own row
    rather than one its ``shared`` code fixes)."""

    def __init__(self, checks: Checks, facts: Callable[..., Any],
                 many: Callable[[np.ndarray, np.ndarray], list[Any]],
                 shared: Callable[[np.ndarray], np.ndarray] | None = None):
        self.checks = checks
        self.facts = facts
        self.many = many  # (rows, idle) -> the state facts of each pair, in one go
        self.shared = shared
        """Optional: per row, a code such that rows of one code have the same facts but those
        a predicate can only read through an attribute that sets the facts' ``read_row``
        (:meth:`failures` then evaluates a predicate once per code and idle flag, for every
        row of the code, when it read nothing of its row)."""
        self.verdicts: dict[tuple[str, ...], np.ndarray] = {}  # [row * 2 + idle, j]: -1, 0, 1
        self.values: dict[str, tuple[np.ndarray, dict[Any, int], list[Any]]] = {}
        self.pairs: dict[str, dict[tuple[int, int], bool]] = {}
        self.matrices: dict[str, np.ndarray] = {}  # per property: verdicts of value-id pairs
        self._read_row = True

    def failures(self, props: list[Property], rows: np.ndarray, idle: np.ndarray,
                 gate: int = 0) -> np.ndarray:
        """Per state (configuration row, idle flag) and property of ``props`` (state
        properties), whether it fails: a ``(len(rows), len(props))`` boolean array. The
        verdicts are kept per (row, idle) in one table per list of properties. Where one of
        the first ``gate`` properties (the halting ones) fails, the state is never expanded:
        the others are not evaluated there (as in the reference engine)."""
        key = rows * 2 + idle if rows.dtype == np.int64 else rows.astype(np.int64) * 2 + idle
        names = tuple(p.name for p in props)
        table = self.verdicts.get(names)
        need = (int(key.max()) | 1) + 1 if len(key) else 0  # both idle values of each row
        if table is None or len(table) < need:
            size = max(need, 2 * (0 if table is None else len(table)), 1024)
            grown = np.full((size, len(props)), -1, dtype=np.int8)
            if table is not None:
                grown[:len(table)] = table
            self.verdicts[names] = table = grown
        got = np.take(table, key, axis=0)  # (much faster than table[key] on rows)
        if len(got) and got.min() < 0:
            todo = np.unique(key[(got < 0).any(axis=1)])
            verdicts = table[todo]
            one = np.ones(len(todo), dtype=bool) if self.shared is None \
                else self._share(props, todo, verdicts, gate)
            rest = todo[one]
            lines = verdicts[one].tolist()
            spread: list[tuple[int, int, bool]] = []  # (key, j, verdict) for the other idle value
            done = dict(zip(rest.tolist(), lines, strict=True))
            for (k, line), s in zip(done.items(), self.many(rest >> 1, (rest & 1).astype(bool)),
                                    strict=True):
                self._evaluate(props, gate, line, s, k, done, spread)
            if lines:
                verdicts[one] = lines
            table[todo] = verdicts
            if spread:
                ks, js, oks = zip(*spread, strict=True)
                table[list(ks), list(js)] = oks
            got = np.take(table, key, axis=0)
        return got == 0

    def _evaluate(self, props: list[Property], gate: int, line: list[int], s: Any,
                  k: int | None = None, done: dict[int, list[int]] | None = None,
                  spread: list[tuple[int, int, bool]] | None = None) -> list[bool]:
        """The verdicts of ``props`` left open (-1) in ``line`` on the facts ``s`` of key ``k``
        (row * 2 + idle), in order; a halting property failing (among the first ``gate``)
        settles the others as holding (not evaluated, as in the reference engine). A verdict
        that did not read ``idle`` is also the other idle value's (``done``, else ``spread``).
        Returns per property whether its verdict read nothing of the row (with ``shared``)."""
        free = [False] * len(props)
        sharing = self.shared is not None
        for j, p in enumerate(props):
            if j == gate and gate and 0 in line[:gate]:
                line[gate:] = [1] * (len(props) - gate)  # halting: nothing else checked
                free[gate:] = [all(free[:gate])] * (len(props) - gate)
                break
            if line[j] >= 0:
                continue  # settled with the other idle value (its predicate did not read it)
            s.read_idle = False
            if sharing:
                s.read_row = False
            ok = bool(p.holds(s))  # type: ignore[misc]
            line[j] = ok
            free[j] = sharing and not s.read_row
            if k is not None and not s.read_idle:  # the answer does not depend on idle
                twin = None if done is None else done.get(k ^ 1)
                if twin is not None:
                    twin[j] = ok
                elif spread is not None:
                    spread.append((k ^ 1, j, ok))
        return free

    def _share(self, props: list[Property], todo: np.ndarray, verdicts: np.ndarray,
               gate: int) -> np.ndarray:
        """The verdicts of the keys ``todo`` (rows of ``verdicts``, filled in) evaluated once
        per ``shared`` code and idle flag, on the first key of each: a verdict whose predicate
        read nothing of that key's row is every key's of its group. Returns which keys still
        have verdicts to evaluate one by one."""
        assert self.shared is not None
        code = self.shared(todo >> 1).astype(np.int64) * 2 + (todo & 1)
        _, first, group = np.unique(code, return_index=True, return_inverse=True)
        reps = todo[first]
        values = verdicts[first]
        free = np.zeros(values.shape, dtype=bool)
        for g, s in enumerate(self.many(reps >> 1, (reps & 1).astype(bool))):
            line = values[g].tolist()
            free[g] = self._evaluate(props, gate, line, s)
            values[g] = line
        verdicts[first] = values
        copy = free[group]
        verdicts[copy] = values[group][copy]
        return np.asarray((verdicts < 0).any(axis=1))

    def first_failure(self, props: list[Property], failures: np.ndarray
                      ) -> tuple[int, Property] | None:
        """The first state (index) where one of ``props`` fails (``failures``, their columns),
        and the first such property."""
        if not len(props) or not failures.size:
            return None
        # the first failure in row-major order: its state, then its property (argmax stops
        # at the first True, where ``any(axis=1)`` reduces every short row)
        first = int(failures.argmax())
        if not failures.flat[first]:
            return None
        i, j = divmod(first, failures.shape[1])
        return i, props[j]

    def record_halt(self, sid: int, row: int, idle: bool, prop: Property) -> None:
        self.checks._record(prop, sid, self.facts(row, idle))

    def record(self, first_id: int, props: list[Property], failures: np.ndarray,
               rows: np.ndarray, idle: np.ndarray) -> None:
        """The first witness of each property of ``props`` without one yet, among states
        ``first_id, first_id + 1, ...`` (``failures``: :meth:`failures` of those states)."""
        for j, p in enumerate(props):
            if p.name in self.checks.violations:
                continue
            hit = np.flatnonzero(failures[:, j])
            if len(hit):
                i = int(hit[0])
                self.checks._record(p, first_id + i, self.facts(int(rows[i]), bool(idle[i])))

    def states(self, first_id: int, rows: np.ndarray, idle: np.ndarray,
               props: list[Property]) -> None:
        """Check state properties ``props`` on states ``first_id, first_id + 1, ...``."""
        if len(rows) and self.checks.open(props):
            self.record(first_id, props, self.failures(props, rows, idle), rows, idle)

    def value_ids(self, prop: Property, rows: np.ndarray) -> tuple[np.ndarray, list[Any]]:
        """Per row, the id of ``prop.value`` of its facts (values numbered as first seen)."""
        col, index, values = self.values.get(prop.name) or (np.empty(0, dtype=np.int32), {}, [])
        need = int(rows.max()) + 1 if len(rows) else 0
        if len(col) < need:
            grown = np.full(max(need, 2 * len(col), 1024), -1, dtype=np.int32)
            grown[:len(col)] = col
            col = grown
        self.values[prop.name] = (col, index, values)
        got = np.take(col, rows)
        unknown = got < 0
        if unknown.any():
            todo = np.unique(rows[unknown])
            if self.shared is not None:  # once per code when the value reads nothing of its row
                code = self.shared(todo)
                _, first, group = np.unique(code, return_index=True, return_inverse=True)
                free = np.zeros(len(first), dtype=bool)
                for g, r in enumerate(todo[first].tolist()):
                    col[r] = self._value_id(prop, r, index, values)
                    free[g] = not self._read_row
                spread = free[group]
                col[todo[spread]] = col[todo[first][group[spread]]]
                todo = todo[col[todo] < 0]
            for r in todo.tolist():
                col[r] = self._value_id(prop, r, index, values)
            got[unknown] = col[rows[unknown]]
        return got, values

    def _value_id(self, prop: Property, row: int, index: dict[Any, int], values: list[Any]
                  ) -> int:
        """The id of ``prop.value`` of the facts of ``row`` (a new value numbered next);
        ``_read_row`` tells whether it read a fact of its own row (with ``shared``)."""
        f = self.facts(row)
        if self.shared is not None:
            f.read_row = False
        v = prop.value(f)  # type: ignore[misc]
        self._read_row = self.shared is None or f.read_row
        if v not in index:
            index[v] = len(values)
            values.append(v)
        return index[v]

    def _dense_failures(self, p: Property, vb: np.ndarray, va: np.ndarray, values: list[Any],
                        pairs: dict[tuple[int, int], bool]) -> np.ndarray:
        """Where ``p.holds`` fails on the pairs of value ids ``(vb, va)``, through a matrix of
        verdicts (-1: not evaluated yet) kept per property: each distinct pair once."""
        matrix = self.matrices.get(p.name)
        if matrix is None:
            grown = np.full((DENSE_VALUES, DENSE_VALUES), -1, dtype=np.int8)
            for (a, b), ok in pairs.items():
                grown[a, b] = ok
            self.matrices[p.name] = matrix = grown
        at = vb * np.int32(DENSE_VALUES)  # below DENSE_VALUES**2: int32, one array
        at += va
        got = np.take(matrix.reshape(-1), at)
        if len(got) and got.min() < 0:
            for k in np.unique(at[got < 0]).tolist():
                a, b = divmod(k, DENSE_VALUES)
                pairs[a, b] = ok = bool(p.holds(values[a], values[b]))  # type: ignore[misc]
                matrix[a, b] = ok
            np.take(matrix.reshape(-1), at, out=got)
        return np.flatnonzero(got == 0)

    def transitions(self, first_id: int, src: np.ndarray, before: np.ndarray,
                    after: np.ndarray, step: Callable[[int], tuple[Event, State]]) -> None:
        """Check the transition properties on transitions from states ``first_id + src`` whose
        configurations are the rows ``before[src]`` (``before``: per source state) and
        ``after`` (in BFS and event order); ``step(i)`` gives the event and successor of the
        ``i``-th (for a witness)."""
        if not len(src):
            return
        for p in self.checks.open(self.checks.on_transition):
            vb, values = self.value_ids(p, before[:int(src[-1]) + 1])
            vb = vb[src]  # read once per source state, not once per transition
            va, values = self.value_ids(p, after)
            pairs = self.pairs.setdefault(p.name, {})
            if len(values) <= DENSE_VALUES:  # few values: a verdict matrix, no sorting
                hit = self._dense_failures(p, vb, va, values, pairs)
                if len(hit):
                    i = int(hit[0])
                    self.checks._record(p, first_id + int(src[i]), values[int(vb[i])],
                                        values[int(va[i])], step=step(i))
                continue
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
                                    values[int(va[i])], step=step(i))
