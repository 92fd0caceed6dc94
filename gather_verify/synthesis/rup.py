"""A refutation by reverse unit propagation (RUP): the compact form of a certificate of
``none`` (SEMANTICS.md §12) when its decision tree grows too large.

The certificate's claim is that no table (one option per view) escapes every
counterexample. As clauses over the variables "view k takes option o": per view, at least
one option and at most one; per counterexample, "not all of its literals". A decision tree
proves these clauses unsatisfiable by trying every table, path by path: a tree-like
refutation, which can be exponentially larger than a general (DAG-like) one. The SAT
solver's own proof is such a general refutation, as a list of steps (DRUP, as
``drat-trim`` reads it):

- a *lemma* (a clause) is added once it follows by unit propagation: with every literal of
  the lemma false, unit propagation over the clauses held so far reaches a conflict. Then
  every assignment that satisfies those clauses satisfies the lemma;
- a *deletion* drops a clause (fewer clauses: whatever follows still followed before).

The proof holds once it adds the empty clause: nothing satisfies the clauses, so every
table meets a counterexample, as with the tree. :func:`check` re-checks every step, in
compiled code (numba, :mod:`~gather_verify.synthesis.rup_kernel`). :func:`trim` keeps only
the lemmas the empty clause depends on, and the counterexamples they use, so that a
certificate carries the part of the solver's proof that matters.

Literals are DIMACS integers (``v`` or ``-v``, ``v`` from 1); a deletion step is written
with a leading 0.

>>> base = [[1, 2], [-1, 2], [1, -2], [-1, -2]]
>>> check(2, base, [[1], []]).holds
True
>>> check(2, base, [[]]).step  # the empty clause does not follow by unit propagation alone
0
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field

import numpy as np


@dataclass
class Checked:
    """What :func:`check` found: whether the proof derives the empty clause; if not, the
    step that fails (-1: every step holds, the empty clause is missing) and why; with
    ``deps``, per added lemma the clauses (base ids, then lemmas by step) its propagation
    used."""

    holds: bool
    step: int = -1
    why: str = ""
    last: int = -1
    """The step that added the empty clause."""
    deps: dict[int, list[int]] = field(default_factory=dict)
    clause_of_step: list[int] = field(default_factory=list)


def _encode(nvars: int, clauses: Sequence[Sequence[int]]) -> tuple[np.ndarray, np.ndarray]:
    """The clauses as one flat array of literal codes (``2 (v - 1)`` for ``v``, plus 1 for
    ``-v``), each clause's literals once, and their offsets."""
    flat: list[int] = []
    starts = [0]
    for clause in clauses:
        for lit in dict.fromkeys(clause):
            v = abs(lit)
            if not isinstance(lit, int) or isinstance(lit, bool) or not 1 <= v <= nvars:
                raise ValueError(f"literal {lit!r} is not a variable 1..{nvars}")
            flat.append(2 * (v - 1) + (lit < 0))
        starts.append(len(flat))
    return np.array(flat, dtype=np.int64), np.array(starts, dtype=np.int64)


def _steps(base: Sequence[Sequence[int]], steps: Sequence[Sequence[int]]
           ) -> tuple[list[list[int]], np.ndarray, np.ndarray]:
    """Every clause (base, then each lemma) and, per step, its kind and its clause: a
    deletion names the latest live clause with the same literals (one that matches none is
    left out: keeping a clause only keeps what follows)."""
    from gather_verify.synthesis.rup_kernel import ADD, DELETE

    clauses = [list(c) for c in base]
    live: dict[frozenset[int], list[int]] = {}
    for j, c in enumerate(clauses):
        live.setdefault(frozenset(c), []).append(j)
    kinds, ids = [], []
    for step in steps:
        if step and step[0] == 0:
            got = live.get(frozenset(step[1:]))
            if got:
                kinds.append(DELETE)
                ids.append(got.pop())
            else:
                kinds.append(0)
                ids.append(-1)
            continue
        live.setdefault(frozenset(step), []).append(len(clauses))
        kinds.append(ADD)
        ids.append(len(clauses))
        clauses.append(list(step))
    return clauses, np.array(kinds, dtype=np.int64), np.array(ids, dtype=np.int64)


def check(nvars: int, base: Sequence[Sequence[int]], steps: Sequence[Sequence[int]],
          deps: bool = False) -> Checked:
    """Re-check a DRUP proof that ``base`` (clauses over variables 1..``nvars``) is
    unsatisfiable: each lemma must follow by unit propagation, and one must be the empty
    clause (the check stops there). ``deps``: also record what each lemma used
    (:func:`trim`). :class:`ValueError` for a literal out of range."""
    from gather_verify.synthesis.rup_kernel import ADD, FULL, NO_EMPTY, NOT_RUP, check_steps

    clauses, kinds, ids = _steps(base, steps)
    lits, starts = _encode(nvars, clauses)
    empty = next((j for j, c in enumerate(base) if not c), None)
    if empty is not None:  # nothing to prove: no assignment satisfies the empty clause
        return Checked(True, last=-1, clause_of_step=[empty])
    size = 1 << 16
    while True:
        buf = np.empty(size if deps else 1, dtype=np.int64)
        offsets = np.zeros(len(kinds) + 1, dtype=np.int64)
        status, at, last = check_steps(nvars, lits, starts, len(base), kinds, ids, deps, buf,
                                       offsets)
        if status != FULL:
            break
        size *= 4
    out = Checked(status == 0, -1 if status in (0, NO_EMPTY) else int(at),
                  {0: "", NOT_RUP: "the lemma does not follow by unit propagation",
                   NO_EMPTY: "the proof never adds the empty clause"}[int(status)],
                  int(last), clause_of_step=[int(i) for i in ids])
    if deps and status == 0:
        for s in range(int(last) + 1):
            if kinds[s] == ADD:
                out.deps[s] = [int(x) for x in buf[offsets[s]:offsets[s + 1]]]
    return out


def trim(nvars: int, base: Sequence[Sequence[int]], steps: Sequence[Sequence[int]]
         ) -> tuple[list[int], list[list[int]]] | None:
    """The part of a proof that matters: the base clauses (ids) the empty clause depends on,
    and the lemmas it depends on, in order, each clause deleted after its last use, with the
    base renumbered to those clauses only. None when the proof does not hold."""
    got = check(nvars, base, steps, deps=True)
    if not got.holds:
        return None
    if got.last < 0:
        return got.clause_of_step, []
    nbase = len(base)
    step_of = {got.clause_of_step[s]: s for s in got.deps}
    needed = {got.clause_of_step[got.last]}
    for s in range(got.last, -1, -1):
        c = got.clause_of_step[s]
        if s in got.deps and c in needed:
            needed.update(got.deps[s])
    last_use: dict[int, int] = {}
    for s in sorted(got.deps):
        if got.clause_of_step[s] in needed:
            for d in got.deps[s]:
                last_use[d] = s
    core = sorted(c for c in needed if c < nbase)
    lemmas = {c: list(steps[step_of[c]]) for c in needed if c >= nbase}
    drop: dict[int, list[int]] = {}
    for c, s in last_use.items():
        if s != got.last:
            drop.setdefault(s, []).append(c)
    out: list[list[int]] = []
    for s in sorted(step_of[c] for c in lemmas):
        out.append(lemmas[got.clause_of_step[s]])
        for c in sorted(drop.get(s, ())):
            clause = list(base[c]) if c < nbase else lemmas[c]
            if clause:
                out.append([0, *clause])
    return core, out
