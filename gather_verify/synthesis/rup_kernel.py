"""The compiled check of a DRUP proof (:mod:`gather_verify.synthesis.rup`): two watched
literals per clause, linked lists of watchers per literal, and every lemma checked from no
assignment at all (so a deletion never leaves a stale unit behind).

Literal codes: ``2 (v - 1)`` for ``v`` and that plus 1 for ``-v`` (the negation flips the
low bit). Imported only when a proof is checked: numba costs a quarter of a second to load.
"""

import numpy as np
from numba import njit

ADD, DELETE = 1, 2
"""The kinds of step (0: a deletion that matches no clause, skipped)."""
NOT_RUP, NO_EMPTY, FULL = 1, 2, 3
"""The answers beside 0 (the empty clause was derived): a step that is not RUP, a proof that
ends without the empty clause, the dependency buffer full (grown and rerun)."""


@njit(cache=True, nogil=True)
def check_steps(nvars, lits, starts, nbase, kinds, ids, want, buf, offsets
                 ):  # pragma: no cover - compiled
    """The DRUP check (numba-compatible): two watched literals per clause, linked lists of
    watchers per literal, every check propagating from no assignment at all. Returns
    (status, step, the step of the empty clause)."""
    nclauses = len(starts) - 1
    val = np.zeros(2 * nvars, dtype=np.int8)
    reason = np.full(nvars, -1, dtype=np.int64)
    trail = np.empty(nvars, dtype=np.int64)
    seen = np.zeros(nvars, dtype=np.bool_)
    stack = np.empty(nvars, dtype=np.int64)
    alive = np.zeros(nclauses, dtype=np.bool_)
    head = np.full(2 * nvars, -1, dtype=np.int64)
    nxt = np.full(2 * nclauses, -1, dtype=np.int64)
    units = np.empty(nclauses, dtype=np.int64)
    nunits = 0
    used = 0
    for c in range(nbase):
        nunits = _insert(c, lits, starts, alive, head, nxt, units, nunits)
        if starts[c + 1] == starts[c]:
            return 0, -1, -1
    for s in range(len(kinds)):
        offsets[s + 1] = used
        c = ids[s]
        if kinds[s] == DELETE:
            alive[c] = False
            continue
        if kinds[s] != ADD:
            continue
        # every literal of the lemma false, the units of the database true, then propagate
        ntrail = 0
        conflict = -1
        culprit = -1
        for j in range(nunits):
            u = units[j]
            if not alive[u]:
                continue
            lit = lits[starts[u]]
            if val[lit] == -1:
                conflict = u
                break
            if val[lit] == 0:
                val[lit], val[lit ^ 1] = 1, -1
                reason[lit >> 1] = u
                trail[ntrail] = lit
                ntrail += 1
        if conflict < 0:
            for i in range(starts[c], starts[c + 1]):
                lit = lits[i] ^ 1  # the lemma's literal, made false
                if val[lit] == -1:
                    culprit = lit >> 1
                    break
                if val[lit] == 0:
                    val[lit], val[lit ^ 1] = 1, -1
                    trail[ntrail] = lit
                    ntrail += 1
        if conflict < 0 and culprit < 0:
            conflict, ntrail = _propagate(lits, starts, alive, head, nxt, val, reason, trail,
                                          ntrail)
        if conflict < 0 and culprit < 0:
            return NOT_RUP, s, -1
        if want:
            used = _dependencies(conflict, culprit, lits, starts, reason, seen, stack, buf,
                                 used)
            if used < 0:
                return FULL, s, -1
            offsets[s + 1] = used
        for j in range(ntrail):
            lit = trail[j]
            val[lit] = 0
            val[lit ^ 1] = 0
            reason[lit >> 1] = -1
        if starts[c + 1] == starts[c]:
            return 0, s, s
        nunits = _insert(c, lits, starts, alive, head, nxt, units, nunits)
    return NO_EMPTY, -1, -1


@njit(cache=True, nogil=True)
def _insert(c, lits, starts, alive, head, nxt, units, nunits):  # pragma: no cover - compiled
    """Clause ``c`` into the database: its first two literals watched, or a unit."""
    alive[c] = True
    size = starts[c + 1] - starts[c]
    if size == 1:
        units[nunits] = c
        return nunits + 1
    if size >= 2:
        for slot in range(2):
            lit = lits[starts[c] + slot]
            nxt[2 * c + slot] = head[lit]
            head[lit] = 2 * c + slot
    return nunits


@njit(cache=True, nogil=True)
def _propagate(lits, starts, alive, head, nxt, val, reason, trail, ntrail
               ):  # pragma: no cover - compiled
    """Unit propagation from the literals on the trail: (a clause all false, or -1; the
    trail's new length)."""
    qhead = 0
    while qhead < ntrail:
        false = trail[qhead] ^ 1
        qhead += 1
        prev = -1
        e = head[false]
        while e != -1:
            c, slot = e >> 1, e & 1
            after = nxt[e]
            if not alive[c]:  # a deleted clause leaves the list lazily
                if prev == -1:
                    head[false] = after
                else:
                    nxt[prev] = after
                e = after
                continue
            other = lits[starts[c] + 1 - slot]
            if val[other] == 1:
                prev = e
                e = after
                continue
            moved = False
            for i in range(starts[c] + 2, starts[c + 1]):
                lit = lits[i]
                if val[lit] != -1:  # watch it instead
                    lits[i] = false
                    lits[starts[c] + slot] = lit
                    if prev == -1:
                        head[false] = after
                    else:
                        nxt[prev] = after
                    nxt[e] = head[lit]
                    head[lit] = e
                    moved = True
                    break
            if not moved:
                if val[other] == -1:
                    return c, ntrail
                val[other], val[other ^ 1] = 1, -1
                reason[other >> 1] = c
                trail[ntrail] = other
                ntrail += 1
                prev = e
            e = after
    return -1, ntrail


@njit(cache=True, nogil=True)
def _dependencies(conflict, culprit, lits, starts, reason, seen, stack, buf, used
                  ):  # pragma: no cover - compiled
    """The clauses of the conflict's implication graph appended to ``buf`` from ``used``
    (the new end, or -1 when ``buf`` is full)."""
    top = 0
    if conflict >= 0:
        if used >= len(buf):
            return -1
        buf[used] = conflict
        used += 1
        for i in range(starts[conflict], starts[conflict + 1]):
            v = lits[i] >> 1
            if not seen[v]:
                seen[v] = True
                stack[top] = v
                top += 1
    else:
        seen[culprit] = True
        stack[top] = culprit
        top += 1
    marked = 0
    while top > 0:
        top -= 1
        v = stack[top]
        marked += 1
        r = reason[v]
        if r < 0:
            continue
        if used >= len(buf):
            return -1
        buf[used] = r
        used += 1
        for i in range(starts[r], starts[r + 1]):
            w = lits[i] >> 1
            if not seen[w]:
                seen[w] = True
                stack[top] = w
                top += 1
    # clear the marks: every marked variable was pushed once
    for i in range(len(seen)):
        if marked == 0:
            break
        if seen[i]:
            seen[i] = False
            marked -= 1
    return used
