"""The world part: a finite graph the robots live on, as the engines see it.

SEMANTICS.md §9. A world is a finite, connected, undirected graph. The engines
know a node only by its *index* (``0 .. size-1``); the world says how a node is
written (:meth:`World.label`, :meth:`World.parse_node`), who its neighbours are
(:attr:`World.adjacency`), what its automorphisms are, and in which *frames* a
robot may be handed its view. A new world is a subclass in one module and one
line in :data:`gather_verify.worlds.WORLDS`; the engines, the tasks and the
schedulers never ask which world they run.

>>> from gather_verify.worlds import get_world
>>> ring = get_world("ring:5")
>>> ring.size, ring.adjacency[0], ring.distance(0, 3)
(5, (1, 4), 2)
>>> len(ring.automorphisms)
10
"""

from __future__ import annotations

import copy
import re
from collections import deque
from collections.abc import Hashable, Iterable, Iterator, Mapping, Sequence
from functools import cached_property
from typing import TYPE_CHECKING, Any, NamedTuple, Protocol, runtime_checkable

from gather_verify.errors import InvalidInput

if TYPE_CHECKING:
    import networkx as nx

Label = Hashable
"""A node as the world writes it and as a view presents it (an int on a ring, ``(x, y)`` on
grids and tori, the file's id on ``graph:FILE``)."""
Frame = dict[int, Label]
"""One presentation of a robot's view: node index -> the label the robot reads."""

Point = tuple[float, float]
"""A place in a world's drawing (x to the right, y up)."""


class DrawnEdge(NamedTuple):
    """An edge as the pictures draw it: its ends (node indices), the lines that draw it
    (each a list of points, the first line leaving ``a``, the last one reaching ``b``) and
    whether it wraps around (its lines leave the picture on one side and come back on the
    other)."""

    a: int
    b: int
    lines: tuple[tuple[Point, ...], ...]
    wraps: bool = False


class Outline(NamedTuple):
    """A closed line around the world's nodes: its border (``wraps`` false), or the seam
    that wrapping edges cross (``wraps`` true, drawn dashed); ``title`` says which."""

    points: tuple[Point, ...]
    wraps: bool
    title: str


FINITE, PLANE = "finite", "plane"
"""The entries of check, sweep and synthesize a world names as its :attr:`AnyWorld.entry`:
the finite-world search, or the Z² engines (with their region growth)."""


@runtime_checkable
class AnyFrame(Protocol):
    """One presentation of a robot's view: what the robot reads for each node it sees."""

    def label(self, u: Any) -> Label:
        """The label node ``u`` (as the world writes it) carries in this frame."""
        ...


@runtime_checkable
class AnyWorld(Protocol):
    """What every world offers the edge (the commands, the pictures, the census), finite or
    not: the commands ask the world, never its name, which entry runs it.

    A node is whatever the world's own engines take (an index on a finite world, ``(x, y)``
    on Z²): the world parses and prints it, stores it in JSON and reads it back.
    """

    name: str
    """The spec that names the world (``grid``, ``ring:9``, ...)."""
    kind: str
    entry: str
    """Which entry of check, sweep and synthesize runs the world: :data:`FINITE` or
    :data:`PLANE`."""

    def format_node(self, v: Any) -> str:
        """A node as the command line and the traces write it."""
        ...

    def parse_node(self, text: str) -> Any:
        """One node's text (one line, :class:`InvalidInput`, if it is none)."""
        ...

    def parse_nodes(self, text: str) -> list[Any]:
        """Whitespace-separated nodes, as ``--robots`` and ``--meeting`` give them."""
        ...

    def node_to_json(self, v: Any) -> object:
        """A node as a scenario or trace file stores it."""
        ...

    def node_from_json(self, value: object) -> Any:
        """A node as a scenario or trace file stores it, read back."""
        ...

    def frames(self, v: Any, visibility: int | None, frames: str) -> Sequence[AnyFrame]:
        """The frames of the view of a robot on ``v`` (§9), restricted by the frame set
        (``all``, ``chirality``, ``compass``, §3)."""
        ...

    def canonical(self, robots: Iterable[Any], meeting: Iterable[Any],
                  frames: str = "all") -> Hashable:
        """One key per class of configurations under the symmetries of the world the
        robots' frames move along (Aut(G) for ``all`` frames): two configurations have the
        same key exactly when one such symmetry maps one onto the other."""
        ...

    def drawing(self) -> dict[str, Any] | None:
        """The picture of the world as JSON (:meth:`World.drawing`), or None for a world the
        pictures draw around a trace's own nodes (Z², which has no end)."""
        ...


FRAME_SETS = ("all", "chirality", "compass")
MAX_AUTOMORPHISMS = 100_000
"""Aut(G) is enumerated; a graph with more automorphisms is refused (one line) rather than
enumerated for minutes (a complete graph on 9 nodes has 362,880)."""


class World:
    """A finite connected graph with node indices ``0 .. size-1``.

    Subclasses set :attr:`name` and :attr:`kind`, build :attr:`labels` and
    :attr:`adjacency`, and define :meth:`frame_labels`; everything else follows.
    """

    name: str
    kind: str
    entry = FINITE
    labels: tuple[Label, ...]
    adjacency: tuple[tuple[int, ...], ...]

    def __init__(self, name: str, labels: Sequence[Label], edges: Iterable[tuple[int, int]]):
        self.name = name
        self.labels = tuple(labels)
        self.index = {label: i for i, label in enumerate(self.labels)}
        around: list[set[int]] = [set() for _ in self.labels]
        for a, b in edges:
            if a != b:
                around[a].add(b)
                around[b].add(a)
        self.adjacency = tuple(tuple(sorted(s)) for s in around)
        if self.size and len(self._bfs(0)) != self.size:
            raise InvalidInput(f"world {name}: the graph is not connected")

    # -- the graph ---------------------------------------------------------------------
    @property
    def size(self) -> int:
        return len(self.labels)

    @cached_property
    def degree(self) -> int:
        """The largest degree (the bulk engine's neighbour table is this wide)."""
        return max((len(a) for a in self.adjacency), default=0)

    def _bfs(self, source: int, limit: int | None = None) -> dict[int, int]:
        """Graph distance from ``source`` to every node within ``limit`` hops."""
        return hops(self.adjacency, source, limit)

    @cached_property
    def _distances(self) -> tuple[dict[int, int], ...]:
        return tuple(self._bfs(v) for v in range(self.size))

    def distance(self, u: int, v: int) -> int:
        """Graph distance between two node indices."""
        return self._distances[u][v]

    def ball(self, v: int, radius: int | None) -> tuple[int, ...]:
        """The nodes within ``radius`` hops of ``v`` (all of them for ``None``), sorted."""
        if radius is None:
            return tuple(range(self.size))
        return tuple(sorted(self._bfs(v, radius)))

    @cached_property
    def graph(self) -> nx.Graph:
        """The world as a networkx graph on node indices (for layouts and isomorphisms)."""
        import networkx as nx  # here: importing networkx costs a run that never asks 0.2 s

        g = nx.Graph()
        g.add_nodes_from(range(self.size))
        g.add_edges_from((a, b) for a, nbrs in enumerate(self.adjacency) for b in nbrs if a < b)
        return g

    @cached_property
    def automorphisms(self) -> tuple[tuple[int, ...], ...]:
        """Aut(G) as permutations of node indices (``p[v]`` is the image of ``v``), the
        identity first. Subclasses with a known group list it; the default enumerates it."""
        return enumerate_automorphisms(self.graph, self.name)

    def symmetries(self, frames: str) -> tuple[tuple[int, ...], ...]:
        """The automorphisms that commute with the frame set: those under which the robots'
        decisions move with the configuration, so a search or a census may merge what they
        relate (§4 reductions, §9 sweeps). By default all of Aut(G) for ``all`` frames (each
        frame is the labelling moved by an automorphism) and the identity for ``compass``."""
        if frames == "all":
            return self.automorphisms
        return (tuple(range(self.size)),)

    def canonical(self, robots: Iterable[int], meeting: Iterable[int], frames: str = "all",
                  colours: Iterable[int] | None = None) -> tuple[tuple[Any, ...], tuple[int, ...]]:
        """The least image (sorted node indices of the robots, a multiset, then of the
        meeting nodes) of a configuration under :meth:`symmetries` (:class:`AnyWorld`). With
        the robots' initial ``colours`` (one per robot), the robots are sorted ``(node,
        colour)`` pairs: the symmetries move nodes, never colours.

        >>> from gather_verify.worlds import get_world
        >>> get_world("ring:6").canonical([3, 5], [4])
        ((0, 2), (1,))
        >>> get_world("ring:6").canonical([3, 5], [4], colours=[1, 0])
        (((0, 0), (2, 1)), (1,))
        """
        meeting = tuple(meeting)
        group = self._symmetries(frames)
        if colours is None:
            nodes = tuple(robots)
            return min((tuple(sorted(p[v] for v in nodes)), tuple(sorted(p[v] for v in meeting)))
                       for p in group)
        lit = tuple(zip(robots, colours, strict=True))
        return min((tuple(sorted((p[v], c) for v, c in lit)), tuple(sorted(p[v] for v in meeting)))
                   for p in group)

    def _symmetries(self, frames: str) -> tuple[tuple[int, ...], ...]:
        """:meth:`symmetries`, asked once per frame set (a census asks per configuration)."""
        got = self._symmetries_of.get(frames)
        if got is None:
            _check_frames(frames)
            got = self._symmetries_of[frames] = self.symmetries(frames)
        return got

    @cached_property
    def _symmetries_of(self) -> dict[str, tuple[tuple[int, ...], ...]]:
        return {}

    # -- how nodes are written ---------------------------------------------------------
    def label(self, v: int) -> Label:
        return self.labels[v]

    def format_node(self, v: int) -> str:
        """A node as the command line and the traces write it."""
        label = self.labels[v]
        if isinstance(label, tuple):
            return ",".join(map(str, label))
        return str(label)

    def parse_label(self, text: str) -> Label:
        """One node's text as a label (subclasses: ints, pairs)."""
        return text

    def parse_node(self, text: str) -> int:
        try:
            label = self.parse_label(text.strip())
        except ValueError:
            label = None
        if label is None or label not in self.index:
            raise InvalidInput(f"{text.strip()!r} is not a node of {self.name}"
                               f" (nodes are written like {self.format_node(0)!r})")
        return self.index[label]

    def parse_nodes(self, text: str) -> list[int]:
        """Whitespace-separated nodes, as ``--robots`` and ``--meeting`` give them."""
        return [self.parse_node(part) for part in text.split()]

    def node_from_json(self, value: object) -> int:
        """A node as a scenario or trace file stores it (its label, lists for pairs). JSON's
        ``true`` and ``1.0`` are no node, though Python takes them for ``1``."""
        label = tuple(value) if isinstance(value, list) else value
        parts = label if isinstance(label, tuple) else (label,)
        if not all(isinstance(x, int | str) and not isinstance(x, bool) for x in parts) \
                or not _hashable(label) or label not in self.index:
            raise InvalidInput(f"{json_text(value)} is not a node of {self.name} (nodes are "
                               f"written like {json_text(self.node_to_json(0))})")
        return self.index[label]

    def node_to_json(self, v: int) -> object:
        label = self.labels[v]
        return list(label) if isinstance(label, tuple) else label

    # -- frames ------------------------------------------------------------------------
    def frame_labels(self, v: int, ball: tuple[int, ...], frames: str) -> list[Frame]:
        """The presentations of the view of a robot on ``v`` that shows ``ball``: per frame,
        ``ball``'s nodes -> labels (§9), restricted by the frame set (§3)."""
        raise NotImplementedError

    def frames(self, v: int, visibility: int | None, frames: str) -> list[FrameMap]:
        """The frames of the view from ``v`` (cached: they depend on nothing else)."""
        key = (v, visibility, frames)
        got = self._frames.get(key)
        if got is None:
            _check_frames(frames)
            got = [FrameMap(self, labels)
                   for labels in self.frame_labels(v, self.ball(v, visibility), frames)]
            self._frames[key] = got
        return got

    @cached_property
    def _frames(self) -> dict[tuple[int, int | None, str], list[FrameMap]]:
        return {}

    def frame_group(self, frames: str, visibility: int | None) -> list[object]:
        """The robots' frames as a group acting on view labels: the label maps that move one
        presentation of a view to every other one (§9), for the synthesis to key views up to
        isomorphism (:func:`gather_verify.synthesis.viewkey.build` reads it: ``["ring", N,
        [signs]]``, ``["d4", [matrix, ...]]`` or ``["perm", [[[label, image], ...], ...]]``).
        A world whose frames are no such group says so in one line."""
        raise InvalidInput(f"synthesize does not know the frames of {self.name}")

    # -- drawing -----------------------------------------------------------------------
    # The pictures (the viewer, the SVG storyboard, the report) draw a world from
    # :meth:`drawing` alone and never ask which world it is: a world says where its nodes
    # are (:meth:`layout`), how its edges are drawn (:meth:`drawn_edges`) and what line goes
    # around it (:meth:`outline`).
    def layout(self) -> dict[int, Point]:
        """Where to draw each node (y up), the same on every run: by default a spring layout
        with a fixed seed (a circle past 500 nodes, where the spring layout needs scipy)."""
        import networkx as nx

        if self.size >= 500:
            pos = nx.circular_layout(self.graph)
        else:
            pos = nx.spring_layout(self.graph, seed=0, method="force")
        return {v: (float(x), float(y)) for v, (x, y) in pos.items()}

    def drawn_edges(self) -> list[DrawnEdge]:
        """Every edge once, as drawn: by default a straight line between its ends."""
        pos = self.layout()
        return [DrawnEdge(a, b, ((pos[a], pos[b]),))
                for a, nbrs in enumerate(self.adjacency) for b in nbrs if a < b]

    def outline(self) -> Outline | None:
        """The line around the world, if it has one (a finite grid's border, a torus's seam)."""
        return None

    def drawing(self) -> dict[str, Any]:
        """The picture of the world as JSON, for the traces and the renderers: per node its
        label, its text, its place and the side its name is written on (a unit vector away
        from its edges, outwards where it can); per edge its ends, its lines when they are not the
        straight segment between the ends, and whether it wraps; the outline. Coordinates
        are scaled so that the median edge is 1 long (or longer, so that no two nodes are
        closer than 0.625), and rounded: the same world gives the
        same drawing, byte for byte.

        >>> from gather_verify.worlds import get_world
        >>> d = get_world("ring:4").drawing()
        >>> d["nodes"][0], d["edges"][0]["ends"], len(d["edges"][0]["lines"][0]), d["outline"]
        ({'label': 0, 'text': '0', 'x': 0.0, 'y': 0.7071, 'side': [0.0, 1.0]}, [0, 1], 10, None)
        """
        return copy.deepcopy(self._drawing)

    @cached_property
    def _drawing(self) -> dict[str, Any]:
        import statistics  # a picture's only need (random, fractions, decimal: not a check's)

        pos = self.layout()
        edges = self.drawn_edges()
        lengths = [_dist(pos[e.a], pos[e.b]) for e in edges if not e.wraps]
        unit = statistics.median(lengths) if lengths else 1.0
        # two nodes closer than an edge (a spring layout puts some at half an edge) stay
        # far enough apart for the robots drawn on them not to overlap
        unit = min(unit, 1.6 * _closest(list(pos.values())))
        unit = unit if unit > 1e-9 else 1.0

        def at(p: Point) -> list[float]:
            return [_round(p[0] / unit), _round(p[1] / unit)]

        out_edges = []
        for e in edges:
            item: dict[str, Any] = {"ends": [e.a, e.b]}
            if e.wraps or e.lines != ((pos[e.a], pos[e.b]),):
                item["lines"] = [[at(p) for p in line] for line in e.lines]
            if e.wraps:
                item["wraps"] = True
            out_edges.append(item)
        outline = self.outline()
        sides = _name_sides(pos, edges)
        return {
            "nodes": [{"label": self.node_to_json(v), "text": self.format_node(v),
                       **dict(zip(("x", "y"), at(pos[v]), strict=True)),
                       "side": [_round(sides[v][0]), _round(sides[v][1])]}
                      for v in range(self.size)],
            "edges": out_edges,
            "outline": None if outline is None else {
                "points": [at(p) for p in outline.points], "wraps": outline.wraps,
                "title": outline.title},
        }

    def __repr__(self) -> str:
        return f"<world {self.name}>"


def decimal(text: str) -> int:
    """An integer written with the digits 0-9 and an optional minus, as a node's text on the
    command line: ``int`` also takes ``٣``, ``1_0`` and ``+1``, which name no node.

    >>> decimal("12"), decimal("-3")
    (12, -3)
    >>> decimal("1_0")
    Traceback (most recent call last):
    ...
    ValueError: '1_0' is not written with the digits 0-9
    """
    if not _DECIMAL.fullmatch(text.strip()):
        raise ValueError(f"{text!r} is not written with the digits 0-9")
    return int(text, 10)


_DECIMAL = re.compile(r"-?[0-9]+", re.ASCII)


def json_text(value: object) -> str:
    """A value as JSON writes it, cut at 40 characters (for a message)."""
    import json

    try:
        text = json.dumps(value)
    except (TypeError, ValueError):
        text = repr(value)
    return text if len(text) <= 40 else text[:37] + "..."


def _hashable(value: object) -> bool:
    try:
        hash(value)
    except TypeError:
        return False
    return True


def _check_frames(frames: str) -> None:
    if frames not in FRAME_SETS:
        raise InvalidInput(f"unknown frames {frames!r}: use one of {', '.join(FRAME_SETS)}")


def _dist(p: Point, q: Point) -> float:
    return ((p[0] - q[0]) ** 2 + (p[1] - q[1]) ** 2) ** 0.5


def _name_sides(pos: dict[int, Point], edges: list[DrawnEdge]) -> dict[int, Point]:
    """Per node, the side to write its name on: of 16 directions, the one farthest in angle
    from the node's edges, outwards from the middle of the drawing on a tie (the same every
    run: the directions are tried in a fixed order)."""
    import math

    leaving: dict[int, list[float]] = {v: [] for v in pos}
    for e in edges:
        for v, line in ((e.a, e.lines[0]), (e.b, e.lines[-1][::-1])):
            (x0, y0), (x1, y1) = line[0], line[1]
            if (x1, y1) != (x0, y0):
                leaving[v].append(math.atan2(y1 - y0, x1 - x0))
    mx = sum(p[0] for p in pos.values()) / len(pos)
    my = sum(p[1] for p in pos.values()) / len(pos)
    out = {}
    for v, (x, y) in pos.items():
        away = math.atan2(y - my, x - mx) if (x, y) != (mx, my) else -math.pi / 4

        def gap(a: float, v: int = v) -> float:
            return min((abs((a - b + math.pi) % (2 * math.pi) - math.pi) for b in leaving[v]),
                       default=math.pi)

        best = max((k * math.pi / 8 for k in range(16)),
                   key=lambda a, away=away: (round(gap(a), 6), math.cos(a - away)))
        out[v] = (math.cos(best), math.sin(best))
    return out


def _closest(points: list[Point]) -> float:
    """The smallest distance between two of ``points`` (infinity for fewer than two)."""
    import numpy as np

    p = np.array(points, dtype=float).reshape(-1, 2)
    best = float("inf")
    for i in range(len(p) - 1):
        d = np.hypot(*(p[i + 1:] - p[i]).T)
        best = min(best, float(d.min()))
    return best


def _round(value: float) -> float:
    out = round(value, 4)
    return 0.0 if out == 0 else out  # never -0.0


def hops(adjacency: Any, source: Any, limit: int | None = None) -> dict[Any, int]:
    """Breadth-first search: the distance from ``source`` to every node within ``limit``
    hops, over ``adjacency[node]`` (the node's neighbours)."""
    seen = {source: 0}
    queue = deque([source])
    while queue:
        u = queue.popleft()
        if limit is not None and seen[u] == limit:
            continue
        for w in adjacency[u]:
            if w not in seen:
                seen[w] = seen[u] + 1
                queue.append(w)
    return seen


def enumerate_automorphisms(graph: nx.Graph, name: str,
                            fixed: int | None = None) -> tuple[tuple[int, ...], ...]:
    """The automorphisms of ``graph`` (nodes ``0 .. k-1`` or any ints), as permutations over
    ``sorted(graph)`` positions' node ids, the identity first; with ``fixed``, only those
    that fix that node. Refused past :data:`MAX_AUTOMORPHISMS`."""
    import networkx as nx
    from networkx.algorithms.isomorphism import GraphMatcher

    g = graph.copy()
    nx.set_node_attributes(g, {v: v == fixed for v in g}, "centre")
    matcher = GraphMatcher(g, g, node_match=lambda a, b: a["centre"] == b["centre"])
    nodes = sorted(g)
    out = []
    for mapping in matcher.isomorphisms_iter():
        out.append(tuple(mapping[v] for v in nodes))
        if len(out) > MAX_AUTOMORPHISMS:
            raise InvalidInput(f"world {name} has more than {MAX_AUTOMORPHISMS:,} automorphisms:"
                               " too many frames to try one by one")
    identity = tuple(nodes)
    out.sort(key=lambda p: p != identity)
    return tuple(out)


class _DistanceRows(Mapping[Label, dict[Label, int]]):
    """Rows of graph distances over ``adjacency`` (label -> its neighbours), one
    breadth-first search per row, when the row is first read; a mapping over every label,
    as a full table would be (a label outside the graph: ``KeyError``)."""

    def __init__(self, adjacency: dict[Label, tuple[Label, ...]]):
        self.adjacency = adjacency
        self.rows: dict[Label, dict[Label, int]] = {}

    def __getitem__(self, a: Label) -> dict[Label, int]:
        row = self.rows.get(a)
        if row is None:
            if a not in self.adjacency:
                raise KeyError(a)
            row = self.rows[a] = hops(self.adjacency, a)
        return row

    def __iter__(self) -> Iterator[Label]:
        return iter(self.adjacency)

    def __len__(self) -> int:
        return len(self.adjacency)


class FrameMap:
    """One frame of the view from one node: ``labels`` (node index -> label in the frame)
    and what follows from it, computed once (a world caches its frames)."""

    __slots__ = ("labels", "world", "__dict__")

    def __init__(self, world: World, labels: Frame):
        self.world, self.labels = world, labels

    def label(self, u: int) -> Label:
        """The label node ``u`` carries in this frame (:class:`AnyFrame`)."""
        return self.labels[u]

    @cached_property
    def inverse(self) -> dict[Label, int]:
        return {label: u for u, label in self.labels.items()}

    @cached_property
    def graph(self) -> nx.Graph:
        import networkx as nx

        g = nx.Graph()
        g.add_nodes_from(self.labels.values())
        g.add_edges_from((self.labels[u], self.labels[w]) for u in self.labels
                         for w in self.world.adjacency[u] if w in self.labels)
        return nx.freeze(g)

    @cached_property
    def _adjacent(self) -> dict[Label, tuple[Label, ...]]:
        """Each label's neighbours in the frame's graph (the labelled nodes next to it),
        sorted: :attr:`graph`'s adjacency, without building it (networkx is imported only
        by what asks for the graph itself)."""
        labels: dict[int, Any] = self.labels  # a world's labels compare with each other
        adjacency = self.world.adjacency
        return {labels[u]: tuple(sorted(labels[w] for w in adjacency[u] if w in labels))
                for u in labels}

    @cached_property
    def distances(self) -> Mapping[Label, dict[Label, int]]:
        """Per visible node, the hops to the others inside the frame's graph (only those
        reachable): each row computed when first read (an algorithm reads few: go-to-target
        its own node's)."""
        return _DistanceRows(self._adjacent)

    def neighbours(self, label: Label) -> tuple[Label, ...]:
        """The neighbours of ``label`` in the frame's graph, sorted."""
        return self._adjacent[label]

    @cached_property
    def _shown(self) -> dict[frozenset[int], frozenset[Label]]:
        return {}

    def shown(self, nodes: frozenset[int]) -> frozenset[Label]:
        """The labels of those of ``nodes`` in the frame (the meeting nodes a view shows:
        computed once per set)."""
        if not isinstance(nodes, frozenset):
            nodes = frozenset(nodes)
        got = self._shown.get(nodes)
        if got is None:
            got = self._shown[nodes] = frozenset(self.labels[u] for u in nodes
                                                 if u in self.labels)
        return got
