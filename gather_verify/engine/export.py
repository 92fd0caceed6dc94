"""The reachable state graph for the tools researchers know: a networkx ``DiGraph``,
GraphML or DOT (``gather-verify check --graph-out FILE``; docs/explorer.md).

A node is a stored state id (0 is the initial state); with reductions on (the
default) it stands for a class of states and shows its representative, with
``--no-reduction`` it is one concrete state. Node attributes: ``robots`` (robot
``i``'s node, ``"x,y"`` separated by spaces) and ``pending`` (robot ``i``'s
pending destination, ``-`` when idle). Edge attributes: ``event`` (what the
transition did, as in a rendered trace) and ``weight`` (the edges of the grid
it traversed, 0 for a look); when several events lead from one state to the
same state, the edge keeps the one with the most moves and ``events`` counts
them. All attributes are strings, integers or booleans, so the graph is written
to GraphML as it is. The events are recomputed from the scheduler (the search
keeps only ids and weights) and checked against the stored edges.

>>> from gather_verify.engine.explore import explore_reference
>>> from gather_verify.model.configuration import Configuration
>>> c = Configuration([(0, 0), (1, 0)], [(2, 0)], initial=True)
>>> g = to_networkx(explore_reference(c, "go-to-target", "fsync", reduction=False))
>>> g.number_of_nodes(), g.nodes[0]["robots"], g.nodes[0]["pending"]
(3, '0,0 1,0', '- -')
>>> g.edges[0, 1]["event"], g.edges[0, 1]["weight"]
('round(r0,r1): r0 (0, 0)->(1, 0), r1 (1, 0)->(2, 0)', 2)
>>> print(dot(g).splitlines()[3])
  0 [label="0,0 1,0", robots="0,0 1,0", pending="- -"];
"""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path
from typing import TYPE_CHECKING

from gather_verify.engine.explore import Exploration
from gather_verify.errors import InvalidInput
from gather_verify.model.geometry import Node
from schedulers import Event

if TYPE_CHECKING:
    import networkx as nx

FORMATS = {".graphml": "GraphML", ".dot": "DOT", ".gv": "DOT"}


def _node(v: Node | None) -> str:
    return "-" if v is None else f"{v[0]},{v[1]}"


def event_text(event: Event) -> str:
    """``kind(robots): moves``, the words of a rendered trace (:mod:`gather_verify.render`)."""
    moves = ", ".join(f"r{i} {a}->{b}" for i, a, b in event.moves)
    robots = ",".join(f"r{i}" for i in event.robots)
    return f"{event.kind}({robots})" + (f": {moves}" if moves else ": all stay")


def to_networkx(e: Exploration) -> nx.DiGraph:
    """The reachable graph of ``e`` as a networkx ``DiGraph`` (see the module docstring).

    A search that stopped early (``e.stopped``) gives the part it explored; the graph
    attribute ``stopped`` says why (empty when the search was complete). A search run
    with ``graph=False`` kept no edges: InvalidInput."""
    if len(e.offsets) == 0 and e.states:
        raise InvalidInput("this exploration kept no edges (graph=False): explore again with "
                           "graph=True to export its graph")
    import networkx as nx  # here: check imports this module, and writes a graph only when asked

    g = nx.DiGraph(
        algorithm=e.algorithm.name, scheduler=e.scheduler_name, detection=e.detection,
        frames=e.frames, meeting=" ".join(_node(m) for m in sorted(e.initial.meeting_nodes)),
        anonymity=bool(e.anonymity), symmetry=bool(e.symmetry), stopped=str(e.stopped or ""),
        states=int(e.states), transitions=int(e.transitions))
    ids = {int(key): sid for sid, key in enumerate(e.keys)}
    for sid in range(len(ids)):
        state = e.state(sid)
        g.add_node(sid, robots=" ".join(_node(r[0]) for r in state),
                   pending=" ".join(_node(r[1]) for r in state),
                   **({} if e.lights is None else
                      {"colours": " ".join(str(r[2]) for r in state)}))  # type: ignore[misc]
    expanded = max(len(e.offsets) - 1, 0)
    for sid in range(expanded):
        stored = sorted(int(e.targets[j]) for j in e.successors(sid))
        found = []
        for event, succ in e.concrete_successors(e.state(sid)):
            did = ids.get(e.key_of(succ))
            if did is None:  # beyond a limit: the search never stored it
                continue
            found.append(did)
            weight = event.distance
            if g.has_edge(sid, did):
                edge = g.edges[sid, did]
                edge["events"] += 1
                if weight > edge["weight"]:
                    edge.update(event=event_text(event), weight=weight)
            else:
                g.add_edge(sid, did, event=event_text(event), weight=weight, events=1)
        if not e.stopped and sorted(found) != stored:
            raise AssertionError(f"state {sid}: the scheduler's successors are not the stored "
                                 "edges (a bug of the explorer)")
    return g


def _quote(value: object) -> str:
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, int):
        return str(value)
    return '"' + str(value).replace("\\", "\\\\").replace('"', '\\"') + '"'


def _attributes(attributes: dict[str, object], first: Sequence[tuple[str, object]] = ()) -> str:
    items = [*first, *attributes.items()]
    return ", ".join(f"{k}={_quote(v)}" for k, v in items)


def dot(g: nx.DiGraph) -> str:
    """``g`` in Graphviz DOT, written by hand (no pydot): nodes labelled by their robots."""
    lines = ['digraph "gather-verify" {', f"  graph [{_attributes(g.graph)}];",
             "  node [shape=box, fontname=monospace];"]
    for sid, attributes in g.nodes(data=True):
        lines.append(f"  {sid} [{_attributes(attributes, [('label', attributes.get('robots', ''))])}];")
    for u, v, attributes in g.edges(data=True):
        lines.append(f"  {u} -> {v} [{_attributes(attributes)}];")
    lines.append("}")
    return "\n".join(lines) + "\n"


def graph_format(path: str | Path) -> str:
    """``GraphML`` or ``DOT`` from the file's suffix; InvalidInput for any other."""
    suffix = Path(path).suffix.lower()
    if suffix not in FORMATS:
        raise InvalidInput(f"--graph-out {path}: unknown graph format {suffix or '(none)'!r}: "
                           f"use a file ending in {', '.join(FORMATS)}")
    return FORMATS[suffix]


def write_graph(e: Exploration, path: str | Path) -> nx.DiGraph:
    """Write the reachable graph of ``e`` to ``path`` (GraphML or DOT, by its suffix)."""
    kind = graph_format(path)
    g = to_networkx(e)
    if kind == "GraphML":
        import networkx as nx

        nx.write_graphml(g, path)
    else:
        Path(path).write_text(dot(g), encoding="utf-8")
    return g
