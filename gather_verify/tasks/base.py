"""What a task is, and the fairness test its liveness parts share (SEMANTICS.md §5, §11).

A task is a set of properties checked on the reachable space of a finite world
(:mod:`gather_verify.engine.world_search`). A safety part may be decided on a
partial search (a violation found is a violation); a liveness part needs the
whole space, unreduced (robot identities decide fairness).
"""

from __future__ import annotations

from collections.abc import Callable, Iterator
from dataclasses import dataclass, field

import numpy as np

from gather_verify.engine.world_search import SearchArrays, WorldSearch
from gather_verify.properties.graph import components_of


@dataclass
class Finding:
    """A violated part: the state it fails in (or the end of the prefix to a cycle), why,
    and for a liveness part the cycle (state ids, first = last) the run can stay on."""

    property: str
    state: int
    reason: str
    cycle: list[int] | None = None
    edge: tuple[int, int] | None = None  # a transition part: (source id, index in its edges)
    detail: dict[str, object] = field(default_factory=dict)
    component: list[int] | None = None
    """For a liveness part: the fair component the cycle lies in (its trace walks through it
    so that the cycle itself is fair, :func:`fair_walk`)."""


@dataclass(frozen=True)
class Context:
    """What a task knows of the instance besides the search."""

    n: int
    size: int
    meeting: frozenset[int]
    scheduler: str
    names: tuple[str, ...]  # each node as the world writes it


class Task:
    """A registered task: its parts, which are liveness, and whether it needs the visited
    nodes in the state. ``check`` returns, per part, its first finding or None (holds)."""

    name: str
    summary: str
    parts: tuple[str, ...]
    liveness: tuple[str, ...] = ()
    visits: bool = False
    explores: bool = False
    """The traces record the nodes visited so far (from the state when ``visits``, else
    counted along the trace) and the pictures mark them."""
    needs_meeting: bool = False

    def check(self, s: WorldSearch, ctx: Context) -> dict[str, Finding | None]:
        raise NotImplementedError


def components(s: WorldSearch, inside: Callable[[int], bool] | None = None) -> Iterator[list[int]]:
    """The strongly connected components of the expanded states (those ``inside`` only),
    iteratively (Tarjan, :func:`~gather_verify.properties.graph.components_of`), each as a
    list of ids."""
    return components_of(len(s.edges), lambda v: [w for w, _, _ in s.edges[v]], inside)


def fair(s: WorldSearch, comp: list[int], n: int) -> bool:
    """§5: a fair run can stay in ``comp`` forever exactly when every robot has an event on
    an edge inside it, or is idle in a state of it where its move set holds staying."""
    members = set(comp)
    covered = 0
    for v in comp:
        covered |= s.stay[v]
        for w, robots, _ in s.edges[v]:
            if w in members:
                covered |= robots
    return covered == (1 << n) - 1


def cycle_in(s: WorldSearch, comp: list[int]) -> list[int]:
    """A cycle inside ``comp`` from its state nearest the start (first = last), or that
    state alone when the run stays on it by null activations."""
    members = set(comp)
    start = min(comp)
    parent = {start: -1}
    queue = [start]
    for v in queue:
        for w, _, _ in s.edges[v]:
            if w == start:
                path = [v]
                while parent[path[-1]] >= 0:
                    path.append(parent[path[-1]])
                return path[::-1] + [start]
            if w in members and w not in parent:
                parent[w] = v
                queue.append(w)
    return [start]


def livelock(s: WorldSearch, ctx: Context, name: str, what: str,
             inside: Callable[[int], bool] | np.ndarray | None = None,
             single_states: bool = False) -> Finding | None:
    """The first fair component (with an edge between distinct states, or any state when
    ``single_states``), as a finding whose cycle a trace can show. Without ``inside`` (the
    termination test) a component that holds a final state does not count: a run in it has
    reached a final state (a round-robin turn going round gathered robots, say).

    ``inside``: a test of a state id, or a boolean array over the states. On a search with
    arrays (the bulk engine's) the same component is found by compiled code
    (:func:`livelock_arrays`)."""
    if s.arrays is not None:
        return livelock_arrays(s.arrays, ctx, name, what, inside, single_states)
    if isinstance(inside, np.ndarray):
        inside = inside.__getitem__
    found = None
    for comp in components(s, inside):
        if len(comp) == 1 and not single_states:
            continue
        if inside is None and any(s.final[v] for v in comp):
            continue
        if fair(s, comp, ctx.n) and (found is None or min(comp) < min(found)):
            found = comp
    if found is None:
        return None
    cycle = cycle_in(s, found)
    return Finding(name, cycle[0], what, cycle=cycle, component=sorted(found))


def livelock_arrays(a: SearchArrays, ctx: Context, name: str, what: str,
                    inside: Callable[[int], bool] | np.ndarray | None = None,
                    single_states: bool = False) -> Finding | None:
    """:func:`livelock` on a search's arrays: the same component (the fair one whose least
    state is least) and the same cycle, by compiled Tarjan and breadth-first search."""
    from gather_verify.kernels import world as kw

    total = len(a.offsets) - 1
    if inside is None:
        mask = np.ones(total, dtype=np.bool_)
    elif isinstance(inside, np.ndarray):
        mask = np.ascontiguousarray(inside[:total], dtype=np.bool_)
    else:
        mask = np.fromiter((bool(inside(v)) for v in range(total)), dtype=np.bool_, count=total)
    labels, best = kw.fair_component(a.offsets, a.targets, a.robots, a.stay, a.final, mask,
                                     inside is None, single_states, (1 << ctx.n) - 1)
    if best < 0:
        return None
    member = labels == best
    start = int(np.argmax(member))
    cycle = kw.cycle_from(a.offsets, a.targets, member, start).tolist()
    return Finding(name, cycle[0], what, cycle=cycle, component=np.flatnonzero(member).tolist())


def fair_walk(s: WorldSearch, component: list[int], n: int, start: int
              ) -> list[tuple[int, int]]:
    """A closed walk from ``start`` inside the fair ``component`` that is fair by itself
    (§5): every robot has an event on one of its edges or is idle, and may stay, in one of
    its states. As ``(source id, index in its edges)`` per step; empty when the run stays on
    ``start`` alone by null activations (a component of one state with no edge)."""
    members = set(component)

    def out(u: int) -> list[tuple[int, int, int]]:  # (edge index, target, robots mask)
        if s.arrays is not None:
            lo, hi = int(s.arrays.offsets[u]), int(s.arrays.offsets[u + 1])
            return [(k - lo, int(s.arrays.targets[k]), int(s.arrays.robots[k]))
                    for k in range(lo, hi) if int(s.arrays.targets[k]) in members]
        return [(k, w, m) for k, (w, m, _) in enumerate(s.edges[u]) if w in members]

    def path(frm: int, goal: Callable[[int], tuple[int, int] | None]
             ) -> tuple[list[tuple[int, int]], int]:
        """Steps from ``frm`` (breadth-first, inside the component) to the first state where
        ``goal`` gives a last step (an edge index, or -1 for none), and the state reached."""
        parent: dict[int, tuple[int, int]] = {frm: (-1, -1)}
        queue = [frm]
        for u in queue:
            hit = goal(u)
            if hit is not None:
                steps: list[tuple[int, int]] = []
                v = u
                while parent[v][0] >= 0:
                    steps.append(parent[v])
                    v = parent[v][0]
                steps.reverse()
                k, w = hit
                if k >= 0:
                    steps.append((u, k))
                return steps, (w if k >= 0 else u)
            for k, w, _ in out(u):
                if w not in parent:
                    parent[w] = (u, k)
                    queue.append(w)
        raise AssertionError("the component is not strongly connected")  # pragma: no cover

    walk: list[tuple[int, int]] = []
    here = start
    covered = int(s.stay[start])
    for i in range(n):
        if covered >> i & 1:
            continue

        def witness(u: int, bit: int = 1 << i) -> tuple[int, int] | None:
            if int(s.stay[u]) & bit:
                return -1, u
            return next(((k, w) for k, w, m in out(u) if m & bit), None)

        steps, here = path(here, witness)
        walk += steps
        for u, k in steps:
            covered |= int(s.stay[u]) | next(m for j, _, m in out(u) if j == k)
        covered |= int(s.stay[here])
    if here != start:
        walk += path(here, lambda u: (-1, u) if u == start else None)[0]
    if not walk and len(component) > 1:  # null activations cover everyone: go round once
        k, w, _ = out(start)[0]
        walk = [(start, k), *path(w, lambda u: (-1, u) if u == start else None)[0]]
    return walk


def final_states(s: WorldSearch) -> list[int]:
    """The ids of the final states, in order."""
    if s.arrays is not None:
        return np.flatnonzero(s.arrays.final).tolist()
    return [sid for sid, is_final in enumerate(s.final) if is_final]
