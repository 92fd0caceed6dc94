"""Learn more from each counterexample: start it at the last initial configuration it passes
through (SEMANTICS.md §12).

A run from one initial configuration often passes through another one of the instance (up
to the world's symmetries): robots idle, on distinct nodes, with their initial colours, in
a configuration of the start set. The run's suffix from there is a run from that
configuration too, moved by the symmetry: the scheduler and the views are equivariant, and
a view's key is up to isomorphism, so the suffix needs only the answers of the views it
meets. Its clause names fewer views, and so excludes more tables. The violation holds on
the suffix as well: a final state or a cycle is the same, and a node not visited from the
start is not visited from later on.

Nothing here is trusted: the shortened counterexample is replayed (and re-checked in the
certificate) like any other.
"""

from __future__ import annotations

from typing import Any

from gather_verify.synthesis.certificate import apply_event, event_from_json, event_to_json
from gather_verify.synthesis.views import Instance
from schedulers import Event


def restart(inst: Instance, cex: dict[str, Any]) -> dict[str, Any]:
    """``cex`` from the last initial configuration of ``inst`` it passes through, before its
    cycle or its violation (``cex`` itself when there is none after its start)."""
    w = inst.world
    if cex.get("start") is not None or "busy" in cex or inst.lights.colours > 1:
        return cex  # a scheduler with a state of its own, or lights: left as it is
    group = [p for p in w.symmetries(inst.frames)
             if frozenset(p[v] for v in inst.meeting) == inst.meeting]
    reps = {tuple(r): j for j, (r, _) in enumerate(inst.configurations)}
    robots0, colours0 = inst.configurations[int(cex["configuration"])]
    state: tuple[tuple[int, int | None, int], ...] = tuple(
        (v, None, c) for v, c in zip(robots0, colours0, strict=True))
    events = [event_from_json(w, e) for e in cex["events"]]
    # the restart comes before the cycle, or before the last event of an exclusivity
    # violation (a crossing ends on distinct nodes); a final state may be a start itself
    last = cex.get("loop", len(events) - (cex["property"] == "exclusivity"))
    best = None
    for j, e in enumerate(events[:last], start=1):
        state = apply_event(state, e)
        nodes = [v for v, p, _ in state]
        if any(p is not None for _, p, _ in state) or len(set(nodes)) < len(nodes):
            continue
        for p in group:
            image = tuple(sorted(p[v] for v in nodes))
            if image in reps:
                best = (j, p, reps[image], nodes)
                break
    if best is None:
        return cex
    j, p, target, nodes = best
    rep = inst.configurations[target][0]
    rename = {i: rep.index(p[v]) for i, v in enumerate(nodes)}
    out = dict(cex, configuration=target,
               events=[event_to_json(w, _moved(e, p, rename)) for e in events[j:]])
    if "loop" in cex:
        out["loop"] = cex["loop"] - j
        out["stays"] = [[s - j, rename[i]] for s, i in cex.get("stays", [])]
    if "node" in cex:
        out["node"] = w.node_to_json(p[w.node_from_json(cex["node"])])
    return out


def _moved(e: Event, p: tuple[int, ...], rename: dict[int, int]) -> Event:
    """An event moved by the symmetry ``p`` (nodes) and the renaming of the robots."""
    at: Any = p  # a finite world's nodes are indices (Event types them as Z² nodes)
    return Event(e.kind, tuple(sorted(rename[i] for i in e.robots)),
                 tuple(sorted((rename[i], at[a], at[b]) for i, a, b in e.moves)),
                 tuple(sorted((rename[i], a, b) for i, a, b in e.lights)))
