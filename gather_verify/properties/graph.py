"""The graph analyses behind the graph properties (SEMANTICS.md §5): the longest path
weighted by edges traversed (``move-bound``) and the fair strongly connected components
(``termination``), on the reachable graph of an
:class:`~gather_verify.engine.explore.Exploration`.

Small graphs go through networkx (topological order, Tarjan's SCCs); large ones through
the hand-written code (the bulk engine's numpy columns for the longest path; an
iterative Tarjan for the components), which gives the same answers in the same order.

>>> from gather_verify.engine.search import explore
>>> from gather_verify.model.configuration import Configuration
>>> e = explore(Configuration([(0, 0), (3, 1)], [(2, 2)], initial=True), "go-to-target", "async")
>>> longest_path(e).max_moves, strongly_connected(e)
(6, [])
"""

from __future__ import annotations

from array import array
from collections import deque
from collections.abc import Callable, Iterable, Iterator, Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    import networkx as nx

    from gather_verify.engine.explore import Exploration

NX_MAX_STATES = 200_000
"""Graphs up to this many states go through networkx; larger ones through the hand-written
code (networkx holds a few hundred bytes per edge)."""


def real_edges(e: Exploration, sid: int) -> Iterable[tuple[int, int]]:
    """(successor, weight) of ``sid``, self-loops of an unchanged state left out.

    A self-loop of the quotient whose concrete state changed is kept: it lifts
    to a real cycle."""
    state = None
    for k in e.successors(sid):
        t = e.targets[k]
        if t == sid:
            if state is None:
                state = e.state(sid)
            if not e.changed_loops:
                continue
            if all(succ == state or e.key_of(succ) != e.keys[sid]
                   for _, succ in e.concrete_successors(state)):
                continue
        yield t, e.weights[k]


@dataclass
class LongestPath:
    """The largest total moves from the initial state; None when a cycle with moves exists."""

    max_moves: int | None
    path: list[int]  # ids of a worst-case execution (acyclic case)
    cyclic: bool = False
    """The graph has cycles that make no move (a ``stateful`` scheduler's turn going round
    robots that stay): ``max_moves`` is still the bound, but a cycle is there to check."""


def longest_path(e: Exploration) -> LongestPath:
    """Longest path over the reachable graph weighted by edges traversed: a topological
    order (networkx on small graphs, Kahn's algorithm on large ones; the numpy columns of the
    bulk engine a round at a time), then the best total per state in reverse order, keeping
    the first best successor in edge order (so every order gives the same path)."""
    if getattr(e, "turns", None) is not None:
        return _longest_path_condensed(e)
    if _columns(e) and not e.changed_loops:
        from gather_verify import kernels

        if kernels.enabled() and _whole(e):
            longest = _longest_path_compiled(e)
        else:
            longest = _longest_path_bulk(e)
        if longest.max_moves is None and still_cycles(e):
            return _longest_path_condensed(e)
        return longest
    n = e.states
    succs: list[list[tuple[int, int]]] = [list(real_edges(e, s)) for s in range(n)]
    order = _topological_order(succs)
    if order is None:
        return _longest_path_condensed(e) if still_cycles(e) else LongestPath(None, [])
    best = [0] * n
    choice = [-1] * n
    for s in reversed(order):
        for t, w in succs[s]:
            if w + best[t] > best[s] or choice[s] < 0 and w + best[t] == best[s]:
                best[s], choice[s] = w + best[t], t
    path = [0]
    while choice[path[-1]] >= 0:
        path.append(choice[path[-1]])
    return LongestPath(best[0], path)


def still_cycles(e: Exploration) -> bool:
    """Whether ``e``'s graph may have a cycle that makes no move: a ``stateful`` scheduler's
    turn going round robots that stay, or lights changing colours while the robots stay
    (SEMANTICS.md §10). Without either, every change of a state but a move is a Look that
    sets a pending move, undone only by that move: every cycle moves."""
    lights = getattr(e, "lights", None)
    return getattr(e, "turns", None) is not None or (lights is not None and lights.colours > 1)


def _longest_path_condensed(e: Exploration) -> LongestPath:
    """:func:`longest_path` of a graph with cycles that may make no move (:func:`still_cycles`:
    round-robin's turn going round robots that stay, lights changing colours). Moves are
    unbounded only when a cycle makes one; else every state of a strongly connected
    component has the same best total (its members reach each other for free), read off the
    components in reverse topological order, and the path walks inside a component to its
    best way out."""
    import networkx as nx

    succs = [list(real_edges(e, s)) for s in range(e.states)]
    g = digraph(succs)
    comps = [sorted(c) for c in nx.strongly_connected_components(g)]
    comp_of = [0] * e.states
    for k, c in enumerate(comps):
        for v in c:
            comp_of[v] = k
    if any(w and comp_of[s] == comp_of[t] for s, out in enumerate(succs) for t, w in out):
        return LongestPath(None, [], True)
    # a cycle: an edge inside a component (a self-loop of a changed state, too)
    cyclic = any(comp_of[s] == comp_of[t] for s, out in enumerate(succs) for t, _ in out)
    order = list(nx.topological_sort(nx.condensation(g, [set(c) for c in comps])))
    best = [0] * len(comps)
    exit_: list[tuple[int, int] | None] = [None] * len(comps)
    for k in reversed(order):
        for s in comps[k]:
            for t, w in succs[s]:
                kt = comp_of[t]
                if kt != k and (w + best[kt] > best[k] or exit_[k] is None and
                                w + best[kt] == best[k]):
                    best[k], exit_[k] = w + best[kt], (s, t)
    seeds = range(len(e.starts)) if e.starts else range(1)  # each start of the scheduler
    here = max(seeds, key=lambda sid: (best[comp_of[sid]], -sid))
    path = [here]
    while (way := exit_[comp_of[here]]) is not None:
        u, t = way
        path += walk(e, set(comps[comp_of[here]]), here, u)[1:] + [t]
        here = t
    return LongestPath(best[comp_of[path[0]]], path, cyclic)


def digraph(succs: Sequence[Sequence[int | tuple[int, int]]]) -> nx.DiGraph:
    """A networkx ``DiGraph`` of states ``0 .. len(succs) - 1``, nodes and edges inserted in
    id and edge order (so networkx visits them in the order the hand-written code does)."""
    import networkx as nx

    g = nx.DiGraph()
    g.add_nodes_from(range(len(succs)))
    g.add_edges_from((s, t if isinstance(t, int) else t[0])
                     for s, out in enumerate(succs) for t in out)
    return g


def _topological_order(succs: list[list[tuple[int, int]]]) -> list[int] | None:
    """The states in a topological order, or None when the graph has a cycle."""
    n = len(succs)
    if n <= NX_MAX_STATES:
        import networkx as nx

        try:
            return list(nx.topological_sort(digraph(succs)))
        except nx.NetworkXUnfeasible:
            return None
    indegree = array("q", [0]) * n
    for out in succs:
        for t, _ in out:
            indegree[t] += 1
    order = [s for s in range(n) if indegree[s] == 0]
    head = 0
    while head < len(order):
        s = order[head]
        head += 1
        for t, _ in succs[s]:
            indegree[t] -= 1
            if indegree[t] == 0:
                order.append(t)
    return order if len(order) == n else None


def _longest_path_bulk(e: Exploration) -> LongestPath:
    """:func:`longest_path` on the numpy columns of the bulk explorer, a topological round
    at a time; the same value and the same path (first best successor in edge order)."""
    import numpy as np

    n = e.states
    off = e.offsets.array[:n + 1].astype(np.int64)  # type: ignore[attr-defined]
    tgt = e.targets.array.astype(np.int64)  # type: ignore[attr-defined]
    w = e.weights.array.astype(np.int64)  # type: ignore[attr-defined]
    src = np.repeat(np.arange(n), np.diff(off))
    keep = tgt != src  # self-loops of an unchanged state are no edges (no changed loops here)

    def out_edges(states: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        counts = off[states + 1] - off[states]
        idx = np.repeat(off[states] - np.cumsum(counts) + counts, counts) + np.arange(counts.sum())
        return idx[keep[idx]], counts

    indegree = np.bincount(tgt[keep], minlength=n)
    frontier = np.flatnonzero(indegree == 0)
    rounds = []
    while len(frontier):
        rounds.append(frontier)
        t = tgt[out_edges(frontier)[0]]
        indegree -= np.bincount(t, minlength=n)
        frontier = np.unique(t[indegree[t] == 0])
    if sum(map(len, rounds)) < n:
        return LongestPath(None, [])
    best = np.zeros(n, dtype=np.int64)
    choice = np.full(n, -1, dtype=np.int64)
    for states in reversed(rounds):
        idx, _ = out_edges(states)
        if not len(idx):
            continue
        s = src[idx]
        starts = np.flatnonzero(np.r_[True, s[1:] != s[:-1]])
        vals = w[idx] + best[tgt[idx]]
        top = np.maximum.reduceat(vals, starts)
        lengths = np.diff(np.r_[starts, len(idx)])
        pos = np.where(vals == np.repeat(top, lengths), np.arange(len(idx)), len(idx))
        first = np.minimum.reduceat(pos, starts)
        best[s[starts]] = top
        choice[s[starts]] = tgt[idx[first]]
    path = [0]
    while choice[path[-1]] >= 0:
        path.append(int(choice[path[-1]]))
    return LongestPath(int(best[0]), path)


def _whole(e: Exploration) -> bool:
    """Whether every state of ``e`` was expanded (the CSR columns cover every id the edges
    name: what the compiled kernels, which do not check bounds, need)."""
    return len(e.offsets) == e.states + 1 and e.stopped is None


def _longest_path_compiled(e: Exploration) -> LongestPath:
    """:func:`_longest_path_bulk` by the compiled depth-first search over the int32 columns
    (:func:`gather_verify.kernels.longest_path`): the same value, and the same path
    (from each state, the first successor in edge order that attains its best total)."""
    import numpy as np

    from gather_verify import kernels
    off = e.offsets.array[:e.states + 1]  # type: ignore[attr-defined]
    tgt, packed = _raw_targets(e)
    bits = hasattr(e.weights, "bits")  # one bit per edge (engine.columns.BitColumn): no copy
    w = e.weights.bits if bits else e.weights.array  # type: ignore[attr-defined]
    best = kernels.longest_path(off, tgt, w, bits, packed)
    if best[0] < 0:
        return LongestPath(None, [])
    path = [0]
    while True:
        s = path[-1]
        lo, hi = int(off[s]), int(off[s + 1])
        ts = np.asarray(e.targets[lo:hi], dtype=np.int64)
        vals = np.asarray(e.weights[lo:hi], dtype=np.int64) + best[ts]
        ok = np.flatnonzero((ts != s) & (vals == best[s]))
        if not len(ok):  # no successor but itself: the path ends
            break
        path.append(int(ts[ok[0]]))
    return LongestPath(int(best[0]), path)


def _columns(e: Exploration) -> bool:
    """Whether ``e``'s graph is the bulk engine's numpy columns (asked of the column's type:
    a packed column makes its ``array`` when read)."""
    return hasattr(type(e.targets), "array")


def _raw_targets(e: Exploration) -> tuple[Any, bool]:
    """The bulk engine's target ids as the compiled kernels read them, and whether they are
    packed three bytes each (``engine.columns.IdColumn``: no copy)."""
    packed = bool(getattr(e.targets, "packed", False))
    return (e.targets.raw if packed else e.targets.array), packed  # type: ignore[attr-defined]


def has_cycle(e: Exploration) -> bool:
    """Whether the graph (unchanged self-loops aside) has a cycle, one that moves or not."""
    longest = longest_path(e)
    return longest.max_moves is None or longest.cyclic


def strongly_connected(e: Exploration) -> list[list[int]]:
    """Components with an edge between distinct states, each sorted, in the order Tarjan's
    algorithm finds them from state 0 (networkx on small graphs)."""
    if _columns(e) and not e.changed_loops:
        from gather_verify import kernels

        if kernels.enabled() and _whole(e):  # every self-loop is unchanged: none is an edge
            import numpy as np

            tgt, packed = _raw_targets(e)
            members, starts = kernels.tarjan_csr(e.offsets.array[:e.states + 1],  # type: ignore[attr-defined]
                                                 tgt, True, packed)
            return [np.sort(members[a:b]).tolist() for a, b in zip(starts[:-1], starts[1:], strict=True)]
    succs = [[t for t, _ in real_edges(e, s)] for s in range(e.states)]
    if e.states <= NX_MAX_STATES:
        import networkx as nx

        g = digraph(succs)
        return [sorted(c) for c in nx.strongly_connected_components(g)
                if len(c) > 1 or g.has_edge(next(iter(c)), next(iter(c)))]
    return tarjan(succs)


def tarjan(succs: Sequence[Sequence[int]]) -> list[list[int]]:
    """:func:`strongly_connected` on successor lists, by an iterative Tarjan (large graphs):
    the components with an edge between distinct states or a self-loop, each sorted.

    >>> tarjan([[1], [0, 2], [2], []])
    [[2], [0, 1]]
    """
    return [sorted(comp) for comp in components_of(len(succs), succs.__getitem__)
            if len(comp) > 1 or comp[0] in succs[comp[0]]]


def components_of(count: int, successors: Callable[[int], Sequence[int]],
                  inside: Callable[[int], bool] | None = None) -> Iterator[list[int]]:
    """Tarjan's strongly connected components of the states ``0 .. count - 1`` that are
    ``inside`` (all by default), over the edges between them (an edge to a state past them
    is left out), iteratively: roots in id order, edges in the order ``successors`` gives
    them; each component as its states in the order they leave the stack, in the order the
    components close (the compiled kernel's order, :func:`gather_verify.kernels.compiled.tarjan`)."""
    ok = (lambda _v: True) if inside is None else inside
    index = [-1] * count
    low = [0] * count
    on_stack = [False] * count
    stack: list[int] = []
    counter = 0
    for root in range(count):
        if index[root] >= 0 or not ok(root):
            continue
        work = [(root, 0)]
        index[root] = low[root] = counter
        counter += 1
        stack.append(root)
        on_stack[root] = True
        while work:
            v, i = work[-1]
            edges = successors(v)
            if i < len(edges):
                work[-1] = (v, i + 1)
                w = edges[i]
                if w >= count or not ok(w):
                    continue
                if index[w] < 0:
                    index[w] = low[w] = counter
                    counter += 1
                    stack.append(w)
                    on_stack[w] = True
                    work.append((w, 0))
                elif on_stack[w]:
                    low[v] = min(low[v], index[w])
                continue
            work.pop()
            if work:
                low[work[-1][0]] = min(low[work[-1][0]], low[v])
            if low[v] == index[v]:
                comp = []
                while True:
                    w = stack.pop()
                    on_stack[w] = False
                    comp.append(w)
                    if w == v:
                        break
                yield comp


@dataclass
class Livelock:
    """A fair component: its entry state and a closed walk (ids) through it that gives every
    robot an event or a null activation."""

    component: list[int]
    cycle: list[int]


def fair_witnesses(e: Exploration, component: Sequence[int]) -> dict[int, tuple[int, int | None]] | None:
    """Per robot, an edge ``(u, v)`` inside the component where it has an event, or a state
    ``(u, None)`` where it is idle and may stay; None if some robot has neither (unfair)."""
    inside = set(component)
    need = set(range(e.n))
    found: dict[int, tuple[int, int | None]] = {}
    for u in component:
        state = e.state(u)
        for i in range(e.n):
            if i in need and e.may_stay(state, i):
                found[i] = (u, None)
                need.discard(i)
        for event, succ in e.concrete_successors(state):
            t = _id(e, succ)
            if t in inside and t != u:
                for i in event.robots:
                    if i in need:
                        found[i] = (u, t)
                        need.discard(i)
        if not need:
            return found
    return None


def _id(e: Exploration, state: object) -> int:
    index = getattr(e, "_index", None)
    if index is None:
        index = {k: i for i, k in enumerate(e.keys)}
        e._index = index  # type: ignore[attr-defined]
    return index.get(e.key_of(state), -1)  # type: ignore[arg-type]


def walk(e: Exploration, inside: set[int], start: int, goal: int) -> list[int]:
    """A shortest path of ids from ``start`` to ``goal`` inside ``inside`` (BFS)."""
    parent = {start: start}
    queue = deque([start])
    while queue:
        u = queue.popleft()
        if u == goal:
            break
        for t, _ in real_edges(e, u):
            if t in inside and t not in parent:
                parent[t] = u
                queue.append(t)
    path = [goal]
    while path[-1] != start:
        path.append(parent[path[-1]])
    return path[::-1]


def livelock(e: Exploration) -> Livelock | None:
    """The first fair component (termination fails), with a cycle through it; needs an
    exploration without anonymity reduction (robot identity matters for fairness)."""
    if e.anonymity or e.symmetry:
        raise ValueError("fairness needs the graph without reductions")
    for comp in strongly_connected(e):
        if e.turns is not None and any(_final(e, e.state(u)) for u in comp):
            continue  # a run in it has reached a final state (a turn going round, §4); without
            # a scheduler state a final state has self-loops only, never a component of its own
        witnesses = fair_witnesses(e, comp)
        if witnesses is None:
            continue
        inside = set(comp)
        entry = min(comp)  # BFS ids: the component state reached first
        cycle, here = [entry], entry
        for u, v in witnesses.values():
            cycle += walk(e, inside, here, u)[1:]
            here = u
            if v is not None:
                cycle.append(v)
                here = v
        cycle += walk(e, inside, here, entry)[1:]
        if len(cycle) == 1:  # all witnesses are null activations at the entry: go round once
            nxt = next(t for t, _ in real_edges(e, entry) if t in inside)
            cycle += [nxt, *walk(e, inside, nxt, entry)[1:]]
        return Livelock(comp, cycle)
    return None


def _final(e: Exploration, state: Any) -> bool:
    """No robot can move and none has a pending move: what termination waits for. Such a
    state has self-loops only, but for a ``stateful`` scheduler's turn going round."""
    return bool(e.facts_of(state).stuck and all(r[1] is None for r in state))


def any_cycle(e: Exploration) -> list[int] | None:
    """Some cycle of ids (first = last) in a component, or None."""
    for comp in strongly_connected(e):
        inside = set(comp)
        entry = min(comp)
        nxt = next(t for t, _ in real_edges(e, entry) if t in inside)
        return [entry, *walk(e, inside, nxt, entry)] if nxt != entry else [entry, entry]
    return None


def moving_cycle(e: Exploration) -> list[int] | None:
    """A cycle of ids (first = last, its component's first state) that makes a move, or None:
    what makes the moves unbounded. The first component's :func:`any_cycle` when it moves
    (every cycle does without :func:`still_cycles`), else through the first edge in id and
    edge order that moves inside a component."""
    for comp in strongly_connected(e):
        inside = set(comp)
        entry = min(comp)
        nxt = next(t for t, _ in real_edges(e, entry) if t in inside)
        cycle = [entry, *walk(e, inside, nxt, entry)] if nxt != entry else [entry, entry]
        if _moves(e, cycle):
            return cycle
        for u in comp:
            t = next((t for t, w in real_edges(e, u) if w and t in inside), None)
            if t is not None:  # (t = u: a self-loop of a changed state, taken once)
                return walk(e, inside, entry, u) + walk(e, inside, t, entry)
    return None


def _moves(e: Exploration, ids: Sequence[int]) -> bool:
    """Whether some step of the walk ``ids`` can make a move (a moving edge between them)."""
    return any(w for a, b in zip(ids[:-1], ids[1:], strict=True) for t, w in real_edges(e, a) if t == b)


@dataclass
class GraphFacts:
    """What a graph property reads once a search is complete: the explored graph, its longest
    path, and when that path is unbounded (a cycle) the graph ``lifted`` to concrete states
    (robot identity matters for fairness, SEMANTICS.md §5; the same graph when the search ran
    without reductions); ``D``, ``n`` and the move bound's ``c``."""

    exploration: Exploration
    longest: LongestPath
    lifted: Exploration | None
    D: int
    n: int
    c: float


WALK_MAX_EDGES = 5_000_000
"""Past this many stored transitions, :func:`most_moves` is not tried (it is a Python loop;
the move bound then stays undecided on an unfinished search)."""


@dataclass
class Walk:
    """An execution prefix in the stored graph: ``path`` (ids from the initial state), the
    ``weights`` (moves) of the edges it takes, and its total ``moves``."""

    path: list[int]
    weights: list[int]
    moves: int


def most_moves(e: Exploration, bound: float) -> Walk | None:
    """The walk (from an initial state, over the stored edges, states may repeat) with the
    fewest events among those whose total moves exceed ``bound``; when none does, the one
    with the most moves, fewest events among those (None: no move stored, or too many
    edges). A ``stateful`` scheduler's every start is an initial state (its seed ids).

    It works on an unfinished graph too: every stored edge is a transition the scheduler
    offers, so the walk is a real execution prefix, whatever the search did not reach.
    A breadth-first search by events over (state, moves) that keeps, per state, an entry
    only when it has strictly more moves than every entry of that state in an earlier or
    the same layer: an entry with fewer moves and no fewer events cannot lead to a shorter
    excess. Each state is kept at most ``bound + 1`` times, so the search ends. Ties go to
    the lowest state id (so the first start), then the first edge in edge order (so the walk
    is deterministic).

    >>> from gather_verify.engine.search import explore
    >>> from gather_verify.model.configuration import Configuration
    >>> e = explore(Configuration([(0, 0), (3, 1)], [(2, 2)], initial=True), "go-to-target", "async")
    >>> w = most_moves(e, 4)
    >>> w.moves, len(w.path) - 1
    (5, 10)
    """
    if e.transitions > WALK_MAX_EDGES:
        return None
    expanded = len(e.offsets) - 1
    best = [-1] * e.states  # the most moves of an entry of this state kept so far
    starts = getattr(e, "starts", None)
    seeds = list(range(len(starts) if starts else 1))
    for sid in seeds:
        best[sid] = 0
    state, moves, parent, weight = list(seeds), [0] * len(seeds), [-1] * len(seeds), \
        [0] * len(seeds)
    top = 0  # the entry with the most moves (the earliest on ties)
    layer = list(seeds)
    while layer:
        here: dict[int, int] = {}  # state -> its entry in the next layer
        for k in layer:
            s, m = state[k], moves[k]
            if s >= expanded:
                continue
            for t, w in real_edges(e, s):
                mt = m + w
                if mt <= best[t]:
                    continue
                j = here.get(t)
                if j is None:
                    here[t] = len(state)
                    state.append(t)
                    moves.append(mt)
                    parent.append(k)
                    weight.append(w)
                elif mt > moves[j]:
                    moves[j], parent[j], weight[j] = mt, k, w
        layer = sorted(here.values(), key=lambda j: state[j])
        for j in layer:
            best[state[j]] = moves[j]
        if layer:
            j = max(layer, key=lambda j: (moves[j], -state[j]))
            if moves[j] > moves[top]:
                top = j
            if moves[top] > bound:
                break
    if moves[top] == 0:
        return None
    path, weights, k = [], [], top
    while k >= 0:
        path.append(state[k])
        weights.append(weight[k])
        k = parent[k]
    return Walk(path[::-1], weights[::-1][1:], moves[top])
