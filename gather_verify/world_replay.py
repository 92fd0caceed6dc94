"""Replay of a finite world's trace: re-execute it from scratch and confirm its violation
(SEMANTICS.md §9-11), without the search.

A trace of a finite world (:func:`gather_verify.world_check.trace_of`) names its world, its
task and the failing part. Replay builds the world, the algorithm's move sets
(:class:`~gather_verify.worlds.moves.WorldMoves`) and the scheduler again, and walks the
trace: every event must be one the scheduler offers from the state before when each acting
robot does what the trace says (a node it can reach in one edge, a colour of the lights:
else the trace does not match itself, exit 2), the recorded state must be the one reached,
and the algorithm must still choose that action (else it no longer reproduces: exit 5,
``step-not-taken``). Under round-robin the scheduler follows the order the trace names
(``round-robin:order=1 0 2``, as on Z²); a trace without one (written before traces named
it) is followed from every order, and accepted when one of them produces it. The failure
of the part is then re-established on the replayed states (else exit 5,
``property-holds``):

- ``crash`` / ``defined``: the algorithm still raises / has no rule in the last state;
- ``final``, ``gathered-when-final``: the last state is final (nothing pending, every robot's
  only action is to stay) and the robots are not together (on a meeting node);
- ``explored-when-final``: the last state is final and some node was never visited;
- ``exclusivity``: two robots on one node in the last state, or the last round moves two
  robots across one edge in opposite directions;
- ``termination``: the run from ``cycle_start`` returns to the same state, no state of the
  trace is final, and the cycle is fair (§5: every robot has an event in it, or is idle in a
  state of it where it may stay);
- ``perpetual-exploration``: the same fair cycle (or, without a cycle, a last state that
  every robot may stay in for ever), with the node ``detail.node`` empty all along it.

>>> from gather_verify.world_check import run_world_check
>>> r = run_world_check("ring:6", "0 2", "", "ring-gather", "fsync", task="gathering",
...                     detection="global-weak")
>>> r["property"], replay_world(r["trace"]).confirmed
('gathered-when-final', True)
"""

from __future__ import annotations

import json
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any, NoReturn

from gather_verify.algorithms import AlgorithmCrash, Unhandled, get_algorithm
from gather_verify.errors import InvalidInput
from gather_verify.inputs import read_text
from gather_verify.tasks import get_task
from gather_verify.viewer import world_trace_problem
from gather_verify.worlds import finite_world
from gather_verify.worlds.base import World
from gather_verify.worlds.moves import WorldMoves, parse_lights
from schedulers import Event, get_scheduler

LRobots = tuple[tuple[int, int | None, int], ...]
"""Per robot: node, pending destination (None when idle), colour (node indices)."""
PSEUDO = ("crash", "defined")
"""Parts every task checks: the algorithm answers a move in every view it meets."""


class NoLongerReproduces(InvalidInput):
    """The world trace no longer reproduces (``replay`` exits 5, ``step-not-taken``).

    Cause: every step is a legal execution of the robots, but the algorithm (edited since
    the trace was written) no longer takes one of them. Fix: run ``check`` again for a
    fresh trace."""


@dataclass
class WorldReplayed:
    confirmed: bool
    message: str
    steps: int


def read_trace(source: str | Path) -> Any:
    """The JSON of a trace file (a scenario that stores one under ``trace``: that trace), as
    it is; one line when it is not JSON."""
    try:
        data = json.loads(read_text(source, "trace"))
    except json.JSONDecodeError as error:
        raise InvalidInput(f"bad trace {source}: not JSON ({error.msg} at line "
                           f"{error.lineno})") from None
    except RecursionError:
        raise InvalidInput(f"bad trace {source}: not JSON (nested too deeply)") from None
    if isinstance(data, dict) and "robots" in data and isinstance(data.get("trace"), dict):
        data = data["trace"]
    return data


def _fail(message: str) -> NoReturn:
    raise InvalidInput(f"bad trace: {message}")


def world_of(spec: str, folder: Path | None) -> World:
    """The trace's world; a relative ``graph:FILE`` is taken from the trace's folder, else
    from the working directory."""
    if spec.startswith("graph:") and folder is not None:
        path = Path(spec[6:])
        if not path.is_absolute() and (folder / path).is_file():
            spec = f"graph:{folder / path}"
    try:
        return finite_world(spec)
    except InvalidInput as error:
        _fail(f"its world: {error}")


@dataclass
class WorldTrace:
    """A world trace, checked and read into node indices."""

    raw: dict[str, Any]
    world: World
    robots: list[int]
    meeting: list[int]
    events: list[Event]
    states: list[LRobots]
    visited: list[frozenset[int] | None]


def load_world_trace(trace: dict[str, Any], folder: Path | None = None) -> WorldTrace:
    """A world trace validated and read (one line naming the first problem when it is
    malformed). ``folder``: the trace file's folder, for its algorithm and graph files."""
    problem = world_trace_problem(trace)
    if problem is not None:
        _fail(problem)
    if not isinstance(trace.get("detail", {}), dict):
        _fail("'detail' must be an object")
    vis = trace.get("visibility")
    if vis is not None and (isinstance(vis, bool) or not isinstance(vis, int) or vis < 0):
        _fail("'visibility' must be null or a number of hops >= 0")
    if folder is not None:
        from gather_verify.algorithms.loading import confined_spec

        trace = {**trace, "algorithm": confined_spec(trace["algorithm"], folder, "the trace")}
    world = world_of(trace["world"], folder)
    _same_graph(trace, world)

    def node(value: object, where: str) -> int:
        try:
            return world.node_from_json(value)
        except InvalidInput as error:
            _fail(f"{where}: {error}")

    robots = [node(v, "'robots'") for v in trace["robots"]]
    meeting = [node(v, "'meeting_nodes'") for v in trace["meeting_nodes"]]
    n = len(robots)
    if n == 0:
        _fail("no robots")
    try:
        light = parse_lights(str(trace.get("lights", "1")))
    except InvalidInput as error:
        _fail(f"'lights': {error}")
    states: list[LRobots] = []
    events: list[Event] = []
    visited: list[frozenset[int] | None] = []
    for k, step in enumerate(trace["steps"]):
        where = f"step {k}"
        if not isinstance(step, dict):
            _fail(f"{where} must be an object")
        pairs = step.get("robots")
        if not isinstance(pairs, list) or len(pairs) != n or not all(
                isinstance(p, list) and len(p) == 2 for p in pairs):
            _fail(f"{where}: 'robots' must list {n} pairs [node, pending]")
        colours = step.get("colours", [0] * n)
        if not isinstance(colours, list) or len(colours) != n or any(
                isinstance(c, bool) or not isinstance(c, int) or not 0 <= c < light.colours
                for c in colours):
            _fail(f"{where}: 'colours' must list {n} colours in 0..{light.colours - 1}")
        states.append(tuple((node(v, where), None if p is None else node(p, where), c)
                            for (v, p), c in zip(pairs, colours, strict=True)))
        seen = step.get("visited")
        if seen is not None and not isinstance(seen, list):
            _fail(f"{where}: 'visited' must be a list of nodes")
        visited.append(None if seen is None else frozenset(node(v, where) for v in seen))
        event = step.get("event")
        if k == 0:
            if event is not None:
                _fail("step 0 is the initial state: its event is null")
            continue
        events.append(_event(event, where, node, n))
    if [v for v, _, _ in states[0]] != robots or any(p is not None for _, p, _ in states[0]):
        _fail("step 0 is not the initial configuration, every robot idle")
    cs = trace.get("cycle_start")
    if cs is not None and (isinstance(cs, bool) or not isinstance(cs, int)
                           or not 0 <= cs < len(states)):
        _fail("'cycle_start' must be null or a step index 0..len(steps) - 1")
    return WorldTrace(trace, world, robots, meeting, events, states, visited)


def _same_graph(trace: dict[str, Any], world: World) -> None:
    """A trace of a graph file replays only on the graph it was written on: its
    ``graph_digest`` names the file's content; a trace without one is compared by its
    drawing's nodes and edges, and one with neither is refused (it cannot tell)."""
    mine = getattr(world, "digest", None)
    if not isinstance(mine, str):
        return  # a world of its name alone (ring:9): nothing can change under it
    changed = (f"the graph file of {world.name} is not the one the trace was written on "
               "(its content changed)")
    digest = trace.get("graph_digest")
    if digest is not None:
        if digest != mine:
            _fail(changed)
        return
    drawing = trace.get("drawing")
    if not isinstance(drawing, dict):
        _fail(f"it names no graph_digest and no drawing: it cannot tell whether the graph file "
              f"of {world.name} is the one it was written on")
    try:
        labels = [n["label"] for n in drawing["nodes"]]
        ends = sorted(tuple(sorted(e["ends"])) for e in drawing["edges"])
    except (KeyError, TypeError):
        _fail("'drawing' must hold 'nodes' with a 'label' and 'edges' with 'ends'")
    now = world.drawing()
    if labels != [n["label"] for n in now["nodes"]] or \
            ends != sorted(tuple(sorted(e["ends"])) for e in now["edges"]):
        _fail(changed)


def _event(raw: object, where: str, node: Callable[[object, str], int], n: int) -> Event:
    if not isinstance(raw, dict) or not {"kind", "robots", "moves"} <= set(raw) \
            or not set(raw) <= {"kind", "robots", "moves", "lights"}:
        _fail(f"{where}: an event is an object with 'kind', 'robots', 'moves' (and 'lights')")

    def index(i: object) -> int:
        if isinstance(i, bool) or not isinstance(i, int) or not 0 <= i < n:
            _fail(f"{where}: {i!r} is not a robot index 0..{n - 1}")
        return i

    def triples(value: object, what: str) -> list[list[Any]]:
        if not isinstance(value, list) or not all(isinstance(t, list) and len(t) == 3
                                                  for t in value):
            _fail(f"{where}: {what!r} must be a list of [robot, a, b]")
        return value

    if not isinstance(raw["kind"], str) or not isinstance(raw["robots"], list):
        _fail(f"{where}: 'kind' is a string and 'robots' a list of robot indices")
    moves = tuple((index(i), node(a, where), node(b, where))
                  for i, a, b in triples(raw["moves"], "moves"))
    lights = []
    for i, a, b in triples(raw.get("lights", []), "lights"):
        if any(isinstance(c, bool) or not isinstance(c, int) for c in (a, b)):
            _fail(f"{where}: a light change is [robot, old colour, new colour]")
        lights.append((index(i), a, b))
    return Event(raw["kind"], tuple(index(i) for i in raw["robots"]), moves,  # type: ignore[arg-type]
                 tuple(lights))


def scheduler_after(sched: Any, before: Any, extra: object, event: Any, after: Any
                    ) -> list[object]:
    """The scheduler's own state after ``event`` (a list of one), when it offers ``event``
    from the robots ``before`` (its own state ``extra``) and the event reaches ``after`` with
    each acting robot doing what ``after`` shows it did; else an empty list."""
    chosen = chosen_actions(event, after)
    legal = {i: frozenset({chosen[i]}) if i in chosen else frozenset({(v, c)})
             for i, (v, _, c) in enumerate(before)}
    for got, succ, nxt in sched.luminous(before, extra, legal.__getitem__):
        if same_event(got, event) and succ == after:
            return [nxt]
    return []


def same_event(a: Any, b: Any) -> bool:
    """One event: the same kind, robots, moves and colour changes."""
    return (a.kind, a.robots, sorted(a.moves), sorted(a.lights)) == \
        (b.kind, b.robots, sorted(b.moves), sorted(b.lights))


def chosen_actions(event: Any, after: Any) -> dict[int, tuple[int, int]]:
    """What each robot that computed in ``event`` chose, read from the state after it: its
    destination (its new node after a round, its pending one after a Look) and colour."""
    out: dict[int, tuple[int, int]] = {}
    if event.kind == "move":
        return out
    for i in event.robots:
        v, pending, colour = after[i]
        out[i] = (pending if event.kind == "look" and pending is not None else v, colour)
    return out


def replay_world(trace: dict[str, Any], folder: Path | None = None) -> WorldReplayed:
    """Re-execute a world trace and confirm its failure (see the module): confirmed or not,
    with why; :class:`NoLongerReproduces` when the algorithm no longer takes a step;
    :class:`InvalidInput` (one line) when the trace is malformed or does not match itself."""
    t = load_world_trace(trace, folder)
    raw, world = t.raw, t.world
    try:
        task = get_task(raw["task"])
    except InvalidInput as error:
        _fail(str(error))
    prop = raw["property"]
    if prop not in task.parts and prop not in PSEUDO:
        _fail(f"task {task.name} has no part {prop!r}: use {', '.join(task.parts + PSEUDO)}")
    try:
        algorithm = get_algorithm(raw["algorithm"])
        scheduler = get_scheduler(raw["scheduler"])
        light = parse_lights(str(raw.get("lights", "1")))
        moves = WorldMoves(world, algorithm, frozenset(t.meeting), raw["detection"],
                           raw["frames"], raw.get("visibility"), light)
    except InvalidInput as error:
        _fail(str(error))
    n = len(t.robots)
    # the scheduler's own state (round-robin's order and turn): a trace names the start its
    # run began in (round-robin:order=1 0 2), then that start alone is followed; an older
    # trace without it is followed from every start, keeping those it is consistent with
    try:
        runs: list[list[object]] = [[extra] for extra in
                                    getattr(scheduler, "starts", lambda _n: [None])(n)]
    except InvalidInput as error:
        _fail(f"its scheduler: {error}")
    actions: list[list[frozenset[tuple[int, int]]]] = []
    for k, (event, after) in enumerate(zip(t.events, t.states[1:], strict=True), 1):
        before = t.states[k - 1]
        chosen = chosen_actions(event, after)
        for i, (d, _) in chosen.items():
            v = before[i][0]
            if d != v and d not in world.adjacency[v]:
                _fail(f"step {k}: robot {i} cannot reach {world.format_node(d)} from "
                      f"{world.format_node(v)} in one edge")
        kept = [[*run, extra] for run in runs
                for extra in scheduler_after(scheduler, before, run[-1], event, after)]
        if not kept:
            _fail(f"step {k}: the event {_text(world, event)} is not allowed from the state "
                  "before, or does not reach the recorded state"
                  + (f" (under {raw['scheduler']}, the order the trace names)"
                     if ":order=" in raw["scheduler"] else ""))
        runs = kept
        try:
            offered = moves.actions(before)
        except (AlgorithmCrash, Unhandled) as error:
            raise NoLongerReproduces(f"step {k}: the algorithm does not decide the state before "
                                     f"any more ({error})") from None
        actions.append(offered)
        for i, action in chosen.items():
            if action not in offered[i]:
                raise NoLongerReproduces(f"step {k}: the algorithm no longer lets robot {i} "
                                         f"do {_action_text(world, action)} "
                                         f"({_text(world, event)})")
    seen = _visits(t.states)
    for k, recorded in enumerate(t.visited):
        if recorded is not None and recorded != seen[k]:
            _fail(f"step {k}: the visited nodes are not those of the steps up to it")
    last = t.states[-1]
    try:
        actions.append(moves.actions(last))
    except AlgorithmCrash as error:
        if prop == "crash":
            return WorldReplayed(True, error.reason, len(t.events))
        raise NoLongerReproduces(f"the algorithm crashes in the last state: {error}") from None
    except Unhandled as error:
        if prop == "defined":
            return WorldReplayed(True, f"the algorithm has no rule here: {error}", len(t.events))
        raise NoLongerReproduces(f"the algorithm has no rule in the last state: {error}") from None
    if prop in PSEUDO:
        return WorldReplayed(False, f"the algorithm decides the last state ({prop} holds)",
                             len(t.events))
    final = [all(p is None and acts[i] == {(v, c)} for i, (v, p, c) in enumerate(state))
             for state, acts in zip(t.states, actions, strict=True)]
    confirmed, message = _confirm(prop, t, final, actions, seen, runs)
    return WorldReplayed(confirmed, message, len(t.events))


def _confirm(prop: str, t: WorldTrace, final: list[bool],
             actions: Sequence[Sequence[frozenset[tuple[int, int]]]],
             seen: list[frozenset[int]], runs: list[list[object]]) -> tuple[bool, str]:
    """Whether the replayed run shows the failure of ``prop``, and why (or why not)."""
    world, last = t.world, t.states[-1]
    nodes = {v for v, _, _ in last}
    if prop in ("final", "gathered-when-final"):
        if not final[-1]:
            return False, "the last state is not final: a robot can still act"
        if len(nodes) > 1:
            return True, f"deadlock: no robot can move, robots on {len(nodes)} nodes"
        if prop == "final" and not nodes <= set(t.meeting):
            return True, "the robots stopped together on a node that is not a meeting node"
        return False, "the robots are gathered" + (" on a meeting node" if prop == "final" else "")
    if prop == "explored-when-final":
        if not final[-1]:
            return False, "the last state is not final: a robot can still act"
        missing = world.size - len(seen[-1])
        if missing:
            return True, f"the robots stopped with {missing} node(s) never visited"
        return False, "every node was visited"
    if prop == "exclusivity":
        if len(nodes) < len(last):
            return True, "two robots on one node"
        event = t.events[-1] if t.events else None
        if event is not None and event.kind == "round":
            crossing = {(a, b) for _, a, b in event.moves}
            if any((b, a) in crossing for a, b in crossing):
                return True, "two robots cross one edge in opposite directions in one round"
        return False, "no two robots on one node in the last state, and no crossing round"
    if prop in ("termination", "perpetual-exploration"):
        return _fair_cycle(prop, t, final, actions, runs)
    return False, f"replay does not confirm {prop!r}"  # pragma: no cover - every part above


def _fair_cycle(prop: str, t: WorldTrace, final: list[bool],
                actions: Sequence[Sequence[frozenset[tuple[int, int]]]],
                runs: list[list[object]]) -> tuple[bool, str]:
    """A liveness part: the cycle from ``cycle_start`` returns and is fair (§5), and what
    the part needs of its states."""
    world, n = t.world, len(t.robots)
    start = t.raw.get("cycle_start")
    end = len(t.states) - 1
    if start is None:
        if prop == "termination":
            return False, "the trace has no cycle (cycle_start is null)"
        start = end  # the run stays on the last state by null activations
    else:
        if start == end:
            return False, "the cycle has no step"
        if t.states[start] != t.states[end]:
            return False, f"the last state is not state {start}: the cycle does not return"
        if not any(run[start] == run[end] for run in runs):
            return False, (f"the scheduler's turn at the last state is not the one at state "
                           f"{start}: the cycle does not return")
    cycle = range(start, end + 1)
    covered = set()
    for k in cycle:
        covered |= {i for i, (v, p, c) in enumerate(t.states[k])
                    if p is None and (v, c) in actions[k][i]}
    for event in t.events[start:end]:
        covered |= set(event.robots)
    unfair = sorted(set(range(n)) - covered)
    if unfair:
        return False, (f"the cycle is not fair: robot {unfair[0]} has no event in it and is "
                       "never idle in it with staying among its actions")
    if prop == "termination":
        if any(final):
            return False, f"the run reaches a final state (step {final.index(True)})"
        return True, ("livelock: a fair execution never reaches a final state (it repeats the "
                      f"steps {start}..{end} for ever)")
    target = t.raw.get("detail", {}).get("node")
    if target is None:
        _fail("a perpetual-exploration trace names the node never visited again in "
              "detail.node")
    try:
        v = world.node_from_json(target)
    except InvalidInput as error:
        _fail(f"detail.node: {error}")
    if any(u == v for k in cycle for u, _, _ in t.states[k]):
        return False, f"node {world.format_node(v)} is visited on the cycle"
    return True, f"a fair execution stops visiting node {world.format_node(v)}"


def _visits(states: Sequence[LRobots]) -> list[frozenset[int]]:
    """Per step, the nodes the robots have stood on so far."""
    out, seen = [], frozenset[int]()
    for state in states:
        seen = seen | {v for v, _, _ in state}
        out.append(seen)
    return out


def _action_text(world: World, action: tuple[int, int]) -> str:
    d, c = action
    return world.format_node(d) + (f" with colour {c}" if c else "")


def event_json(world: World, event: Any) -> dict[str, Any]:
    """An event as a trace writes it: nodes as the world writes them."""
    name = world.node_to_json
    return {"kind": event.kind, "robots": list(event.robots),
            "moves": [[i, name(a), name(b)] for i, a, b in event.moves],
            **({"lights": [list(x) for x in event.lights]} if event.lights else {})}


def _text(world: World, event: Event) -> str:
    return json.dumps(event_json(world, event))
