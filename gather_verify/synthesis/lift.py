"""The cheapest adversary first: a counterexample found under FSYNC (or the centralized
scheduler) is one under SSYNC and ASYNC (SEMANTICS.md §4, §12).

Every FSYNC round is an SSYNC round in which the adversary activates every robot; every
centralized step is an SSYNC round that activates one robot; every SSYNC round is an ASYNC
sequence: the Looks of the robots that move, then their Moves. The runs are fair where the
first one is: a robot active in a round acts in its events, or, if it stayed, is idle in the
state before them with staying in its move set. So a violation under the weaker adversary is
one under the stronger, with the same views and answers. (FSYNC and the centralized
scheduler are not comparable: neither's runs are the other's.)

:func:`lift` rewrites a counterexample (its events, the position of its cycle, its stays)
for a stronger scheduler. Nothing here is trusted: the certificate's re-check replays the
lifted counterexample through that scheduler's own successor function
(:func:`~gather_verify.synthesis.certificate.replay`), as it replays any other.

Without lights only, for ASYNC: under ASYNC a light changes at the Look, so a robot that
looks after another would see its new colour, which the round did not show it.

>>> cex = {"configuration": 0, "property": "exclusivity", "final": False, "events": [
...     {"kind": "round", "robots": [0, 1], "moves": [[0, 0, 1], [1, 1, 0]], "lights": []}]}
>>> [e["kind"] for e in lift(cex, "fsync", "async", 1, [0, 1])["events"]]
['look', 'look', 'move']
"""

from __future__ import annotations

import copy
from typing import Any

LADDER = ("fsync", "centralized", "ssync", "async")
"""The adversaries whose counterexamples lift, cheapest first."""
STRONGER = {"fsync": ("ssync", "async"), "centralized": ("ssync", "async"),
            "ssync": ("async",), "async": ()}
"""Per adversary, those of which each of its runs is a run too (to ASYNC: without lights)."""


def liftable(source: str, target: str, colours: int) -> bool:
    """Whether every counterexample under ``source`` is one under ``target``."""
    if source == target:
        return True
    return target in STRONGER.get(source, ()) and (target != "async" or colours == 1)


def rungs(target: str, colours: int) -> list[str]:
    """The schedulers to try a candidate under before ``target``, cheapest first, then
    ``target`` itself: those whose counterexamples lift to it."""
    return [s for s in LADDER if s != target and liftable(s, target, colours)] + [target]


def lift(cex: dict[str, Any], source: str, target: str, colours: int,
         start: list[Any]) -> dict[str, Any]:
    """``cex`` (found under ``source``, from the robots' nodes ``start`` as its events write
    nodes) as a counterexample under ``target``. FSYNC to SSYNC
    keeps every event (a round of every robot is one SSYNC may take). To ASYNC, each round
    becomes the Looks of its movers and then their Moves, in robot order; a robot active in
    a round of the cycle that stayed is listed as staying in the state before it. A
    counterexample of exclusivity ends at the first state with two robots on one node (a
    crossing under FSYNC or SSYNC puts the first mover on the other's node)."""
    if not liftable(source, target, colours):
        raise ValueError(f"a counterexample under {source} is not one under {target}")
    out = copy.deepcopy(cex)
    out["scheduler"] = target
    if target != "async" or source == "async":
        return out  # a round of FSYNC or the centralized scheduler is one SSYNC may take
    events = cex["events"]
    loop = cex.get("loop")
    pos = [0]
    lifted: list[dict[str, Any]] = []
    stays = []
    robots = [_hashable(v) for v in start]
    for j, e in enumerate(events):
        movers = [m for m in e["moves"] if m[1] != m[2]]
        if loop is not None and j >= loop:
            moved = {m[0] for m in movers}
            stays += [[pos[j], i] for i in e["robots"] if i not in moved]
        lifted += [{"kind": "look", "robots": [i], "moves": [[i, a, b]], "lights": []}
                   for i, a, b in movers]
        for i, a, b in movers:
            lifted.append({"kind": "move", "robots": [i], "moves": [[i, a, b]], "lights": []})
            robots[i] = _hashable(b)
            if cex["property"] == "exclusivity" and len(set(robots)) < len(robots):
                out["events"] = lifted
                out.pop("stays", None)
                return out
        pos.append(len(lifted))
    out["events"] = lifted
    if loop is not None:
        out["loop"] = pos[loop]
        out["stays"] = sorted([[pos[s], i] for s, i in cex.get("stays", [])] + stays)
    return out


def _hashable(node: Any) -> Any:
    """A node as the events write it (an int, or a list on grids), as a dict key."""
    return tuple(node) if isinstance(node, list) else node
