"""The interactive trace viewer: one self-contained HTML file per counterexample.

``viewer_html(trace)`` returns a page with its script and style inline and
nothing loaded from the network, so it opens from ``file://``. Everything the
page shows that needs the model (the class of each configuration, the target
meeting node, the phase of ``paper``, every robot's move set, which snapshot a
pending move was decided on) is computed here, in Python, by :func:`annotate`,
and embedded as JSON; the page's script only draws and steps.

A Move under ASYNC executes a decision taken at the robot's Look, on the
snapshot it saw then. When the robots have moved since, the decision is
*stale*: :func:`annotate` names the Look and the snapshot, and the page shows
that snapshot beside the current configuration.

>>> from gather_verify.plane_check import run_check
>>> from gather_verify.model.configuration import Configuration
>>> r = run_check(Configuration([(0, 0), (2, 1)], [(1, 1)], initial=True), algorithm="go-to-target",
...               scheduler="async", max_states=1000, max_seconds=10, move_bound_c=0.1)
>>> data = annotate(r["trace"])
>>> data["states"][0]["class"], data["states"][0]["target"]
('I13', [1, 1])
>>> page = viewer_html(r["trace"])
>>> "<script src" in page, "<link" in page, "https://" in page
(False, False, False)
"""

from __future__ import annotations

import contextlib
import html
import json
import math
from importlib import resources
from typing import Any

from gather_verify.errors import InvalidInput
from gather_verify.model.configuration import Configuration
from gather_verify.model.geometry import bounding_box
from gather_verify.trace import KINDS, load_trace

MAX_ANNOTATED_STATES = 5000
"""Longer traces are shown without move sets (they cost one view per robot and frame)."""


def _node(v: Any) -> list[int] | None:
    return None if v is None else [int(v[0]), int(v[1])]


def _states(trace: dict[str, Any]) -> list[list[dict[str, Any]]]:
    first: list[dict[str, Any]] = [{"node": list(r), "pending": None}
                                   for r in trace["initial"]["robots"]]
    if trace.get("lights") is not None:  # a trace with lights: the initial colours
        colours = trace["initial"].get("colours") or [0] * len(first)
        for robot, colour in zip(first, colours, strict=True):
            robot["colour"] = colour
    return [first] + [step["state"] for step in trace["steps"]]


def event_text(event: dict[str, Any]) -> str:
    """One line for an event: ``look(r1): r1 decides (1, 0)``, ``move(r1): r1 (1, 1)->(1, 0)``,
    ``round(r0,r2): r0 (0, 0)->(0, 1)``.

    >>> event_text({"kind": "look", "robots": [1], "moves": [[1, [1, 1], [1, 0]]]})
    'look(r1): r1 decides (1, 0)'
    >>> event_text({"kind": "round", "robots": [0, 1], "moves": []})
    'round(r0,r1): all stay'
    """
    robots = ",".join(f"r{i}" for i in event["robots"])
    if event["kind"] == "look":
        moves = ", ".join(f"r{i} decides {tuple(b)}" for i, _, b in event["moves"])
    else:
        moves = ", ".join(f"r{i} {tuple(a)}->{tuple(b)}" for i, a, b in event["moves"])
    lights = ", ".join(f"r{i} light {a}->{b}" for i, a, b in event.get("lights", []))
    moves = ", ".join(part for part in (moves, lights) if part)
    return f"{event['kind']}({robots}): " + (moves or "all stay")


def _load_algorithm(name: str, load_code: bool = True) -> Any:
    """The algorithm named by a trace, for its phases and move sets; None when it cannot be
    had, or (``load_code`` false: a trace read from a results database) when it is not a
    registered name: a database never makes the viewer run a file it names."""
    from gather_verify.algorithms import get_algorithm
    from gather_verify.algorithms.loading import split_external
    from gather_verify.errors import InvalidInput

    if not load_code and split_external(name) is not None:
        return None
    try:
        return get_algorithm(name)
    except InvalidInput:
        return None  # a user algorithm not registered in this process: draw without it


def _state_info(algorithm: Any, trace: dict[str, Any], robots: list[tuple[int, int]],
                with_moves: bool) -> dict[str, Any]:
    """Class, target, phase, guard and move sets of one configuration (None where unknown)."""
    from gather_verify.algorithms import AlgorithmCrash, AlgorithmError, Unhandled, target_of
    from gather_verify.algorithms.base import phase_of
    from gather_verify.algorithms.moves import frames_for, move_sets
    from gather_verify.theory import get_fact

    meeting = frozenset(tuple(m) for m in trace["initial"]["meeting_nodes"])
    conf = Configuration.trusted(tuple(sorted(robots)), meeting)
    out: dict[str, Any] = {"class": None, "in_U": None, "target": None, "phase": None,
                           "guard": None, "moves": None, "unhandled": None}
    try:
        out["class"] = get_fact("class").of(conf)
        out["in_U"] = bool(get_fact("in_U").of(conf))
    except Exception as error:  # a picture must not fail on a configuration it cannot classify
        out["class"] = f"? ({error})"
    if algorithm is None:
        return out
    with contextlib.suppress(Unhandled, AlgorithmCrash):
        out["target"] = _node(target_of(algorithm, conf))
    plan = getattr(algorithm, "plan", None)
    if plan is not None:
        try:
            p = plan(conf)
            out["phase"], out["guard"] = p.phase, _node(getattr(p, "guard", None))
        except Unhandled as error:
            out["phase"], out["unhandled"] = "no rule", str(error)
    elif getattr(algorithm, "phase", None) is not None:  # an algorithm that names its rules
        out["phase"] = phase_of(algorithm, conf)
    if with_moves:
        try:
            sets = move_sets(algorithm, conf, trace["detection"], frames_for(trace["frames"]))
            out["moves"] = {f"{v[0]},{v[1]}": sorted(_node(d) for d in s)
                            for v, s in sets.items()}
        except Unhandled as error:
            out["unhandled"] = out["unhandled"] or str(error)
        except (AlgorithmError, AlgorithmCrash) as error:  # a crash, or a non-move answer
            out["unhandled"] = str(error)
    return out


def _look_before(steps: list[dict[str, Any]], robot: int, k: int, lo: int) -> int | None:
    """The event number (1-based) of the last Look of ``robot`` among events lo+1 .. k-1."""
    for j in range(k - 1, lo, -1):
        ev = steps[j - 1]["event"]
        if ev["kind"] == "look" and robot in ev["robots"]:
            return j
    return None


def _positions(state: list[dict[str, Any]]) -> list[tuple[int, int]]:
    return sorted(tuple(r["node"]) for r in state)


def _decision(states: list, robot: int, look: int, now: int) -> dict[str, Any]:
    """The Look (event ``look``) behind a Move of ``robot`` made from state ``now``: the
    snapshot it saw (state ``look - 1``) and whether the robots have moved since (stale)."""
    seen, now_state = states[look - 1], states[now]
    moved = [f"r{i}" for i, (a, b) in enumerate(zip(seen, now_state, strict=True))
             if a["node"] != b["node"]]
    relit = [f"r{i}" for i, (a, b) in enumerate(zip(seen, now_state, strict=True))
             if a.get("colour") != b.get("colour")]  # with lights: a colour changed since

    def lit(state: list[dict[str, Any]]) -> list[tuple[Any, ...]]:
        return sorted((*r["node"], r.get("colour", 0)) for r in state)

    return {"robot": robot, "look": look, "snapshot": look - 1,
            "stale": lit(seen) != lit(now_state), "moved_since": moved,
            **({"relit_since": relit} if relit else {})}


def provides(algorithm: Any) -> dict[str, bool]:
    """Which of the paper's rows an algorithm gives the viewer: a ``phase`` (its ``plan``'s,
    or its own ``phase``), a ``guard`` (a ``plan`` with one), a ``target`` meeting node.
    Nothing for an algorithm that was not loaded: the page then shows none of these rows.

    >>> from gather_verify.algorithms import get_algorithm
    >>> provides(get_algorithm("paper")), provides(get_algorithm("go-to-target"))
    ({'phase': True, 'guard': True, 'target': True}, {'phase': False, 'guard': False, 'target': True})
    """
    if algorithm is None:
        return {"phase": False, "guard": False, "target": False}
    plan = getattr(algorithm, "plan", None) is not None
    return {"phase": plan or getattr(algorithm, "phase", None) is not None, "guard": plan,
            "target": getattr(algorithm, "target", None) is not None}


def annotate(trace: dict[str, Any], load_code: bool = True) -> dict[str, Any]:
    """The data the viewer embeds: the trace, and per state its class, target, phase, guard and
    move sets; per event its text and, for an ASYNC Move, the Look it executes (its snapshot,
    stale or not; for an event in the cycle of a livelock also the Look it executes when the
    cycle repeats, which can be a different one); ``provides``: which of the rows phase,
    guard and target the algorithm gives (:func:`provides`), and ``loaded``: whether the
    algorithm was loaded at all. A trace of a finite world: :func:`annotate_world`; of a
    world that draws its own states: :func:`world_pictures`."""
    if is_world_trace(trace):
        return annotate_world(trace)
    pictured = world_pictures(trace)
    if pictured is not None:
        return pictured(trace)
    trace = load_trace(trace)
    states = _states(trace)
    algorithm = _load_algorithm(trace["algorithm"], load_code)
    lit = trace.get("lights") is not None
    # with lights a robot's moves depend on its colour: the page shows the colours instead
    with_moves = len(states) <= MAX_ANNOTATED_STATES and not lit
    cache: dict[tuple, dict[str, Any]] = {}
    infos = []
    for state in states:
        key = tuple(_positions(state))
        if key not in cache:
            cache[key] = _state_info(algorithm, trace, list(key), with_moves)
        infos.append({**cache[key], "colours": [r.get("colour", 0) for r in state]} if lit
                     else cache[key])
    events = _events(trace, states, event_text, _decision)
    nodes = [tuple(m) for m in trace["initial"]["meeting_nodes"]]
    for state in states:
        nodes += [tuple(r["node"]) for r in state]
        nodes += [tuple(r["pending"]) for r in state if r["pending"]]
    return {
        "trace": trace,
        "states": infos,
        "events": events,
        "pending_since": _pending_since(trace["steps"], len(states[0])),
        "box": list(bounding_box(nodes)),
        "n": len(states[0]),
        "provides": provides(algorithm),
        "loaded": algorithm is not None,
    }


def _events(trace: dict[str, Any], states: list, text: Any, decision: Any) -> list[dict[str, Any]]:
    """Per event its text and, for a Move, the Looks it executes (see :func:`annotate`)."""
    steps, cs = trace["steps"], trace.get("cycle_start")
    events = []
    for k, step in enumerate(steps, 1):
        ev = step["event"]
        item: dict[str, Any] = {"text": text(ev), "decisions": [], "loop_decisions": []}
        if ev["kind"] == "move":
            for i in ev["robots"]:
                look = _look_before(steps, i, k, 0)
                if look is not None:
                    item["decisions"].append(decision(states, i, look, k - 1))
                if cs is not None and k > cs:
                    # when the cycle repeats, the Look is the last one of the cycle before this
                    # Move, cyclically (the robot is idle after its Move, and the cycle ends
                    # in the state it started from, so it looked again in the cycle)
                    loop = _look_before(steps, i, k, cs) or _look_before(steps, i, len(steps) + 1, k)
                    if loop is not None:
                        item["loop_decisions"].append(decision(states, i, loop, k - 1))
        events.append(item)
    return events


def _pending_since(steps: list[dict[str, Any]], n: int) -> list[list[int | None]]:
    """Per state, per robot: the event of the Look behind its pending move."""
    out = []
    since: list[int | None] = [None] * n
    out.append(list(since))
    for k, step in enumerate(steps, 1):
        ev = step["event"]
        for i in ev["robots"]:
            since[i] = k if ev["kind"] == "look" and step["state"][i]["pending"] is not None \
                else None
        out.append(list(since))
    return out


# -- finite worlds ---------------------------------------------------------------------------
# A trace of a finite world (gather_verify.world_check) names its nodes as the world writes
# them and carries the world's drawing. The page draws from the drawing alone: here every node
# becomes its index in the drawing, and the trace takes the shape of a Z² trace (initial
# robots, steps of event and state) so that stepping, the timeline and stale snapshots work
# the same way on every world.

WORLD_TRACE_TEXT = ("world", "task", "algorithm", "scheduler", "detection", "frames",
                    "property", "reason")
WORLD_TRACE_LISTS = ("robots", "meeting_nodes", "steps")


def world_trace_problem(trace: dict[str, Any]) -> str | None:
    """What a finite world's trace lacks (a field, or its type), in words; None when every
    field a replay and a rendering read is there (a partial trace stored in a scenario is
    refused by ``check`` and ``test`` alike)."""
    for key in WORLD_TRACE_TEXT:
        if not isinstance(trace.get(key), str):
            return f"{key!r} must be a string"
    for key in WORLD_TRACE_LISTS:
        if not isinstance(trace.get(key), list):
            return f"{key!r} must be a list"
    if not trace["steps"]:
        return "'steps' is empty: the first step is the initial state"
    return None


def is_world_trace(trace: Any) -> bool:
    """A trace written by a finite world's check: it names its world (a trace of Z² has a
    ``format`` tag instead, and a ``world`` of ``grid`` or none)."""
    from gather_verify.worlds import FINITE, entry_of

    return isinstance(trace, dict) and "format" not in trace and isinstance(
        trace.get("world"), str) and entry_of(trace["world"]) == FINITE


def world_pictures(trace: Any) -> Any:
    """The annotation of a trace whose world draws its states itself, or None: the
    rendezvous world's entry (two robots in the plane have no nodes to draw) has
    :func:`gather_verify.rendezvous_picture.annotate`. The page then shows the world's
    picture of each state, its rows and its settings (``pictures``, ``states``,
    ``columns``, ``meta``, ``legend``)."""
    from gather_verify.worlds import NAMED_WORLDS, entry_of
    from gather_verify.worlds.rendezvous import RENDEZVOUS

    name = trace.get("world") if isinstance(trace, dict) and "format" not in trace else None
    if not isinstance(name, str) or name not in NAMED_WORLDS or entry_of(name) != RENDEZVOUS:
        return None
    from gather_verify.rendezvous_picture import annotate as pictured

    return pictured


def _bad(message: str) -> InvalidInput:
    return InvalidInput(f"bad world trace: {message}")


def _number(value: Any, what: str) -> float:
    if isinstance(value, bool) or not isinstance(value, int | float) or not math.isfinite(value):
        raise _bad(f"{what} must be a finite number, not {value!r:.40}")
    return float(value)


def _point(value: Any, what: str) -> list[float]:
    if not isinstance(value, list) or len(value) != 2:
        raise _bad(f"{what} must be a point [x, y]")
    return [_number(value[0], what), _number(value[1], what)]


def check_drawing(raw: Any) -> dict[str, Any]:
    """A world's drawing (:meth:`gather_verify.worlds.base.World.drawing`) as read from a
    trace: the keys the pictures use, checked (numbers finite, ends in range), nothing else."""
    if not isinstance(raw, dict) or not isinstance(raw.get("nodes"), list) or not raw["nodes"] \
            or not isinstance(raw.get("edges"), list):
        raise _bad("'drawing' needs a list of 'nodes' and a list of 'edges'")
    nodes = []
    for k, node in enumerate(raw["nodes"]):
        if not isinstance(node, dict) or "label" not in node:
            raise _bad(f"drawing node {k} needs a 'label'")
        nodes.append({"label": node["label"], "text": str(node.get("text", node["label"])),
                      "x": _number(node.get("x"), "a node's x"),
                      "y": _number(node.get("y"), "a node's y"),
                      "side": _point(node.get("side", [0.7071, -0.7071]), "a node's side")})
    edges = []
    for edge in raw["edges"]:
        ends = edge.get("ends") if isinstance(edge, dict) else None
        if not isinstance(ends, list) or len(ends) != 2 or not all(
                isinstance(e, int) and not isinstance(e, bool) and 0 <= e < len(nodes)
                for e in ends):
            raise _bad("a drawing edge needs 'ends', two node numbers of the drawing")
        item: dict[str, Any] = {"ends": list(ends)}
        if "lines" in edge:
            lines = edge["lines"]
            if not isinstance(lines, list) or not lines or not all(
                    isinstance(line, list) and len(line) >= 2 for line in lines):
                raise _bad("an edge's 'lines' must be lists of at least two points")
            item["lines"] = [[_point(p, "a line's point") for p in line] for line in lines]
        if edge.get("wraps") is True:
            item["wraps"] = True
        edges.append(item)
    outline = raw.get("outline")
    if outline is not None:
        if not isinstance(outline, dict) or not isinstance(outline.get("points"), list):
            raise _bad("the drawing's 'outline' needs 'points'")
        outline = {"points": [_point(p, "an outline point") for p in outline["points"]],
                   "wraps": outline.get("wraps") is True, "title": str(outline.get("title", ""))}
    return {"nodes": nodes, "edges": edges, "outline": outline}


def world_drawing(trace: dict[str, Any]) -> dict[str, Any]:
    """The drawing a world trace carries (checked), or, for a trace written before traces
    carried one, the drawing of the world it names."""
    if "drawing" in trace:
        return check_drawing(trace["drawing"])
    from gather_verify.worlds import finite_world

    try:
        return check_drawing(finite_world(trace["world"]).drawing())
    except InvalidInput as error:
        raise _bad(f"no drawing, and the world cannot be had ({error})") from None


def _int(value: Any, what: str) -> int:
    if isinstance(value, bool) or not isinstance(value, int):
        raise _bad(f"{what} must be an integer")
    return value


def world_event_text(event: dict[str, Any], name: Any) -> str:
    """One line for an event of a finite world, nodes as ``name`` writes them:
    ``look(r0): r0 decides 2``, ``move(r0): r0 1->2``, ``round(r0,r1): r0 0->1, r1 light 0->1``.

    >>> world_event_text({"kind": "round", "robots": [0, 1], "moves": [[0, 0, 1]],
    ...                   "lights": [[1, 0, 1]]}, str)
    'round(r0,r1): r0 0->1, r1 light 0->1'
    """
    robots = ",".join(f"r{i}" for i in event["robots"])
    if event["kind"] == "look":
        parts = [f"r{i} decides {name(b)}" for i, _, b in event["moves"]]
    else:
        parts = [f"r{i} {name(a)}->{name(b)}" for i, a, b in event["moves"]]
    parts += [f"r{i} light {a}->{b}" for i, a, b in event.get("lights", [])]
    return f"{event['kind']}({robots}): " + (", ".join(parts) or "all stay")


class _WorldTraceReader:
    """A finite world's trace read against its drawing: nodes by their label, robots by
    their index, each step's robots, colours, visited nodes and event; every mistake one
    line (:func:`_bad`)."""

    def __init__(self, trace: dict[str, Any], drawing: dict[str, Any]):
        self.index = {json.dumps(node["label"], sort_keys=True): i
                      for i, node in enumerate(drawing["nodes"])}
        self.names = [node["text"] for node in drawing["nodes"]]
        self.n = len(trace["robots"])
        # with lights, a step whose colours are all 0 leaves them out: every robot is lit 0
        self.luminous = str(trace.get("lights", "1")).partition(":")[0] not in ("", "1")

    def node(self, value: Any) -> int:
        found = self.index.get(json.dumps(value, sort_keys=True))
        if found is None:
            raise _bad(f"{json.dumps(value)[:40]} is not a node of the drawing")
        return found

    def robot(self, i: Any) -> int:
        i = _int(i, "a robot")
        if not 0 <= i < self.n:
            raise _bad(f"robot {i} is not one of the {self.n} robots")
        return i

    def robots_of(self, raw: Any, k: int) -> list[dict[str, Any]]:
        if not isinstance(raw, list) or len(raw) != self.n or not all(
                isinstance(r, list) and len(r) == 2 for r in raw):
            raise _bad(f"step {k}: 'robots' must list {self.n} pairs [node, pending]")
        return [{"node": self.node(v), "pending": None if p is None else self.node(p)}
                for v, p in raw]

    def colours_of(self, raw: dict[str, Any], k: int) -> list[int] | None:
        c = raw.get("colours")
        if c is not None and (not isinstance(c, list) or len(c) != self.n):
            raise _bad(f"step {k}: 'colours' must list {self.n} colours")
        return ([_int(x, "a colour") for x in c] if c is not None else
                [0] * self.n if self.luminous else None)

    def visited_of(self, raw: dict[str, Any], k: int) -> list[int] | None:
        seen = raw.get("visited")
        if seen is not None and not isinstance(seen, list):
            raise _bad(f"step {k}: 'visited' must be a list of nodes")
        return None if seen is None else sorted({self.node(v) for v in seen})

    def event_of(self, ev: Any, k: int) -> dict[str, Any]:
        if not isinstance(ev, dict) or ev.get("kind") not in KINDS \
                or not isinstance(ev.get("robots"), list) or not isinstance(ev.get("moves"), list):
            raise _bad(f"step {k}: an event has a 'kind' ({', '.join(KINDS)}), 'robots' and "
                       "'moves'")
        event: dict[str, Any] = {"kind": ev["kind"],
                                 "robots": [self.robot(i) for i in ev["robots"]], "moves": []}
        for m in ev["moves"]:
            if not isinstance(m, list) or len(m) != 3:
                raise _bad(f"step {k}: a move is [robot, from, to]")
            event["moves"].append([self.robot(m[0]), self.node(m[1]), self.node(m[2])])
        lights = ev.get("lights", [])
        if not isinstance(lights, list) or not all(isinstance(x, list) and len(x) == 3
                                                   for x in lights):
            raise _bad(f"step {k}: 'lights' is a list of [robot, old, new]")
        if lights:
            event["lights"] = [[self.robot(i), _int(a, "a colour"), _int(b, "a colour")]
                               for i, a, b in lights]
        return event


def annotate_world(trace: dict[str, Any]) -> dict[str, Any]:
    """The data the viewer embeds for a trace of a finite world: the trace in Z² shape with
    node indices of the drawing (``trace``, with the states under ``robots``), the
    ``drawing``, per state the ``colours`` and the ``visited`` nodes (None where the trace
    has none), per event its text and the Looks a Move executes (stale when a robot moved or
    changed its light since), the node the failing property names (``focus``: the node a
    fair run stops visiting, the node of a crashed robot) and the world's settings
    (``world``)."""
    if not isinstance(trace.get("steps"), list) or not trace["steps"] \
            or not isinstance(trace.get("robots"), list):
        raise _bad("a world trace needs 'robots' and a non-empty list of 'steps'")
    for key in ("algorithm", "scheduler", "detection", "frames", "property", "world"):
        if not isinstance(trace.get(key), str):
            raise _bad(f"{key!r} must be a string")
    drawing = world_drawing(trace)
    read = _WorldTraceReader(trace, drawing)
    n, names = read.n, read.names
    states, colours, visited, steps = [], [], [], []
    for k, raw in enumerate(trace["steps"]):
        if not isinstance(raw, dict):
            raise _bad(f"step {k} must be an object")
        states.append(read.robots_of(raw.get("robots"), k))
        colours.append(read.colours_of(raw, k))
        visited.append(read.visited_of(raw, k))
        if k:
            steps.append({"event": read.event_of(raw.get("event"), k), "state": states[-1]})
    normal, focus = _world_normal(trace, read, states, steps)

    def text(ev: dict[str, Any]) -> str:
        return world_event_text(ev, lambda v: names[v])

    def decision(_: list, robot: int, look: int, now: int) -> dict[str, Any]:
        seen = [(r["node"], c) for r, c in zip(states[look - 1], colours[look - 1] or [0] * n,
                                                strict=True)]
        current = [(r["node"], c) for r, c in zip(states[now], colours[now] or [0] * n,
                                                   strict=True)]
        return {"robot": robot, "look": look, "snapshot": look - 1,
                "stale": sorted(seen) != sorted(current),
                "moved_since": [f"r{i}" for i, (a, b) in enumerate(zip(seen, current,
                                                                      strict=True))
                                if a[0] != b[0]],
                "relit_since": [f"r{i}" for i, (a, b) in enumerate(zip(seen, current,
                                                                      strict=True))
                                if a[1] != b[1]]}

    return {
        "trace": normal,
        "robots": states,
        "drawing": drawing,
        "world": {"name": trace["world"], "task": str(trace.get("task", "")),
                  "visibility": trace.get("visibility"), "lights": str(trace.get("lights", "1"))},
        "states": [{"colours": c, "visited": v} for c, v in zip(colours, visited, strict=True)],
        "events": _events(normal, states, text, decision),
        "pending_since": _pending_since(steps, n),
        "focus": focus,
        "n": n,
    }


def _world_normal(trace: dict[str, Any], read: _WorldTraceReader,
                  states: list[list[dict[str, Any]]], steps: list[dict[str, Any]]
                  ) -> tuple[dict[str, Any], int | None]:
    """A finite world's trace in Z² shape (node indices of the drawing), and the node its
    failing property names (``focus``), if any."""
    cs = trace.get("cycle_start")
    if cs is not None and (isinstance(cs, bool) or not isinstance(cs, int)
                           or not 0 <= cs <= len(steps)):
        raise _bad("'cycle_start' must be null or a state index")
    meeting = trace.get("meeting_nodes", [])
    if not isinstance(meeting, list):
        raise _bad("'meeting_nodes' must be a list")
    detail = trace.get("detail") or {}
    if not isinstance(detail, dict):
        raise _bad("'detail' must be an object")
    named = detail.get("node", detail.get("robot_node"))  # the node, or the crashed robot's
    focus = None if named is None else read.node(named)
    shown = {k: (read.names[focus] if k == "node" and focus is not None else v)
             for k, v in detail.items() if k != "drift"}  # drift: a Z² notion
    normal = {
        "initial": {"robots": [r["node"] for r in states[0]],
                    "meeting_nodes": sorted({read.node(m) for m in meeting})},
        "steps": steps, "cycle_start": cs, "detail": shown,
        **{key: trace[key] for key in ("algorithm", "scheduler", "detection", "frames",
                                       "property")},
        "reason": str(trace.get("reason") or ""),
    }
    return normal, focus


def _template() -> str:
    return resources.files("gather_verify").joinpath("viewer.html").read_text(encoding="utf-8")


def viewer_html(trace: dict[str, Any], title: str | None = None, load_code: bool = True) -> str:
    """The viewer page for ``trace`` (a complete HTML document, nothing external);
    ``load_code``: see :func:`annotate`."""
    data = annotate(trace, load_code)
    text = json.dumps(data, separators=(",", ":"), sort_keys=True)
    # "<" only occurs inside JSON strings; as \u003c it cannot end the <script> element
    text = text.replace("<", "\\u003c")
    name = title or (f"{trace['property']} fails: {trace['algorithm']} / {trace['scheduler']}"
                     + (f" on {trace['world']}" if "format" not in trace
                        and isinstance(trace.get("world"), str) else ""))
    return (_template().replace("/*DATA*/null", text)
            .replace("<!--TITLE-->", html.escape(name)))


def write_viewer(trace: dict[str, Any], path: str, title: str | None = None,
                 load_code: bool = True) -> None:
    """Write the viewer page for ``trace`` to ``path``."""
    from pathlib import Path

    Path(path).write_text(viewer_html(trace, title, load_code), encoding="utf-8")
