"""``exclusive-perpetual-exploration`` and ``exploration-with-stop`` (SEMANTICS.md §11).

Exclusive perpetual exploration: no two robots ever share a node, no round swaps two
robots across one edge, and every fair execution visits every node infinitely often
(per node v: no fair component of the states where v is empty; a state the robots can
stay on counts as one). Exploration with stop: every fair execution ends, and every
final state has seen every node visited (the search carries the visited set).
"""

from __future__ import annotations

import numpy as np

from gather_verify.engine.world_search import SearchArrays, WorldSearch
from gather_verify.tasks.base import Context, Finding, Task, final_states, livelock


class ExclusivePerpetualExploration(Task):
    name = "exclusive-perpetual-exploration"
    summary = "no two robots ever on one node or crossing one edge; every node visited " \
              "infinitely often"
    parts = ("exclusivity", "perpetual-exploration")
    liveness = ("perpetual-exploration",)
    explores = True

    def check(self, s: WorldSearch, ctx: Context) -> dict[str, Finding | None]:
        return {"exclusivity": _exclusivity(s),
                "perpetual-exploration": _perpetual(s, ctx)}


def _exclusivity(s: WorldSearch) -> Finding | None:
    if s.arrays is not None:
        return _exclusivity_arrays(s.arrays)
    for sid in range(len(s.keys)):
        nodes = [v for v, *_ in s.keys[sid][0]]
        if len(set(nodes)) < len(nodes):
            return Finding("exclusivity", sid, "two robots on one node")
        if sid >= len(s.edges):
            continue
        for k, (_, _, event) in enumerate(s.edges[sid]):
            if event.kind != "round":
                continue
            crossing = {(a, b) for _, a, b in event.moves}
            if any((b, a) in crossing for a, b in crossing):
                return Finding("exclusivity", sid, "two robots cross one edge in opposite "
                               "directions in one round", edge=(sid, k))
    return None


def _exclusivity_arrays(a: SearchArrays) -> Finding | None:
    """:func:`_exclusivity` on a search's arrays: the first state with two robots on one
    node, unless a crossing round comes out of an earlier state."""
    nodes = np.sort(a.nodes, axis=1)
    shared = np.flatnonzero((nodes[:, 1:] == nodes[:, :-1]).any(axis=1))
    crossing = np.flatnonzero(a.crossing) if a.crossing is not None else ()
    at = int(shared[0]) if len(shared) else None
    if len(crossing):
        e = int(crossing[0])
        sid = int(np.searchsorted(a.offsets, e, side="right")) - 1
        if at is None or sid < at:
            return Finding("exclusivity", sid, "two robots cross one edge in opposite "
                           "directions in one round", edge=(sid, e - int(a.offsets[sid])))
    if at is not None:
        return Finding("exclusivity", at, "two robots on one node")
    return None


def _perpetual(s: WorldSearch, ctx: Context) -> Finding | None:
    for v in range(ctx.size):
        if s.arrays is not None:
            inside: object = ~(s.arrays.nodes[:len(s.arrays.offsets) - 1] == v).any(axis=1)
        else:
            inside = lambda sid, v=v: all(u != v for u, *_ in s.keys[sid][0])  # noqa: E731
        found = livelock(s, ctx, "perpetual-exploration",
                         f"a fair execution stops visiting node {ctx.names[v]}",
                         inside=inside, single_states=True)  # type: ignore[arg-type]
        if found is not None:
            found.detail["node"] = v
            return found
    return None


class ExplorationWithStop(Task):
    name = "exploration-with-stop"
    summary = "every fair execution ends, and by then every node has been visited"
    parts = ("termination", "explored-when-final")
    liveness = ("termination",)
    visits = True
    explores = True

    def check(self, s: WorldSearch, ctx: Context) -> dict[str, Finding | None]:
        everything = (1 << ctx.size) - 1
        explored = None
        for sid in final_states(s):
            if s.keys[sid][1] != everything:
                missing = ctx.size - bin(s.keys[sid][1]).count("1")
                explored = Finding("explored-when-final", sid,
                                   f"the robots stopped with {missing} node(s) never visited")
                break
        return {"termination": livelock(s, ctx, "termination", "livelock: a fair execution "
                                        "never reaches a final state"),
                "explored-when-final": explored}
