"""``exclusive-perpetual-exploration`` and ``exploration-with-stop`` (SEMANTICS.md §11).

Exclusive perpetual exploration: no two robots ever share a node, no round swaps two
robots across one edge, and every fair execution visits every node infinitely often
(per node v: no fair component of the states where v is empty; a state the robots can
stay on counts as one). Exploration with stop: every fair execution ends, and every
final state has seen every node visited (the search carries the visited set).
"""

from __future__ import annotations

from gather_verify.engine.world_search import WorldSearch
from gather_verify.tasks.base import Context, Finding, Task, livelock


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


def _perpetual(s: WorldSearch, ctx: Context) -> Finding | None:
    for v in range(ctx.size):
        found = livelock(s, ctx, "perpetual-exploration",
                         f"a fair execution stops visiting node {ctx.names[v]}",
                         inside=lambda sid, v=v: all(u != v for u, *_ in s.keys[sid][0]),
                         single_states=True)
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
        for sid, is_final in enumerate(s.final):
            if is_final and s.keys[sid][1] != everything:
                missing = ctx.size - bin(s.keys[sid][1]).count("1")
                explored = Finding("explored-when-final", sid,
                                   f"the robots stopped with {missing} node(s) never visited")
                break
        return {"termination": livelock(s, ctx, "termination", "livelock: a fair execution "
                                        "never reaches a final state"),
                "explored-when-final": explored}
