"""The certificate of ``none`` as a resolution proof, when its decision tree is too large
(SEMANTICS.md §12; the check is :mod:`gather_verify.synthesis.rup`).

The clauses are those the search learned, over the views the counterexamples meet, in the
certificate's numbering of them (its ``views`` list, in order): view ``j`` with ``m``
options has the variables ``offset(j) + 1 .. offset(j) + m``, "view ``j`` answers option
``o``". Per view, at least one option and at most one; per counterexample, not all of its
literals (:func:`clauses`). A proof that these are unsatisfiable says what the tree says:
every table has the execution of some counterexample.

:func:`refutation` asks a second solver, Glucose (python-sat, whose proofs are DRUP:
every lemma follows by unit propagation), for the proof, re-checks it and keeps its part
the empty clause depends on (:func:`~gather_verify.synthesis.rup.trim`): the lemmas, and
the counterexamples they use.

Two counterexamples, one with view 0 answering option 0, one with option 1, refute every
table; a third is not needed:

>>> refutation([{0: 0}, {0: 1}, {0: 0, 1: 1}], [2, 2], 10.0)
([0, 1], Refutation(views=[0], steps=[[]]))
"""

from __future__ import annotations

import time
from collections.abc import Sequence
from dataclasses import dataclass

from gather_verify.synthesis import rup

PROOF_SLICE = 10_000
"""Conflicts of one slice of the proof's solver call (the clock is read between slices)."""


@dataclass
class Refutation:
    """A DRUP proof over the certificate's variables, and the views (ids of the search's
    table) those variables are numbered by, in the certificate's order."""

    views: list[int]
    steps: list[list[int]]

    @property
    def lemmas(self) -> int:
        """The clauses the proof adds (its deletions left out)."""
        return sum(1 for s in self.steps if not s or s[0] != 0)


def clauses(options: Sequence[int], literals: Sequence[dict[int, int]]
            ) -> tuple[int, list[list[int]]]:
    """The variables (how many) and the clauses over views ``0 .. len(options) - 1``: per
    view at least one option and at most one, then per counterexample's literals (view ->
    option) the clause "not all of them"."""
    offset = [0]
    for m in options:
        offset.append(offset[-1] + m)
    out: list[list[int]] = []
    for j, m in enumerate(options):
        xs = [offset[j] + o + 1 for o in range(m)]
        out.append(xs)
        out += [[-xs[a], -xs[b]] for a in range(m) for b in range(a + 1, m)]
    for lits in literals:
        out.append(sorted(-(offset[k] + o + 1) for k, o in lits.items()))
    return offset[-1], out


def refutation(literals: Sequence[dict[int, int]], options: Sequence[int], seconds: float
               ) -> tuple[list[int], Refutation] | None:
    """A proof that no table escapes every counterexample (``literals``: per counterexample,
    view -> option, in the search's view ids; ``options``: per view id, its options): the
    counterexamples it uses (indices into ``literals``) and the proof over the views those
    meet. None when the solver did not finish within ``seconds``, or its proof did not
    re-check (then no certificate is given in this form)."""
    used = sorted({k for lits in literals for k in lits})
    number = {k: j for j, k in enumerate(used)}
    nvars, cnf = clauses([options[k] for k in used],
                         [{number[k]: o for k, o in lits.items()} for lits in literals])
    steps = _solve(cnf, time.perf_counter() + seconds)
    if steps is None:
        return None
    trimmed = rup.trim(nvars, cnf, steps)
    if trimmed is None:
        return None
    core, proof = trimmed
    fixed = len(cnf) - len(literals)
    kept = sorted(j - fixed for j in core if j >= fixed)
    # every view a lemma names stays listed: one counterexample that meets it comes along
    offset = [0]
    for k in used:
        offset.append(offset[-1] + options[k])
    view_of = [j for j, k in enumerate(used) for _ in range(options[k])]
    met = {number[k] for c in kept for k in literals[c]}
    for step in proof:
        for lit in step[1:] if step and step[0] == 0 else step:
            j = view_of[abs(lit) - 1]
            if j not in met:
                c = next(c for c, lits in enumerate(literals) if used[j] in lits)
                kept.append(c)
                met |= {number[k] for k in literals[c]}
    kept.sort()
    views = sorted({k for c in kept for k in literals[c]})
    new_offset = {k: 0 for k in views}
    total = 0
    for k in views:
        new_offset[k] = total
        total += options[k]

    def renumber(lit: int) -> int:
        j = view_of[abs(lit) - 1]
        v = new_offset[used[j]] + abs(lit) - offset[j]
        return v if lit > 0 else -v

    return kept, Refutation(views, [[0, *map(renumber, s[1:])] if s and s[0] == 0 else
                                    [renumber(x) for x in s] for s in proof])


def _solve(cnf: list[list[int]], until: float) -> list[list[int]] | None:
    """Glucose's DRUP proof that ``cnf`` is unsatisfiable, its lemmas only (its deletions
    left out: it deletes clauses a unit it never wrote down relied on, which a check from
    scratch cannot follow), ending with the empty clause; None past ``until`` or if ``cnf``
    is satisfiable."""
    from pysat.solvers import Solver

    with Solver(name="glucose4", bootstrap_with=cnf, with_proof=True) as solver:
        while True:
            solver.conf_budget(PROOF_SLICE)
            got = solver.solve_limited()
            if got is not None:
                break
            if time.perf_counter() >= until:
                return None
        if got:
            return None
        lines = solver.get_proof()
    out = []
    for line in lines:
        words = line.split()
        if words and words[0] != "d":
            out.append([int(w) for w in words[:-1]])
    if [] not in out:  # a conflict among the input clauses alone: the proof writes nothing
        out.append([])
    return out
