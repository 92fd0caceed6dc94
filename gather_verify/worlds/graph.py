"""``graph:FILE``: any finite connected undirected graph networkx reads (SEMANTICS.md §9).

GraphML (``.graphml``), GML (``.gml``), an adjacency list (``.adjlist``) or an edge
list (anything else: one ``u v`` pair per line). Nodes are written with the file's
ids. The graph is anonymous to the robots: a frame is the file's labelling moved by
an automorphism of G (of the visible ball fixing the robot's node under
``visibility=φ``), so an algorithm gains nothing from the ids. Aut(G) is computed
once per file content with networkx's isomorphism matcher.
"""

from __future__ import annotations

import hashlib
import re
from functools import cache
from pathlib import Path
from typing import TYPE_CHECKING

from gather_verify.errors import InvalidInput
from gather_verify.inputs import read_text
from gather_verify.worlds.base import Frame, Label, World, enumerate_automorphisms

if TYPE_CHECKING:
    import networkx as nx


def _parse(text: str, suffix: str) -> nx.Graph:
    import networkx as nx  # here: every world imports this module, only graph:FILE reads

    if suffix == ".graphml":
        return nx.parse_graphml(text)
    if suffix == ".gml":
        return nx.parse_gml(text)
    lines = text.splitlines()
    if suffix == ".adjlist":
        return nx.parse_adjlist(lines)
    return nx.parse_edgelist(lines, data=False)


class FileGraph(World):
    kind = "graph"

    def __init__(self, path: str, text: str | None = None):
        if text is None:
            text = read_text(path, "graph file")  # read once per command (gather_verify.inputs)
        self.digest = hashlib.sha256(text.encode()).hexdigest()[:16]
        names, edges = _graph_of(text, path)
        super().__init__(f"graph:{path}", names, edges)

    @classmethod
    def from_spec(cls, arg: str) -> FileGraph:
        """The graph of the file ``arg`` as it was first read (:mod:`gather_verify.inputs`),
        built once per content: a sweep's worker asks for it per configuration."""
        text = read_text(arg, "graph file")
        key = (arg, hashlib.sha256(text.encode()).hexdigest())
        got = _BUILT.get(key)
        if got is None:
            got = _BUILT[key] = cls(arg, text)
            while len(_BUILT) > 4:
                del _BUILT[next(iter(_BUILT))]
        return got

    def parse_label(self, text: str) -> Label:
        return text

    def node_from_json(self, value: object) -> int:
        """The file's node ids are text: a number stored as JSON's ``1`` names id ``"1"``."""
        if isinstance(value, int) and not isinstance(value, bool):
            value = str(value)
        return super().node_from_json(value)

    @property
    def automorphisms(self) -> tuple[tuple[int, ...], ...]:
        return _automorphisms(self.digest, self.adjacency, self.name)

    def symmetries(self, frames: str) -> tuple[tuple[int, ...], ...]:
        if frames == "chirality":
            raise InvalidInput(f"{self.name} has no orientation: --frames chirality needs a "
                               "ring, a grid or a torus (use all or compass)")
        return super().symmetries(frames)

    def frame_labels(self, v: int, ball: tuple[int, ...], frames: str) -> list[Frame]:
        if frames == "chirality":
            raise InvalidInput(f"{self.name} has no orientation: --frames chirality needs a "
                               "ring, a grid or a torus (use all or compass)")
        if frames == "compass":
            return [{u: self.labels[u] for u in ball}]
        if len(ball) == self.size:
            # the file's labels moved by every automorphism (the robot's own node is
            # marked by the view, so each of them is a presentation it could be given)
            return [{u: self.labels[p[u]] for u in ball} for p in self.automorphisms]
        sub = self.graph.subgraph(ball)
        local = enumerate_automorphisms(sub, self.name, fixed=v)
        order = sorted(ball)
        return [{u: self.labels[p[i]] for i, u in enumerate(order)} for p in local]

    def frame_group(self, frames: str, visibility: int | None) -> list[object]:
        """The file's labels moved by each automorphism (the identity alone with a compass).
        A myopic view is presented in the file's own ids, not up to isomorphism: refused in
        one line unless every ball is the whole graph."""
        if frames == "chirality":
            self.symmetries(frames)  # one line: a graph file has no orientation
        if frames == "compass":
            return ["perm", [[[w, w] for w in self.labels]]]
        if visibility is not None and any(len(self.ball(v, visibility)) < self.size
                                          for v in range(self.size)):
            raise InvalidInput(f"{self.name} with --visibility {visibility}: a myopic view of a "
                               "graph file is presented in the file's own node ids, so views "
                               "are not up to isomorphism; synthesize takes the whole view "
                               "there (or --frames compass)")
        return ["perm", [[[self.labels[u], self.labels[p[u]]] for u in range(self.size)]
                         for p in self.automorphisms]]


_BUILT: dict[tuple[str, str], FileGraph] = {}
"""The graphs built lately, by file name and content digest (the oldest goes first)."""


@cache
def _automorphisms(digest: str, adjacency: tuple[tuple[int, ...], ...],
                   name: str) -> tuple[tuple[int, ...], ...]:
    import networkx as nx

    g = nx.Graph()
    g.add_nodes_from(range(len(adjacency)))
    g.add_edges_from((a, b) for a, nbrs in enumerate(adjacency) for b in nbrs)
    return enumerate_automorphisms(g, name)


def _graph_of(text: str, path: str) -> tuple[list[str], list[tuple[int, int]]]:
    """The node ids (in natural order) and the edges (as indices) of a graph file's text;
    one line for a file that is no simple connected graph of at least 2 nodes."""
    try:
        g = _parse(text, Path(path).suffix.lower())
    except Exception as error:  # networkx raises many kinds on a malformed file
        raise InvalidInput(f"graph file {path}: not a readable graph "
                           f"({type(error).__name__}: {error})") from None
    if g.is_directed():
        g = g.to_undirected()
    if g.number_of_nodes() < 2:
        raise InvalidInput(f"graph file {path}: fewer than 2 nodes")
    if g.is_multigraph():
        for a, b in g.edges():
            if g.number_of_edges(a, b) > 1:
                raise InvalidInput(f"graph file {path}: more than one edge between {a} and "
                                   f"{b}: a world is a simple graph (keep one edge)")
    names: dict[str, object] = {}
    for node in g.nodes:
        other = names.setdefault(str(node), node)
        if other is not node and other != node:
            raise InvalidInput(f"graph file {path}: two nodes are both written {str(node)!r} "
                               f"({other!r} and {node!r}): give them distinct ids")
    order = sorted(names, key=_natural)
    index = {name: i for i, name in enumerate(order)}
    return order, [(index[str(a)], index[str(b)]) for a, b in g.edges()]


_INTEGER = re.compile(r"-?[0-9]+")


def _natural(name: str) -> tuple[int, int | str]:
    """Numeric ids (ASCII digits, an optional minus) in numeric order, then the rest.

    >>> sorted(["10", "9", "-1", "b", "²", "--5", "a"], key=_natural)
    ['-1', '9', '10', '--5', 'a', 'b', '²']
    """
    return (0, int(name)) if _INTEGER.fullmatch(name) else (1, name)
