"""The compiled kernels of the finite-world bulk engine
(:mod:`gather_verify.engine.world_bulk`) and of the tasks' liveness and exclusivity tests
on its arrays (:mod:`gather_verify.tasks.base`).

Imported on first use only (it imports numba). A state is one ``int64``:

- robot i's code ``rc = (node * P + slot) * K + colour`` (``P`` = the world's degree + 1;
  ``slot`` 0 when idle, else 1 + the index of the pending destination in the node's sorted
  neighbours; ``K`` colours), as digit i in base ``R = size * P * K``;
- then ``rest = visited + VB * extra`` times ``R**n`` (``visited`` a bit set of nodes when
  the task explores, ``VB`` = 2**size then, else 1; ``extra`` the round-robin scheduler's
  ``order * n + turn``, else 0).

The world's neighbour table ``adj[v, k]`` is node v's k-th sorted neighbour, and
``kernels.codes.NO_EDGE`` past v's degree (no such edge: an illegal move). The kernels read
it only at a slot a robot's pending move names, an edge v has; a finite world has no
``OUTSIDE`` (the search region is the whole world).

A robot's actions are a bit set: bit b of node v is ``(act_node[v, b], act_col[v, b])``,
the bits in the order in which the schedulers try the actions (sorted by ``repr``), so
events come out in the order of the reference search
(:mod:`gather_verify.engine.world_search`).

The helpers with a leading underscore (one state's decoding, facts and ASYNC events) are
inlined into the kernels that share them; :func:`_code_events` (a table per robot code) is
called once per chunk.
"""

from __future__ import annotations

import numpy as np
from numba import njit


@njit(cache=True, nogil=True, inline="always")
def _decode(key, n, radix, rc_node, rc_slot, rc_col, nodes, slots, cols):  # pragma: no cover
    """One state key into its robots' nodes, slots and colours (rows of length ``n``, read
    through the robot code tables); returns the rest (visited and extra)."""
    rest = key
    for i in range(n):
        q = rest // radix
        rc = rest - q * radix
        rest = q
        nodes[i] = rc_node[rc]
        slots[i] = rc_slot[rc]
        cols[i] = rc_col[rc]
    return rest


@njit(cache=True, nogil=True)
def world_decode(keys, n, radix, rc_node, rc_slot, rc_col, colours,
                 cfg_base):  # pragma: no cover - compiled
    """Per state key: per robot its node, slot and colour (a robot code ``rc`` is read
    through the tables ``rc_node``, ``rc_slot``, ``rc_col``); the rest (visited and extra);
    the configuration key (the sorted ``node * K + colour`` digits in base ``cfg_base``);
    each robot's position among those sorted digits (the first equal)."""
    s_count = len(keys)
    nodes = np.empty((s_count, n), dtype=np.int64)
    slots = np.empty((s_count, n), dtype=np.int64)
    cols = np.empty((s_count, n), dtype=np.int64)
    rest_out = np.empty(s_count, dtype=np.int64)
    ckey = np.empty(s_count, dtype=np.int64)
    pos = np.empty((s_count, n), dtype=np.int64)
    srt = np.empty(n, dtype=np.int64)
    elem = np.empty(n, dtype=np.int64)
    for s in range(s_count):
        rest_out[s] = _decode(keys[s], n, radix, rc_node, rc_slot, rc_col, nodes[s], slots[s],
                              cols[s])
        for i in range(n):
            e = nodes[s, i] * colours + cols[s, i]
            elem[i] = e
            k = i
            while k > 0 and srt[k - 1] > e:
                srt[k] = srt[k - 1]
                k -= 1
            srt[k] = e
        key = 0
        w = 1
        for j in range(n):
            key += srt[j] * w
            if j + 1 < n:
                w *= cfg_base
        ckey[s] = key
        for i in range(n):
            for j in range(n):
                if srt[j] == elem[i]:
                    pos[s, i] = j
                    break
    return nodes, slots, cols, rest_out, ckey, pos


@njit(cache=True, nogil=True)
def world_nodes(keys, n, radix, pend, colours):  # pragma: no cover - compiled
    """Per state key, its robots' nodes (int32), and its rest (visited and extra)."""
    s_count = len(keys)
    nodes = np.empty((s_count, n), dtype=np.int32)
    rest_out = np.empty(s_count, dtype=np.int64)
    for s in range(s_count):
        rest = keys[s]
        for i in range(n):
            q = rest // radix
            rc = rest - q * radix
            rest = q
            nodes[s, i] = (rc // colours) // pend
        rest_out[s] = rest
    return nodes, rest_out


@njit(cache=True, nogil=True, inline="always")
def _facts(nodes, slots, cols, masks, stay_bit):  # pragma: no cover - compiled
    """One state's final (every robot idle, its actions exactly staying with its colour)
    and mask of idle robots whose actions hold staying with their colour."""
    one = np.int64(1)
    f = True
    st = np.int64(0)
    for i in range(len(nodes)):
        b = stay_bit[nodes[i], cols[i]]
        m = masks[i]
        if slots[i] != 0:
            f = False
        else:
            if m != (one << b):
                f = False
            if (m >> b) & 1:
                st |= one << i
    return f, st


@njit(cache=True, nogil=True)
def world_facts(nodes, slots, cols, masks, stay_bit):  # pragma: no cover - compiled
    """Per state: final (every robot idle, its actions exactly staying with its colour) and
    the mask of idle robots whose actions hold staying with their colour."""
    s_count = nodes.shape[0]
    final = np.empty(s_count, dtype=np.bool_)
    stay = np.zeros(s_count, dtype=np.int64)
    for s in range(s_count):
        final[s], stay[s] = _facts(nodes[s], slots[s], cols[s], masks[s], stay_bit)
    return final, stay


@njit(cache=True, nogil=True, inline="always")
def _async_count(nodes, slots, cols, masks, act_node, act_col):  # pragma: no cover - compiled
    """How many events ASYNC has in one state (:func:`_async_events`)."""
    width = act_node.shape[1]
    total = 0
    for i in range(len(nodes)):
        if slots[i] == 0:
            v = nodes[i]
            c = cols[i]
            m = masks[i]
            for b in range(width):
                if (m >> b) & 1 and not (act_node[v, b] == v and act_col[v, b] == c):
                    total += 1
        else:
            total += 1
    return total


@njit(cache=True, nogil=True, inline="always")
def _async_events(s, key, seen, nodes, slots, cols, masks, adj, act_node, act_col, act_slot,
                  pw, visits, pend, colours, src, succ, rmask, e):  # pragma: no cover
    """ASYNC's events of state ``s`` (key ``key``, visited ``seen``, its robots' rows),
    written from event ``e`` on, in the order of ``Async.luminous``: per robot, its Looks
    (idle: per action bit, but staying with its colour) or its Move (pending). Returns the
    next event's place."""
    n = len(nodes)
    width = act_node.shape[1]
    one = np.int64(1)
    for i in range(n):
        v = nodes[i]
        c = cols[i]
        old = (v * pend + slots[i]) * colours + c
        if slots[i] == 0:
            m = masks[i]
            look = seen
            if visits:
                for j in range(n):
                    look |= one << nodes[j]
            for b in range(width):
                if (m >> b) & 1 == 0:
                    continue
                d = act_node[v, b]
                c2 = act_col[v, b]
                if d == v and c2 == c:
                    continue
                new = (v * pend + act_slot[v, b]) * colours + c2
                src[e] = s
                succ[e] = key + (new - old) * pw[i] + (look - seen) * pw[n]
                rmask[e] = one << i
                e += 1
        else:
            d = adj[v, slots[i] - 1]
            new = d * pend * colours + c
            moved = seen
            if visits:
                for j in range(n):
                    moved |= one << (d if j == i else nodes[j])
            src[e] = s
            succ[e] = key + (new - old) * pw[i] + (moved - seen) * pw[n]
            rmask[e] = one << i
            e += 1
    return e


@njit(cache=True, nogil=True)
def world_async(keys, nodes, slots, cols, adj, vis, masks, act_node, act_col, act_slot, pw,
                visits, pend, colours):  # pragma: no cover - compiled
    """ASYNC's events of each state (:func:`_async_events`). Returns per event its state
    (row), its successor's key and its robots' mask."""
    s_count = nodes.shape[0]
    total = 0
    for s in range(s_count):
        total += _async_count(nodes[s], slots[s], cols[s], masks[s], act_node, act_col)
    src = np.empty(total, dtype=np.int64)
    succ = np.empty(total, dtype=np.int64)
    rmask = np.empty(total, dtype=np.int64)
    e = 0
    for s in range(s_count):
        e = _async_events(s, keys[s], vis[s], nodes[s], slots[s], cols[s], masks[s], adj,
                          act_node, act_col, act_slot, pw, visits, pend, colours, src, succ,
                          rmask, e)
    return src, succ, rmask


@njit(cache=True, nogil=True)
def _code_events(radix, rc_node, rc_slot, rc_col, pair_mask, known, adj, act_node, act_col,
                 act_slot, stay_bit, pend, colours):  # pragma: no cover - compiled
    """Per robot code, when the algorithm answers by (node, colour) alone: how many ASYNC
    events the robot has (-1: its pair is not known as answered), each event's change of the
    robot's code (in the order of :func:`_async_events`), whether the robot is idle and
    final, whether it is idle with staying among its actions, and its Move's destination
    (-1: idle)."""
    width = act_node.shape[1]
    one = np.int64(1)
    count = np.full(radix, -1, dtype=np.int64)
    change = np.zeros((radix, max(width, 1)), dtype=np.int64)
    final = np.zeros(radix, dtype=np.bool_)
    stays = np.zeros(radix, dtype=np.bool_)
    dest = np.full(radix, -1, dtype=np.int64)
    for rc in range(radix):
        v = rc_node[rc]
        slot = rc_slot[rc]
        c = rc_col[rc]
        pair = v * colours + c
        if known[pair] != 1:
            continue
        old = (v * pend + slot) * colours + c
        if slot:
            dest[rc] = adj[v, slot - 1]
            change[rc, 0] = dest[rc] * pend * colours + c - old
            count[rc] = 1
            continue
        m = pair_mask[pair]
        b0 = stay_bit[v, c]
        final[rc] = m == (one << b0)
        stays[rc] = (m >> b0) & 1
        k = 0
        for b in range(width):
            if (m >> b) & 1 and not (act_node[v, b] == v and act_col[v, b] == c):
                change[rc, k] = (v * pend + act_slot[v, b]) * colours + act_col[v, b] - old
                k += 1
        count[rc] = k
    return count, change, final, stays, dest


@njit(cache=True, nogil=True)
def world_async_by_node(keys, n, radix, rc_node, rc_slot, rc_col, pair_mask, known, adj,
                        act_node, act_col, act_slot, stay_bit, pw, visits, pend, colours,
                        vb):  # pragma: no cover - compiled
    """:func:`world_decode`, :func:`world_facts` and :func:`world_async` in one pass, for an
    algorithm that answers by (node, colour) alone: robot i's bit set is
    ``pair_mask[node * K + colour]``, asked of the algorithm already when ``known`` of its
    pair is 1 (0: not yet; 2: it has no answer there). A robot's events then depend on its
    code alone (:func:`_code_events`), but for the visited nodes. Expands the states up to
    the first one with a pair not known as answered (``cut``; ``len(keys)``: none). Returns
    ``cut``; per event (of the states before it) its state (int32), its successor's key and
    its robots' mask (int32); per state its events' end, final and stay."""
    count, change, code_final, code_stays, dest = _code_events(
        radix, rc_node, rc_slot, rc_col, pair_mask, known, adj, act_node, act_col, act_slot,
        stay_bit, pend, colours)
    s_count = len(keys)
    codes = np.empty((s_count, n), dtype=np.int32)  # the first pass's robot codes
    rests = np.empty(s_count, dtype=np.int64)  # past the robots' digits: the visited nodes
    total = 0
    cut = s_count
    for s in range(s_count):
        rest = keys[s]
        events = 0
        for i in range(n):
            q = rest // radix
            rc = rest - q * radix
            rest = q
            codes[s, i] = rc
            if count[rc] < 0:
                events = -1
                break
            events += count[rc]
        if events < 0:
            cut = s
            break
        if visits:
            rests[s] = rest
        total += events
    src = np.empty(total, dtype=np.int32)
    succ = np.empty(total, dtype=np.int64)
    rmask = np.empty(total, dtype=np.int32)
    ends = np.empty(cut, dtype=np.int64)
    final = np.empty(cut, dtype=np.bool_)
    stay = np.empty(cut, dtype=np.int64)
    one = np.int64(1)
    visited = np.zeros(n, dtype=np.int64)  # per robot, its events' change of that digit
    e = 0
    for s in range(cut):
        if visits:
            seen = rests[s] % vb
            everyone = seen
            for j in range(n):
                everyone |= one << rc_node[codes[s, j]]
            for i in range(n):
                rc = codes[s, i]
                if dest[rc] < 0:  # a Look sees every robot's node
                    visited[i] = (everyone - seen) * pw[n]
                else:  # a Move reaches its destination; the others stay where they are
                    moved = seen | (one << dest[rc])
                    for j in range(n):
                        if j != i:
                            moved |= one << rc_node[codes[s, j]]
                    visited[i] = (moved - seen) * pw[n]
        key = keys[s]
        f = True
        st = np.int64(0)
        for i in range(n):
            rc = codes[s, i]
            f &= code_final[rc]
            st |= np.int64(code_stays[rc]) << i
            base = key + visited[i]
            p = pw[i]
            for k in range(count[rc]):
                src[e] = s
                succ[e] = base + change[rc, k] * p
                rmask[e] = 1 << i
                e += 1
        final[s] = f
        stay[s] = st
        ends[s] = e
    return cut, src, succ, rmask, ends, final, stay


@njit(cache=True, nogil=True)
def world_round_counts(extra, masks, subsets, rr, rr_orders, width, cap):  # pragma: no cover
    """Per leading state, how many events (at most) its rounds make: the sum over the
    activated subsets of the product of the activated robots' action counts, as a float
    (40 robots' products pass 2**63). Stops after the first state that takes the sum past
    ``cap``: the states after it are not counted (a round with very many events is weighed
    before it is made, so no limit is passed by making it)."""
    s_count, n = masks.shape
    nsub = 1 if rr else subsets.shape[0]
    out = np.zeros(s_count, dtype=np.float64)
    total = 0.0
    for s in range(s_count):
        here = 0.0
        for r in range(nsub):
            prod = 1.0
            if rr:
                o = extra[s] // n
                t = extra[s] - o * n
                i = rr_orders[o, t]
                cnt = 0
                for b in range(width):
                    cnt += (masks[s, i] >> b) & 1
                prod = 1.0 * cnt
            else:
                for i in range(n):
                    if subsets[r, i]:
                        cnt = 0
                        for b in range(width):
                            cnt += (masks[s, i] >> b) & 1
                        prod *= cnt
            here += prod
        out[s] = here
        total += here
        if total > cap:
            return out[:s + 1]
    return out


@njit(cache=True, nogil=True)
def world_rounds(keys, nodes, slots, cols, vis, extra, masks, subsets, rr, rr_orders,
                 act_node, act_col, pw, visits, pend, colours, vb, total):  # pragma: no cover
    """The events of the round schedulers, in the order of their ``luminous``: per activated
    subset (the rows of ``subsets``; round-robin: the one robot whose turn it is, by
    ``extra``), every choice of the activated robots' actions in the order of
    ``itertools.product`` over their bits; a round that changes no robot is left out (but
    for round-robin, whose turn moves on). ``total``: the events :func:`world_round_counts`
    counted for these states. Returns per event its state, its successor's key, its robots'
    mask and whether it moves two robots across one edge in opposite directions."""
    s_count, n = nodes.shape
    width = act_node.shape[1]
    one = np.int64(1)
    nsub = 1 if rr else subsets.shape[0]
    src = np.empty(total, dtype=np.int64)
    succ = np.empty(total, dtype=np.int64)
    rmask = np.empty(total, dtype=np.int64)
    cross = np.zeros(total, dtype=np.bool_)
    bits = np.empty((n, width), dtype=np.int64)
    cnt = np.empty(n, dtype=np.int64)
    act = np.empty(n, dtype=np.int64)
    idx = np.empty(n, dtype=np.int64)
    newnode = np.empty(n, dtype=np.int64)
    e = 0
    for s in range(s_count):
        for i in range(n):
            cnt[i] = 0
            m = masks[s, i]
            for b in range(width):
                if (m >> b) & 1:
                    bits[i, cnt[i]] = b
                    cnt[i] += 1
        for r in range(nsub):
            na = 0
            after = extra[s]
            if rr:
                o = extra[s] // n
                t = extra[s] - o * n
                act[0] = rr_orders[o, t]
                na = 1
                after = o * n + (t + 1) % n
            else:
                for i in range(n):
                    if subsets[r, i]:
                        act[na] = i
                        na += 1
            empty = False
            amask = np.int64(0)
            for j in range(na):
                idx[j] = 0
                amask |= one << act[j]
                if cnt[act[j]] == 0:
                    empty = True
            if empty:
                continue
            while True:
                key = keys[s]
                changed = False
                for j in range(na):
                    i = act[j]
                    v = nodes[s, i]
                    c = cols[s, i]
                    b = bits[i, idx[j]]
                    d = act_node[v, b]
                    old = (v * pend + slots[s, i]) * colours + c
                    new = d * pend * colours + act_col[v, b]
                    if new != old:
                        changed = True
                        key += (new - old) * pw[i]
                    newnode[j] = d
                if changed or rr:
                    seen = vis[s]
                    if visits:
                        for i in range(n):
                            node = nodes[s, i]
                            for j in range(na):
                                if act[j] == i:
                                    node = newnode[j]
                            seen |= one << node
                    key += ((seen - vis[s]) + vb * (after - extra[s])) * pw[n]
                    crossing = False
                    for j in range(na):
                        a1 = nodes[s, act[j]]
                        b1 = newnode[j]
                        if a1 == b1:
                            continue
                        for k in range(na):
                            a2 = nodes[s, act[k]]
                            b2 = newnode[k]
                            if k != j and a2 != b2 and a1 == b2 and b1 == a2:
                                crossing = True
                    src[e] = s
                    succ[e] = key
                    rmask[e] = amask
                    cross[e] = crossing
                    e += 1
                j = na - 1
                while j >= 0:
                    idx[j] += 1
                    if idx[j] < cnt[act[j]]:
                        break
                    idx[j] = 0
                    j -= 1
                if j < 0:
                    break
    return src[:e].copy(), succ[:e].copy(), rmask[:e].copy(), cross[:e].copy()


@njit(cache=True, nogil=True)
def world_canon(keys, group, anonymity, visits, n, size, radix, pend, colours, adj, vb,
                pw):  # pragma: no cover - compiled
    """The key of each state under the reductions (``world_search.canonicaliser``): its
    least image under the permutations ``group`` (rows), the robots sorted when
    ``anonymity``, compared robot by robot as ``(node, pending or -1, colour)``, then by the
    visited set."""
    s_count = len(keys)
    out = np.empty(s_count, dtype=np.int64)
    g_count = group.shape[0]
    degree = adj.shape[1]
    one = np.int64(1)
    vv = np.empty(n, dtype=np.int64)
    pp = np.empty(n, dtype=np.int64)
    cc = np.empty(n, dtype=np.int64)
    cur = np.empty(n, dtype=np.int64)
    best = np.empty(n, dtype=np.int64)
    for s in range(s_count):
        rest = keys[s]
        for i in range(n):
            q = rest // radix
            rc = rest - q * radix
            rest = q
            cc[i] = rc % colours
            t = rc // colours
            slot = t % pend
            vv[i] = t // pend
            pp[i] = adj[vv[i], slot - 1] if slot > 0 else -1
        vis = rest % vb
        xtra = rest // vb
        best_vis = np.int64(0)
        for g in range(g_count):
            for i in range(n):
                p = group[g, pp[i]] + 1 if pp[i] >= 0 else 0
                o = (group[g, vv[i]] * (size + 1) + p) * colours + cc[i]
                k = i
                if anonymity:
                    while k > 0 and cur[k - 1] > o:
                        cur[k] = cur[k - 1]
                        k -= 1
                cur[k] = o
            cvis = vis
            if visits:
                cvis = 0
                for u in range(size):
                    if (vis >> u) & 1:
                        cvis |= one << group[g, u]
            take = g == 0
            if not take:
                decided = False
                for i in range(n):
                    if cur[i] != best[i]:
                        take = cur[i] < best[i]
                        decided = True
                        break
                if not decided:
                    take = cvis < best_vis
            if take:
                for i in range(n):
                    best[i] = cur[i]
                best_vis = cvis
        key = np.int64(0)
        for i in range(n):
            o = best[i]
            c = o % colours
            t = o // colours
            p = t % (size + 1)
            v = t // (size + 1)
            slot = 0
            if p > 0:
                for k in range(degree):
                    if adj[v, k] == p - 1:
                        slot = k + 1
                        break
            key += ((v * pend + slot) * colours + c) * pw[i]
        out[s] = key + (best_vis + vb * xtra) * pw[n]
    return out


# -- the tasks' tests on a search's arrays -----------------------------------------------

@njit(cache=True, nogil=True)
def _scc(offsets, targets, inside, robots, stay, final, pick, skip_final, single_states,
         full):  # pragma: no cover - compiled
    """Tarjan's strongly connected components of the expanded states (``len(offsets) - 1``)
    that are ``inside``, over the edges between them, iteratively: a label per state (-1
    outside), how many components, and with ``pick`` the label of the fair component whose
    least state is least (-1: none; see :func:`fair_component`), each component tested as it
    is closed. Per state 4-byte index, low link and label (state ids fit 31 bits)."""
    total = len(offsets) - 1
    index = np.full(total, -1, dtype=np.int32)
    low = np.empty(total, dtype=np.int32)
    on_stack = np.zeros(total, dtype=np.bool_)
    stack = np.empty(total, dtype=np.int32)
    work_v = np.empty(total, dtype=np.int32)
    work_k = np.empty(total, dtype=np.int64)
    labels = np.full(total, -1, dtype=np.int32)
    sp = 0
    counter = 0
    ncomp = 0
    best = -1
    best_least = total
    for root in range(total):
        if index[root] >= 0 or not inside[root]:
            continue
        wp = 0
        work_v[0] = root
        work_k[0] = offsets[root]
        index[root] = counter
        low[root] = counter
        counter += 1
        stack[sp] = root
        sp += 1
        on_stack[root] = True
        while wp >= 0:
            v = work_v[wp]
            k = work_k[wp]
            end = offsets[v + 1]
            recurse = False
            while k < end:
                w = targets[k]
                k += 1
                if w >= total or not inside[w]:
                    continue
                if index[w] < 0:
                    work_k[wp] = k
                    wp += 1
                    work_v[wp] = w
                    work_k[wp] = offsets[w]
                    index[w] = counter
                    low[w] = counter
                    counter += 1
                    stack[sp] = w
                    sp += 1
                    on_stack[w] = True
                    recurse = True
                    break
                if on_stack[w] and index[w] < low[v]:
                    low[v] = index[w]
            if recurse:
                continue
            if low[v] == index[v]:
                top = sp
                while True:
                    sp -= 1
                    w = stack[sp]
                    on_stack[w] = False
                    labels[w] = ncomp
                    if w == v:
                        break
                if pick and (top - sp > 1 or single_states):  # its members: stack[sp:top]
                    least = total
                    has_final = False
                    covered = np.int64(0)
                    for j in range(sp, top):
                        u = stack[j]
                        least = min(least, u)
                        has_final = has_final or final[u]
                        covered |= stay[u]
                        for e in range(offsets[u], offsets[u + 1]):
                            t = targets[e]
                            if t < total and labels[t] == ncomp:
                                covered |= robots[e]
                    if covered == full and not (skip_final and has_final) and least < best_least:
                        best = ncomp
                        best_least = least
                ncomp += 1
            wp -= 1
            if wp >= 0:
                u = work_v[wp]
                if low[v] < low[u]:
                    low[u] = low[v]
    return labels, ncomp, best


@njit(cache=True, nogil=True)
def scc_labels(offsets, targets, inside):  # pragma: no cover - compiled
    """Tarjan's strongly connected components of the expanded states (``len(offsets) - 1``)
    that are ``inside``, over the edges between them: a label per state (int32, -1 outside),
    and how many components."""
    none = np.zeros(0, dtype=np.int64)
    labels, ncomp, _ = _scc(offsets, targets, inside, none, none, np.zeros(0, dtype=np.bool_),
                            False, False, False, 0)
    return labels, ncomp


@njit(cache=True, nogil=True)
def fair_component(offsets, targets, robots, stay, final, inside, skip_final, single_states,
                   full):  # pragma: no cover - compiled
    """The fair component (SEMANTICS §5: every robot has an event on an edge inside it or
    may stay idle in one of its states) of the states ``inside`` whose least state is least;
    components of one state only when ``single_states``, none holding a final state when
    ``skip_final``. Returns the components' labels (:func:`scc_labels`) and its label
    (-1: none)."""
    labels, _, best = _scc(offsets, targets, inside, robots, stay, final, True, skip_final,
                           single_states, full)
    return labels, best


@njit(cache=True, nogil=True)
def cycle_from(offsets, targets, member, start):  # pragma: no cover - compiled
    """``tasks.base.cycle_in`` on arrays: a breadth-first search inside ``member`` from
    ``start`` for an edge back to it; the cycle (first = last), or ``[start]``."""
    total = len(offsets) - 1
    parent = np.full(total, -2, dtype=np.int64)
    parent[start] = -1
    queue = np.empty(total, dtype=np.int64)
    head = 0
    tail = 1
    queue[0] = start
    while head < tail:
        v = queue[head]
        head += 1
        for k in range(offsets[v], offsets[v + 1]):
            w = targets[k]
            if w == start:
                length = 1
                u = v
                while parent[u] >= 0:
                    u = parent[u]
                    length += 1
                path = np.empty(length + 1, dtype=np.int64)
                u = v
                for j in range(length - 1, -1, -1):
                    path[j] = u
                    u = parent[u]
                path[length] = start
                return path
            if w < total and member[w] and parent[w] == -2:
                parent[w] = v
                queue[tail] = w
                tail += 1
    out = np.empty(1, dtype=np.int64)
    out[0] = start
    return out
