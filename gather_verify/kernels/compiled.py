"""The numba-compiled kernels themselves (see :mod:`gather_verify.kernels`, which imports this
module on first use, so that importing the project does not import numba).

>>> import numpy as np
>>> table, keys = np.zeros(16, dtype=np.int32), np.empty(8, dtype=np.uint64)
>>> ids, first = np.empty(3, dtype=np.int32), np.empty(3, dtype=np.int32)
>>> q, local = np.array([5, 2, 5], dtype=np.uint64), np.empty(8, dtype=np.int32)
>>> find_or_add(table, keys, 0, np.uint64(60), 24, q, ids, first, local)
(2, 2)
>>> ids.tolist(), first[:2].tolist(), keys[:2].tolist()
([0, 1, 0], [0, 1], [5, 2])
"""

from __future__ import annotations

import numpy as np
from llvmlite import ir
from numba import njit, types
from numba.core import cgutils
from numba.extending import intrinsic

from gather_verify.kernels.codes import OUTSIDE
from gather_verify.kernels.codes import Z2_DEGREE as DEGREE
from gather_verify.kernels.codes import Z2_SLOTS as SLOTS

_MUL = np.uint64(0x9E3779B97F4A7C15)
_AHEAD = 32
"""How many keys ahead :func:`find_or_add` requests the memory it will read."""


@intrinsic
def prefetch(typingctx, array, index):  # pragma: no cover - compiled
    """Ask the processor to bring ``array[index]`` into the cache (a hint: no effect on the
    result; ``index`` must be inside the array)."""
    sig = types.void(array, index)

    def codegen(context, builder, signature, args):
        aryty = signature.args[0]
        ary = context.make_array(aryty)(context, builder, args[0])
        ptr = cgutils.get_item_pointer(context, builder, aryty, ary, [args[1]],
                                       wraparound=False)
        byte = ir.PointerType(ir.IntType(8))
        i32 = ir.IntType(32)
        fn = cgutils.get_or_insert_function(
            builder.module, ir.FunctionType(ir.VoidType(), [byte, i32, i32, i32]),
            "llvm.prefetch.p0i8")
        # read, high temporal locality, data cache
        builder.call(fn, [builder.bitcast(ptr, byte), ir.Constant(i32, 0), ir.Constant(i32, 3),
                          ir.Constant(i32, 1)])
        return context.get_dummy_value()

    return sig, codegen


# -- the hash index ----------------------------------------------------------------------

@njit(inline="always")
def _slot_tag(k, shift, idbits):  # pragma: no cover - compiled
    """A key's home slot in the index (the top bits of its hash) and its tag: the
    ``31 - idbits`` hash bits below those, kept in a slot above its ``id + 1``."""
    h = k * _MUL
    tag = np.int32((h >> (shift - np.uint64(31 - idbits))) & np.uint64((1 << (31 - idbits)) - 1))
    return np.int64(h >> shift), tag


@njit(cache=True, nogil=True)
def find_or_add(table, keys, count, shift, idbits, q, ids, first,
                local):  # pragma: no cover - compiled
    """Ids of the keys ``q`` in a linear-probing table over the key column ``keys`` (ids
    ``0 .. count - 1``); absent keys get the next ids in order of first occurrence
    (``first``: their positions in ``q``). Returns the new count and how many were added.
    ``shift``: 64 - log2(len(table)); the table must have room for them all.

    A slot holds ``tag << idbits | id + 1`` (0: empty): while the ids fit ``idbits = 24``
    bits, 7 more bits of the key's hash (:func:`_slot_tag`) tell most other keys' slots
    apart without reading their stored key (a miss in the cache); with ``idbits = 31`` no
    tag, every occupied slot's key is compared.

    Two passes. A key met earlier in ``q`` takes that occurrence's id: ``local``, a
    linear-probing table of positions in ``q`` plus one (a power of two at least twice
    ``len(q)``, zeroed here), small enough to stay in the cache, finds it. The keys met
    first are then looked up in ``table`` in order, the memory each will read requested
    ahead (prefetch): the table slot of the key ``_AHEAD`` on, and the stored key that the
    slot of the key half as far on names, so the processor's loads overlap. A bulk step's
    successors repeat (two robots' moves in either order): on the bench instance two in
    three are met earlier in their chunk, and only the first goes to ``table``."""
    mask = len(table) - 1
    idmask = (1 << idbits) - 1
    m = len(q)
    lmask = len(local) - 1
    bits = 0
    while (1 << bits) < len(local):
        bits += 1
    lshift = np.uint64(64 - bits)
    local[:] = 0
    nu = 0  # the first occurrences, their positions in first[:nu] (reused below)
    for i in range(m):
        k = q[i]
        s = np.int64((k * _MUL) >> lshift)
        while True:
            j = local[s]
            if j == 0:
                local[s] = i + 1
                first[nu] = i
                nu += 1
                break
            if q[j - 1] == k:
                ids[i] = -j  # met at j - 1: its id once known
                break
            s = (s + 1) & lmask
    added = 0
    half = _AHEAD // 2
    for u in range(min(_AHEAD, nu)):
        prefetch(table, np.int64((q[first[u]] * _MUL) >> shift))
    for u in range(nu):
        if u + _AHEAD < nu:
            prefetch(table, np.int64((q[first[u + _AHEAD]] * _MUL) >> shift))
        if u + half < nu:
            s, tag = _slot_tag(q[first[u + half]], shift, idbits)
            ahead = table[s]
            if ahead != 0 and ahead >> idbits == tag:
                prefetch(keys, (ahead & idmask) - 1)
        i = first[u]  # read before first[added] (added <= u) is written
        k = q[i]
        s, tag = _slot_tag(k, shift, idbits)
        while True:
            t = table[s]
            if t == 0:
                table[s] = (tag << idbits) | (count + 1)
                keys[count] = k
                ids[i] = count
                first[added] = i
                added += 1
                count += 1
                break
            if t >> idbits == tag and keys[(t & idmask) - 1] == k:
                ids[i] = (t & idmask) - 1
                break
            s = (s + 1) & mask
    for i in range(m):
        if ids[i] < 0:
            ids[i] = ids[-ids[i] - 1]
    return count, added


@njit(cache=True, nogil=True)
def place(table, keys, lo, hi, shift, idbits):  # pragma: no cover - compiled
    """Put the distinct keys ``keys[lo:hi]`` (absent from the table) in it, with their ids
    and tags (:func:`find_or_add`'s slots); the slot of the key ``_AHEAD`` places on
    requested ahead (prefetch), as there."""
    mask = len(table) - 1
    for i in range(lo, min(hi, lo + _AHEAD)):
        prefetch(table, np.int64((keys[i] * _MUL) >> shift))
    for i in range(lo, hi):
        if i + _AHEAD < hi:
            prefetch(table, np.int64((keys[i + _AHEAD] * _MUL) >> shift))
        s, tag = _slot_tag(keys[i], shift, idbits)
        while table[s] != 0:
            s = (s + 1) & mask
        table[s] = (tag << idbits) | (i + 1)


# -- the ASYNC scheduler's bulk step -----------------------------------------------------

@njit(cache=True, nogil=True, inline="always")
def _async_events(codes, masks, neighbour, look_order, src, weight, robot, new,
                  fill):  # pragma: no cover - compiled
    """:func:`async_successors`'s events, counted (``fill`` false) or written into the
    arrays (``fill`` true); returns how many."""
    s_count, n = codes.shape
    e = 0
    for s in range(s_count):
        for i in range(n):
            c = codes[s, i]
            if c % SLOTS == 0:
                m = masks[s, i]
                for j in range(DEGREE):
                    k = look_order[j]
                    if (m >> k) & 1:
                        if fill:
                            src[e] = s
                            robot[e] = i
                            new[e] = c + 1 + k
                        e += 1
            else:
                if fill:
                    cell = c // SLOTS
                    dest = neighbour[cell, c - cell * SLOTS - 1]
                    src[e] = s
                    robot[e] = i
                    new[e] = dest * SLOTS if dest >= 0 else OUTSIDE
                    weight[e] = 1
                e += 1
    return e


@njit(cache=True, nogil=True)
def async_successors(codes, masks, neighbour, look_order):  # pragma: no cover - compiled
    """Every event of the states ``codes`` (robots ``cell * SLOTS + d``) in the order of
    ``Async.successors``: per robot, its Looks (idle: one per step of its move mask, in
    ``look_order``) or its Move (pending). Returns (source, weight, robot, new code;
    ``OUTSIDE`` when the Move leaves the region), ``int32`` but the weight (``int8``): a bulk
    step's largest arrays, a chunk's states, robots and codes fit."""
    none = np.empty(0, dtype=np.int32)
    total = _async_events(codes, masks, neighbour, look_order, none, np.empty(0, np.int8),
                          none, none, False)
    src = np.empty(total, dtype=np.int32)
    weight = np.zeros(total, dtype=np.int8)
    robot = np.empty(total, dtype=np.int32)
    new = np.empty(total, dtype=np.int32)
    _async_events(codes, masks, neighbour, look_order, src, weight, robot, new, True)
    return src, weight, robot, new


# -- the round schedulers' bulk step (FSYNC, SSYNC, centralized) ---------------------

@njit(cache=True, nogil=True)
def round_counts(masks, subsets, count, budget):  # pragma: no cover - compiled
    """How many leading states of ``masks`` (robots' move masks) the round events take: those
    whose events, counted from the first state, stay within ``budget`` (at least one); and
    their events and changes. An event activates the robots of one row of ``subsets`` (a
    boolean ``(k, n)`` matrix), each with one of its ``count[mask]`` choices; a change is an
    activated robot whose choice is a step (every choice but staying, bit ``DEGREE``)."""
    s_count, n = masks.shape
    k = subsets.shape[0]
    taken = 0
    events = 0
    changes = 0
    for s in range(s_count):
        ev = 0
        ch = 0
        for a in range(k):
            per = 1
            for i in range(n):
                if subsets[a, i]:
                    per *= count[masks[s, i]]
            if per == 0:
                continue
            ev += per
            for i in range(n):
                if subsets[a, i]:
                    m = masks[s, i]
                    ch += (count[m] - ((m >> DEGREE) & 1)) * (per // count[m])
        if s > 0 and events + ev > budget:
            break
        taken = s + 1
        events += ev
        changes += ch
    return taken, events, changes


@njit(cache=True, nogil=True, inline="always")
def _state_choices(codes, masks, neighbour, nth, count, s, choice, step):  # pragma: no cover
    """Each robot's choices in state ``s``, in the order of ``nth[mask]``: its new code
    (``OUTSIDE`` when the step leaves the region; its own cell's idle code when it stays)
    into ``choice[i, j]``, and whether that choice is a step into ``step[i, j]``."""
    for i in range(codes.shape[1]):
        cell = codes[s, i] // SLOTS
        m = masks[s, i]
        for j in range(count[m]):
            kk = nth[m, j]
            if kk < DEGREE:
                dest = neighbour[cell, kk]
                choice[i, j] = dest * SLOTS if dest >= 0 else OUTSIDE
                step[i, j] = True
            else:
                choice[i, j] = cell * SLOTS
                step[i, j] = False


@njit(cache=True, nogil=True, inline="always")
def _round_robots(subsets, a, masks, s, count, active, width, digit):  # pragma: no cover
    """The robots that round ``a`` activates in state ``s`` (into ``active``), each with its
    number of choices (``width``) and its first choice (``digit``); how many, or -1 when
    one of them has no choice (the round does not exist)."""
    size = 0
    empty = False
    for i in range(subsets.shape[1]):
        if subsets[a, i]:
            w = count[masks[s, i]]
            active[size] = i
            width[size] = w
            digit[size] = 0
            size += 1
            if w == 0:
                empty = True
    return -1 if empty else size


@njit(cache=True, nogil=True, inline="always")
def _next_choice(digit, width, size):  # pragma: no cover - compiled
    """Move ``digit`` to the round's next joint choice (the last robot varies fastest);
    False after the last."""
    t = size - 1
    while t >= 0:
        digit[t] += 1
        if digit[t] < width[t]:
            return True
        digit[t] = 0
        t -= 1
    return False


@njit(cache=True, nogil=True, inline="always")
def _rounds(codes, masks, neighbour, subsets, nth, count, states, keys, powers, src, weight,
            robot, new, event, succ, keyed):  # pragma: no cover - compiled
    """The round events of the first ``states`` states (see :func:`round_events`): with
    ``keyed`` each event's successor key into ``succ``, stopping after the first event in
    which a robot leaves the region (:func:`round_keys`); else each event's changes into
    ``robot``, ``new`` and ``event``. Returns how many events and whether the last leaves."""
    n = codes.shape[1]
    k = subsets.shape[0]
    choice = np.empty((n, SLOTS), dtype=np.int64)  # robot i's new code for its j-th choice
    step = np.empty((n, SLOTS), dtype=np.bool_)  # whether that choice is a step
    delta = np.zeros((n, SLOTS), dtype=np.uint64)  # the key's change for that choice
    leave = np.zeros((n, SLOTS), dtype=np.bool_)  # whether that step leaves the region
    active = np.empty(n, dtype=np.int64)
    width = np.empty(n, dtype=np.int64)
    digit = np.empty(n, dtype=np.int64)
    e = 0
    c = 0
    base = np.uint64(0)
    for s in range(states):
        _state_choices(codes, masks, neighbour, nth, count, s, choice, step)
        if keyed:
            for i in range(n):
                code = codes[s, i]
                for j in range(count[masks[s, i]]):
                    leave[i, j] = choice[i, j] == OUTSIDE
                    delta[i, j] = 0
                    if not leave[i, j]:
                        delta[i, j] = np.uint64(choice[i, j] - code) * powers[i]  # wraps
            base = keys[s]
        for a in range(k):
            size = _round_robots(subsets, a, masks, s, count, active, width, digit)
            if size < 0:  # an activated robot with no choice: no such round
                continue
            while True:
                moved = 0
                key = base
                leaves = False
                for t in range(size):
                    i = active[t]
                    j = digit[t]
                    if step[i, j]:
                        moved += 1
                        if keyed:
                            key += delta[i, j]
                            leaves |= leave[i, j]
                        else:
                            robot[c] = i
                            new[c] = choice[i, j]
                            event[c] = e
                            c += 1
                src[e] = s
                weight[e] = moved
                if keyed:
                    succ[e] = key
                e += 1
                if leaves:
                    return e, True
                if not _next_choice(digit, width, size):
                    break
    return e, False


@njit(cache=True, nogil=True)
def round_events(codes, masks, neighbour, subsets, nth, count, states, src, weight, robot, new,
                 event):  # pragma: no cover - compiled
    """The round events of the first ``states`` states of ``codes`` into the arrays sized by
    :func:`round_counts`, in the order of ``schedulers.base.bulk_rounds``: per state, per row
    of ``subsets``, every choice of the activated robots (robot j's choices in the order of
    ``nth[mask]``, the last robot varying fastest). Per event its source and weight (the
    robots that step); per change (the robots that step, in robot order) its event, robot and
    new code (``OUTSIDE`` when it leaves the region)."""
    _rounds(codes, masks, neighbour, subsets, nth, count, states, np.zeros(1, np.uint64),
            np.zeros(codes.shape[1], np.uint64), src, weight, robot, new, event,
            np.zeros(1, np.uint64), False)


@njit(cache=True, nogil=True)
def round_keys(keys, codes, masks, neighbour, subsets, nth, count, states, powers, src, weight,
               succ):  # pragma: no cover - compiled
    """:func:`round_events` and :func:`event_keys` in one pass, without the changes: per event
    of the first ``states`` states (in :func:`round_events`' order, into arrays sized by
    :func:`round_counts`) its source, its weight and its successor's key (``keys[s]``, the
    key of state s with digit ``powers``, with each stepping robot recoded). Stops after the
    first event in which a robot leaves the region (a step to ``OUTSIDE``; that event's key
    is not one). Returns how many events it wrote and whether the last one leaves."""
    none = np.zeros(1, np.int64)
    return _rounds(codes, masks, neighbour, subsets, nth, count, states, keys, powers, src,
                   weight, none, none, none, succ, True)


# -- graph analyses over the kept CSR graph ----------------------------------------------

@njit(cache=True, nogil=True, inline="always")
def _weight(weights, j, bits):  # pragma: no cover - compiled
    """The weight of edge ``j``: a byte per edge, or with ``bits`` one bit per edge (bit
    ``j % 8`` of byte ``j // 8``, the layout of ``np.packbits(..., bitorder="little")``)."""
    if bits:
        return np.int64((weights[j >> 3] >> (j & 7)) & 1)
    return np.int64(weights[j])


@njit(cache=True, nogil=True, inline="always")
def _target(targets, j, packed):  # pragma: no cover - compiled
    """The target of edge ``j``: an ``int32`` per edge, or with ``packed`` three bytes per
    edge, least significant first (ids below ``2**24``: ``engine.columns.IdColumn``)."""
    if packed:
        k = 3 * j
        return np.int64(targets[k]) | np.int64(targets[k + 1]) << 8 | \
            np.int64(targets[k + 2]) << 16
    return np.int64(targets[j])


@njit(cache=True, nogil=True)
def longest_path(offsets, targets, weights, bits=False, packed=False):  # pragma: no cover
    """The best total weight from every state over the graph (self-loops left out), by an
    iterative depth-first search from state 0 (every state is reachable from it), each edge
    read once: a finished successor's total is taken when its edge is read (or when it
    finishes, for the edge that led to it); -1 as the first value when a cycle exists.
    ``best`` is int32: a move count. ``weights``: a byte per edge, or with ``bits`` one bit
    per edge (:func:`_weight`); ``targets``: with ``packed``, three bytes each (:func:`_target`).

    When every edge leads to a larger id (breadth-first ids often are a topological order:
    every edge goes one level down), one sweep in decreasing id order, reading the edges in
    place, gives the same totals with no search and no cycle."""
    n = len(offsets) - 1
    forward = True
    for v in range(n):
        for j in range(offsets[v], offsets[v + 1]):
            if _target(targets, j, packed) < v:
                forward = False
                break
        if not forward:
            break
    if forward:
        best = np.zeros(n, dtype=np.int32)
        for v in range(n - 1, -1, -1):
            run = 0
            for j in range(offsets[v], offsets[v + 1]):
                t = _target(targets, j, packed)
                if t != v:
                    val = _weight(weights, j, bits) + best[t]
                    if val > run:
                        run = val
            best[v] = run
        return best
    best = np.full(n, -1, dtype=np.int32)  # -1: unvisited, -2: on the DFS stack
    stack = np.empty(64, dtype=np.int64)
    edge = np.empty(64, dtype=np.int64)
    top = np.empty(64, dtype=np.int64)  # the best total so far of the state at each depth
    for root in range(n):
        if best[root] != -1:
            continue
        depth = 0
        stack[0] = root
        edge[0] = offsets[root]
        top[0] = 0
        best[root] = -2
        while depth >= 0:
            v = stack[depth]
            k = edge[depth]
            end = offsets[v + 1]
            run = top[depth]
            pushed = False
            while k < end:
                t = _target(targets, k, packed)
                k += 1
                if t == v:
                    continue
                bt = best[t]
                if bt == -2:
                    out = np.full(1, -1, dtype=np.int32)
                    return out
                if bt == -1:
                    edge[depth] = k
                    top[depth] = run
                    depth += 1
                    if depth == len(stack):
                        stack = np.concatenate((stack, np.empty(len(stack), dtype=np.int64)))
                        edge = np.concatenate((edge, np.empty(len(edge), dtype=np.int64)))
                        top = np.concatenate((top, np.empty(len(top), dtype=np.int64)))
                    stack[depth] = t
                    edge[depth] = offsets[t]
                    top[depth] = 0
                    best[t] = -2
                    pushed = True
                    break
                val = _weight(weights, k - 1, bits) + bt
                if val > run:
                    run = val
            if pushed:
                continue
            best[v] = run
            depth -= 1
            if depth >= 0:  # the edge that led to v is the one before the parent's position
                val = _weight(weights, edge[depth] - 1, bits) + run
                if val > top[depth]:
                    top[depth] = val
    return best


@njit(cache=True, nogil=True)
def first_sources(offsets, targets, seeds, states, packed=False):  # pragma: no cover
    """Per state, the first state in id and edge order with an edge to it (-1 for the
    ``seeds`` first ids, and for a state no edge reaches): the breadth-first parents, which
    a search that keeps its edges need not store (a state is discovered by its first
    incoming edge, :func:`gather_verify.engine.columns.first_sources`); ``packed``: as
    :func:`longest_path`'s."""
    parents = np.full(states, -1, dtype=np.int32)
    for v in range(len(offsets) - 1):
        for j in range(offsets[v], offsets[v + 1]):
            t = _target(targets, j, packed)
            if t >= seeds and parents[t] < 0:
                parents[t] = v
    return parents


@njit(cache=True, nogil=True, inline="always")
def _int64s(values):  # pragma: no cover - compiled
    """A typed list of integers as an ``int64`` array."""
    out = np.empty(len(values), dtype=np.int64)
    for i in range(len(values)):
        out[i] = values[i]
    return out


@njit(cache=True, nogil=True, inline="always")
def _open(w, wp, counter, sp, offsets, work_v, work_k, index, low, stack,
          on_stack):  # pragma: no cover - compiled
    """Tarjan's visit of state ``w``: on the work stack above ``wp`` (its edges from the
    first), numbered ``counter``, pushed on the component stack at ``sp``; the three
    counters after it."""
    wp += 1
    work_v[wp] = w
    work_k[wp] = offsets[w]
    index[w] = counter
    low[w] = counter
    stack[sp] = w
    on_stack[w] = True
    return wp, counter + 1, sp + 1


@njit(cache=True, nogil=True)
def tarjan(offsets, targets, inside, packed=False):  # pragma: no cover - compiled
    """Tarjan's strongly connected components of the states ``0 .. len(offsets) - 2`` that
    are ``inside``, over the edges between them (an edge to a state past them is left out),
    iteratively, roots in id order and edges in CSR order (the order of
    :func:`gather_verify.properties.graph.tarjan`). Returns (members, starts): every
    component in the order it closes, its members in the order they leave the stack;
    component c is ``members[starts[c]:starts[c + 1]]``. ``packed``: as
    :func:`longest_path`'s. Per state a 4-byte index, low link, stack slot and member."""
    n = len(offsets) - 1
    index = np.full(n, -1, dtype=np.int32)
    low = np.zeros(n, dtype=np.int32)
    on_stack = np.zeros(n, dtype=np.bool_)
    stack = np.empty(n, dtype=np.int32)
    sp = 0
    work_v = np.empty(n, dtype=np.int32)
    work_k = np.empty(n, dtype=np.int64)
    members = np.empty(n, dtype=np.int32)
    mcount = 0
    starts = [0]
    counter = 0
    for root in range(n):
        if index[root] >= 0 or not inside[root]:
            continue
        wp, counter, sp = _open(root, -1, counter, sp, offsets, work_v, work_k, index, low,
                                stack, on_stack)
        while wp >= 0:
            v = work_v[wp]
            k = work_k[wp]
            end = offsets[v + 1]
            recurse = False
            while k < end:
                w = _target(targets, k, packed)
                k += 1
                if w >= n or not inside[w]:
                    continue
                if index[w] < 0:
                    work_k[wp] = k
                    wp, counter, sp = _open(w, wp, counter, sp, offsets, work_v, work_k, index,
                                            low, stack, on_stack)
                    recurse = True
                    break
                if on_stack[w] and index[w] < low[v]:
                    low[v] = index[w]
            if recurse:
                continue
            if low[v] == index[v]:
                while True:
                    sp -= 1
                    w = stack[sp]
                    on_stack[w] = False
                    members[mcount] = w
                    mcount += 1
                    if w == v:
                        break
                starts.append(mcount)
            wp -= 1
            if wp >= 0:
                u = work_v[wp]
                if low[v] < low[u]:
                    low[u] = low[v]
    return members[:mcount], _int64s(starts)


@njit(cache=True, nogil=True)
def tarjan_csr(offsets, targets, skip_loops, packed=False):  # pragma: no cover - compiled
    """The components of :func:`tarjan` over every state that have an edge between distinct
    states, or (unless ``skip_loops``) a self-loop, each unsorted, in the order found:
    (members, starts), component c is ``members[starts[c]:starts[c + 1]]``."""
    members, starts = tarjan(offsets, targets, np.ones(len(offsets) - 1, dtype=np.bool_),
                             packed)
    kept = [0]
    mcount = 0
    for c in range(len(starts) - 1):
        lo = starts[c]
        hi = starts[c + 1]
        keep = hi - lo > 1
        if not keep and not skip_loops:
            v = members[lo]
            for j in range(offsets[v], offsets[v + 1]):
                if _target(targets, j, packed) == v:
                    keep = True
                    break
        if keep:
            for j in range(lo, hi):
                members[mcount] = members[j]
                mcount += 1
            kept.append(mcount)
    return members[:mcount].copy(), _int64s(kept)


# -- the bulk engine's per-chunk arithmetic ----------------------------------------------

@njit(cache=True, nogil=True, inline="always")
def _per_robot(k, s_count, n):  # pragma: no cover - compiled
    """``k`` fresh ``(s_count, n)`` int64 tables, a value per state and robot."""
    block = np.empty((k, s_count, n), dtype=np.int64)
    return [block[i] for i in range(k)]

@njit(cache=True, nogil=True)
def decode_chunk(keys, base, n, weights):  # pragma: no cover - compiled
    """Per state key: its robot codes (digits in base ``base``), their cells, the cells
    sorted, the packed configuration key (sorted cells by ``weights``), whether every robot
    is idle, and each robot's position among the sorted cells (the first equal one)."""
    s_count = len(keys)
    codes, cells, srt, rank = _per_robot(4, s_count, n)
    ck = np.empty(s_count, dtype=np.int64)
    idle = np.empty(s_count, dtype=np.bool_)
    b = np.uint64(base)
    for s in range(s_count):
        rest = keys[s]
        all_idle = True
        for j in range(n):
            quot = rest // b
            c = np.int64(rest - quot * b)
            rest = quot
            codes[s, j] = c
            cell = c // SLOTS
            cells[s, j] = cell
            if c - cell * SLOTS != 0:
                all_idle = False
            # insertion into the sorted prefix
            k = j
            while k > 0 and srt[s, k - 1] > cell:
                srt[s, k] = srt[s, k - 1]
                k -= 1
            srt[s, k] = cell
        idle[s] = all_idle
        key = 0
        for j in range(n):
            key += srt[s, j] * weights[j]
        ck[s] = key
        for i in range(n):
            cell = cells[s, i]
            for j in range(n):
                if srt[s, j] == cell:
                    rank[s, i] = j
                    break
    return codes, cells, srt, ck, idle, rank


@njit(cache=True, nogil=True)
def successor_keys(keys, codes, src, robot, new, powers):  # pragma: no cover - compiled
    """One change per event, no reduction: each successor's key (its source's key with robot
    ``robot`` recoded from its old code to ``new``), and the old codes (of ``new``'s type)."""
    m = len(src)
    succ = np.empty(m, dtype=np.uint64)
    old = np.empty(m, dtype=new.dtype)
    for e in range(m):
        s = src[e]
        r = robot[e]
        o = codes[s, r]
        old[e] = o
        succ[e] = keys[s] + np.uint64(new[e] - o) * powers[r]  # wraps for negative steps
    return succ, old


@njit(cache=True, nogil=True)
def event_keys(keys, codes, src, robot, new, event, powers):  # pragma: no cover - compiled
    """Several changes per event (change ``c`` belongs to event ``event[c]``, in order), no
    reduction: each successor's key (its source's key with each changed robot recoded), and
    the old code of each changed robot."""
    m = len(src)
    succ = np.empty(m, dtype=np.uint64)
    old = np.empty(len(robot), dtype=np.int64)
    for e in range(m):
        succ[e] = keys[src[e]]
    for c in range(len(robot)):
        e = event[c]
        r = robot[c]
        o = codes[src[e], r]
        old[c] = o
        succ[e] += np.uint64(new[c] - o) * powers[r]  # wraps for negative steps
    return succ, old


@njit(cache=True, nogil=True)
def event_canonical_keys(codes, src, robot, new, event, powers, tables,
                         anonymity):  # pragma: no cover - compiled
    """Several changes per event under the reductions: each successor's stored key (as
    ``Canon.keys``: its codes sorted when ``anonymity``, packed by ``powers``, the least over
    its images by the rows of ``tables``), and the old code of each changed robot."""
    m = len(src)
    n = codes.shape[1]
    rows = np.empty((m, n), dtype=np.int64)
    for e in range(m):
        for j in range(n):
            rows[e, j] = codes[src[e], j]
    old = np.empty(len(robot), dtype=np.int64)
    for c in range(len(robot)):
        e = event[c]
        old[c] = rows[e, robot[c]]
        rows[e, robot[c]] = new[c]
    succ = np.empty(m, dtype=np.uint64)
    image = np.empty(n, dtype=np.int64)
    for e in range(m):
        best = np.uint64(0)
        for t in range(-1, len(tables)):
            for j in range(n):
                v = rows[e, j] if t < 0 else tables[t, rows[e, j]]
                if anonymity:  # insertion into the sorted prefix
                    k = j
                    while k > 0 and image[k - 1] > v:
                        image[k] = image[k - 1]
                        k -= 1
                    image[k] = v
                else:
                    image[j] = v
            key = np.uint64(0)
            for j in range(n):
                key += np.uint64(image[j]) * powers[j]
            if t < 0 or key < best:
                best = key
        succ[e] = best
    return succ, old


@njit(cache=True, nogil=True)
def successor_canonical_keys(codes, src, robot, new, powers, tables, anonymity,
                             ordered):  # pragma: no cover - compiled
    """One change per event under the reductions: each successor's stored key (as
    :func:`event_canonical_keys` and ``Canon.keys``), and the old code of each changed robot
    (of ``new``'s type).

    A successor differs from its source in one code. Its source's images (by the identity,
    then by each row of ``tables``) are made once per source state, with their largest
    value, the robot holding it and the next largest. Without anonymity a successor's key
    by each image is its source's packed image with one digit changed. With it, a sorted
    image's largest value is its key's leading digit: the successor's is the larger of the
    new code's image and the largest value of the other robots, so only the images whose
    leading digit is the least can give the least key, and only those are sorted. That
    holds when every value is a digit (``ordered``: the codes and the tables' values in
    ``[0, base)``); else every image is sorted."""
    m = len(src)
    n = codes.shape[1]
    images = len(tables) + 1
    img = np.empty((images, n), dtype=np.int64)
    packed = np.empty(images, dtype=np.uint64)  # each image packed, robot order
    top = np.empty(images, dtype=np.int64)  # the largest value of each image,
    holder = np.empty(images, dtype=np.int64)  # the robot holding it (the first one),
    second = np.empty(images, dtype=np.int64)  # the largest of the other robots' values
    value = np.empty(images, dtype=np.int64)  # the changed robot's new code, by each image
    lead = np.empty(images, dtype=np.int64)  # the successor's image's largest value
    buf = np.empty(n, dtype=np.int64)
    succ = np.empty(m, dtype=np.uint64)
    old = np.empty(m, dtype=new.dtype)
    last = -1
    for e in range(m):
        s = src[e]
        if s != last:
            last = s
            for t in range(images):
                first, at, after, key = np.int64(-1), np.int64(0), np.int64(-1), np.uint64(0)
                for j in range(n):
                    v = codes[s, j] if t == 0 else tables[t - 1, codes[s, j]]
                    img[t, j] = v
                    key += np.uint64(v) * powers[j]
                    after = max(after, min(first, v))  # (branch-free: the values are random)
                    at = j if v > first else at
                    first = max(first, v)
                top[t], holder[t], second[t], packed[t] = first, at, after, key
        r = robot[e]
        c = new[e]
        old[e] = codes[s, r]
        best = np.uint64(0)
        if not anonymity:
            for t in range(images):
                v = c if t == 0 else tables[t - 1, c]
                key = packed[t] - np.uint64(img[t, r]) * powers[r] + np.uint64(v) * powers[r]
                if t == 0 or key < best:
                    best = key
            succ[e] = best
            continue
        least = np.int64(-1)
        for t in range(images):
            v = c if t == 0 else tables[t - 1, c]
            value[t] = v
            rest = second[t] if holder[t] == r else top[t]
            lead[t] = max(rest, v)
            if t == 0 or lead[t] < least:
                least = lead[t]
        found = False
        for t in range(images):
            if ordered and lead[t] != least:
                continue
            for j in range(n):  # the successor's image, sorted by insertion
                v = value[t] if j == r else img[t, j]
                k = j
                while k > 0 and buf[k - 1] > v:
                    buf[k] = buf[k - 1]
                    k -= 1
                buf[k] = v
            key = np.uint64(0)
            for j in range(n):
                key += np.uint64(buf[j]) * powers[j]
            if not found or key < best:
                best, found = key, True
        succ[e] = best
    return succ, old


@njit(cache=True, nogil=True)
def pair_keys(rows, rank, src, robot, old, new, stride, cells):  # pragma: no cover - compiled
    """The transitions that move a robot to another cell, and for each the key of its
    (configuration row, sorted position of the cell left, cell entered)."""
    m = len(src)
    moved = np.empty(m, dtype=np.int64)
    keys = np.empty(m, dtype=np.uint64)
    k = 0
    for e in range(m):
        c = new[e] // SLOTS
        if c != old[e] // SLOTS:
            s = src[e]
            moved[k] = e
            keys[k] = np.uint64(rows[s] * stride + rank[s, robot[e]] * cells + c)
            k += 1
    return moved[:k], keys[:k]


@njit(inline="always")
def _doubled(a, most):  # pragma: no cover - compiled
    """A full list ``a`` with twice its room (at most ``most``), its values kept."""
    grown = np.empty(min(most, 2 * len(a)), dtype=a.dtype)
    grown[:len(a)] = a
    return grown


@njit(cache=True, nogil=True)
def successor_rows(rows, rank, src, robot, old, new, neighbour, succ):  # pragma: no cover
    """The configuration row each one-change transition reaches, from the table ``succ``
    (``succ[row, j, k]``: one more than the row reached when a robot on the ``j``-th sorted
    cell of ``row`` takes step ``k``; 0 unknown). Returns the rows (``int32``; the source's
    own where no robot changes cell), and for the transitions not settled: their positions
    and their ``succ`` slots (flat index; -1 when the change is not one step). The unsettled
    are few once the table fills: their lists start small and double."""
    m = len(src)
    n = succ.shape[1]
    out = np.empty(m, dtype=np.int32)
    miss = np.empty(min(m, 1024), dtype=np.int64)
    slot = np.empty(len(miss), dtype=np.int64)
    flat = succ.reshape(-1)
    k_miss = 0
    for e in range(m):
        s = src[e]
        r = rows[s]
        oc = old[e] // SLOTS
        nc = new[e] // SLOTS
        if oc == nc:
            out[e] = r
            continue
        j = rank[s, robot[e]]
        k = -1
        for d in range(DEGREE):
            if neighbour[oc, d] == nc:
                k = d
                break
        at = -1
        if k >= 0:
            at = (r * n + j) * DEGREE + k
            v = flat[at]
            if v > 0:
                out[e] = v - 1
                continue
        if k_miss == len(miss):
            miss = _doubled(miss, m)
            slot = _doubled(slot, m)
        slot[k_miss] = at
        miss[k_miss] = e
        k_miss += 1
    return out, miss[:k_miss], slot[:k_miss]
