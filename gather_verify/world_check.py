"""Verify an algorithm on a finite world against a task: the search, the verdict, the trace
(SEMANTICS.md §9, §11).

The world, the algorithm, the scheduler and the task are resolved once, here, and
handed to the search as objects. The verdict follows §5: VIOLATED with the first
failing part and its trace; VERIFIED only when the whole space was searched and
every part holds; INCOMPLETE when a limit stopped the search first (a safety part
found failing on the way is still VIOLATED: its trace is real).

>>> r = run_world_check("ring:9", "0 3 5", "7", "go-to-target", "async", reduction=False)
>>> r["verdict"], r["states"], r["transitions"], r["task"]
('VERIFIED', 225, 560, 'gathering-on-meeting-nodes')
"""

from __future__ import annotations

import time
from typing import Any

from gather_verify.algorithms import Algorithm, get_algorithm
from gather_verify.engine import world_bulk
from gather_verify.engine.bounds import SetupStopped, setup
from gather_verify.engine.encoding import (
    DEFAULT_MAX_MEMORY_MB,
    DEFAULT_MAX_SECONDS,
    DEFAULT_MAX_STATES,
    Limits,
    Stop,
)
from gather_verify.engine.world_search import WorldSearch, WorldState, search
from gather_verify.errors import InvalidInput
from gather_verify.progress import PROGRESS
from gather_verify.tasks import TASKS, Context, Finding, Task, get_task
from gather_verify.tasks.base import fair_walk
from gather_verify.watchdog import Overtime, allowance, deadline
from gather_verify.worlds import finite_world
from gather_verify.worlds.base import World
from gather_verify.worlds.moves import WorldMoves, parse_lights
from schedulers import get_scheduler

ENGINES = ("auto", "reference", "bulk")
"""``--engine`` on a finite world (:func:`run_world_check`)."""
PSEUDO = ("crash", "defined")
"""Checked on every task: the algorithm must answer a move in every view it meets."""


def plane_only() -> set[str]:
    """The properties registered for the paper's world (Z²) that no task of a finite world
    has as a part (the paper's ``target-invariance``, ``no-ungatherable`` and ``move-bound``,
    and any other property registered for Z²): asked for on a finite world, one line, never
    a vacuous pass."""
    from gather_verify.properties.registry import names

    parts = {part for name in TASKS for part in get_task(name).parts}
    return set(names()) - parts - set(PSEUDO)


def default_task(meeting: list[int]) -> str:
    """``gathering-on-meeting-nodes`` when meeting nodes are given, else ``gathering``."""
    return "gathering-on-meeting-nodes" if meeting else "gathering"


def run_world_check(world: str | World, robots: str | list[int], meeting: str | list[int],
                    algorithm: str | Algorithm, scheduler: str, *, task: str | None = None,
                    properties: list[str] | None = None, detection: str = "local-weak",
                    frames: str = "all", visibility: int | None = None,
                    lights: str | None = None, colours: list[int] | None = None,
                    reduction: bool = True, max_states: int = DEFAULT_MAX_STATES,
                    max_seconds: float = DEFAULT_MAX_SECONDS,
                    max_memory_mb: float = DEFAULT_MAX_MEMORY_MB,
                    engine: str = "auto") -> dict[str, Any]:
    """Check ``algorithm`` from one initial configuration of ``world``; a JSON-ready report
    (``verdict``, ``property``, ``reason``, ``states``, ``transitions``, per-part results,
    the counterexample ``trace``, ``seconds`` of the whole check and ``search_seconds`` of
    the search alone).

    ``engine``: ``bulk`` (:mod:`gather_verify.engine.world_bulk`, refused in one line when it
    cannot run the request), ``reference`` (:mod:`gather_verify.engine.world_search`), or
    ``auto`` (the default: the bulk engine when it can, else the reference). Both find the
    same search (``tests/test_world_bulk.py``); the report names the engine that ran
    (``engine``) and, when ``auto`` fell back to the reference, why (``engine_fallback``)."""
    started = time.perf_counter()
    if engine not in ENGINES:
        raise InvalidInput(f"unknown engine {engine!r}: use one of {', '.join(ENGINES)}")
    name = world if isinstance(world, str) else world.name
    try:  # the setup is bounded by the limits too (gather_verify.engine.bounds)
        with setup(f"building {name} and what its search needs", max_seconds, max_memory_mb):
            w = finite_world(world) if isinstance(world, str) else world
            r = w.parse_nodes(robots) if isinstance(robots, str) else list(robots)
            m = w.parse_nodes(meeting) if isinstance(meeting, str) else list(meeting)
            if not r:
                raise InvalidInput("no robots: give at least one robot node")
            distinct(w, r, "robots", "an initial configuration has robots on distinct nodes")
            distinct(w, m, "meeting nodes", "give each meeting node once")
            if visibility is not None and visibility < 0:
                raise InvalidInput(f"visibility {visibility} is negative: give a number of hops "
                                   ">= 0")
            with deadline(allowance(max_seconds)):  # the algorithm's file imports in time
                algo = get_algorithm(algorithm) if isinstance(algorithm, str) else algorithm
            sched = get_scheduler(scheduler)  # resolved once: the engines take the objects
            light = parse_lights(lights)
            check_colours(colours, r, light.colours)
            t = get_task(task or default_task(m))
            parts = _parts(t, properties, w)
            check_task(t, w, m)
            liveness = any(p in t.liveness for p in parts)
            reduce = reduction and not liveness
            symmetries = w.symmetries(frames) if reduce else ()
            for v in set(r):  # the frames of the first views (a graph file's automorphisms)
                w.frames(v, visibility, frames)
    except SetupStopped as stop:
        nodes, at = [x.split() if isinstance(x, str) else list(x) for x in (robots, meeting)]
        return stopped_report(stop.stop, stop.reason, name, task or default_task(at),
                              algorithm, scheduler, detection, frames, visibility, nodes, at,
                              lights, started)
    stateful = getattr(sched, "stateful", False)
    moves = WorldMoves(w, algo, frozenset(m), detection, frames, visibility, light)
    limits = Limits(max_states=max_states, max_memory_mb=max_memory_mb,  # the time left
                    max_seconds=max(0.0, max_seconds - (time.perf_counter() - started)))
    reductions = (reductions_used(stateful) if reduce else
                  "off: liveness needs robot identities" if reduction and liveness
                  else "off")  # (the search reduces exactly when ``reduce`` holds)
    PROGRESS.states = 0
    fallback = None if engine == "reference" else world_bulk.unsupported(
        w, len(r), sched, light.colours, visits=t.visits, anonymity=reduce,
        symmetries=symmetries, meeting=frozenset(m))
    if engine == "bulk" and fallback is not None:
        raise InvalidInput(f"the bulk engine cannot run this check: {fallback} (use --engine auto "
                           "or reference)")

    def decided() -> dict[str, Any]:
        PROGRESS.doing = "exploring"
        if engine != "reference" and fallback is None:
            s = world_bulk.search(w, tuple(r), moves, sched, colours=colours,
                                  visits=t.visits, anonymity=reduce, symmetries=symmetries,
                                  meeting=frozenset(m), limits=limits)
        else:
            s = search(w, tuple(r), moves.actions, sched, colours=colours, visits=t.visits,
                       anonymity=reduce, symmetries=symmetries, meeting=frozenset(m),
                       limits=limits)
        ctx = Context(len(r), w.size, frozenset(m), scheduler,
                      tuple(w.format_node(v) for v in range(w.size)))
        results: dict[str, dict[str, Any]] = {}
        first: Finding | None = None
        if s.halt is not None:
            first = Finding(s.halt.property, s.halt.state, s.halt.reason, detail=s.halt.detail)
            results[s.halt.property] = {"holds": False, "reason": s.halt.reason}
        PROGRESS.doing = f"deciding the task's properties ({', '.join(parts)})"
        found = t.check(s, ctx) if s.halt is None else {}
        for name in parts:
            got = found.get(name)
            if got is not None:
                results[name] = {"holds": False, "reason": got.reason}
                first = first or got
            elif s.complete:
                results[name] = {"holds": True}
            else:
                why = (f"the search stopped ({s.stopped}) before the whole space was seen"
                       if s.halt is None else f"the search stopped at a {s.halt.property} violation")
                results[name] = {"holds": None, "reason": why}
        for name in PSEUDO:
            results.setdefault(name, {"holds": True} if s.complete else
                               {"holds": None, "reason": "the search did not finish"})
        if first is not None:
            verdict = "VIOLATED"
        elif s.complete:
            verdict = "VERIFIED"
        else:
            verdict = "INCOMPLETE"
        return {
            "verdict": verdict,
            "world": w.name,
            "task": t.name,
            "algorithm": algo.name,
            "scheduler": scheduler,
            "detection": detection,
            "frames": frames,
            "visibility": visibility,
            "robots": [w.node_to_json(v) for v in r],
            "meeting_nodes": [w.node_to_json(v) for v in m],
            "property": None if first is None else first.property,
            "reason": (first.reason if first is not None else
                       None if s.complete else str(s.stopped)),  # the limit, as on Z²
            "stopped": s.stopped,
            "states": s.states,
            "transitions": s.transitions,
            "engine": s.engine,
            **({"engine_fallback": fallback} if fallback is not None else {}),
            "lights": str(light),
            "reductions": reductions,
            "properties": results,
            "trace": None if first is None else trace_of(w, s, first, r, m, algo.name, scheduler,
                                                         t.name, detection, frames, visibility,
                                                         str(light)),
            "seconds": time.perf_counter() - started,
            "search_seconds": s.seconds,
        }

    try:  # the user's code that does not return ends with the time limit (watchdog)
        with deadline(allowance(max_seconds)):
            return decided()
    except Overtime as stopped:
        report = stopped_report(
            Stop.TIME, f"time (the watchdog stopped your code: still running "
            f"{stopped.seconds:g} s into the check)", w.name, t.name, algo.name, scheduler,
            detection, frames, visibility, [w.node_to_json(v) for v in r],
            [w.node_to_json(v) for v in m], str(light), started, parts)
        report["reductions"] = reductions
        report["engine"] = "bulk" if engine != "reference" and fallback is None else "reference"
        if fallback is not None:
            report["engine_fallback"] = fallback
        return report


def stopped_report(stop: Stop, reason: str, world: str, task: str | None, algorithm: Any,
                   scheduler: str, detection: str, frames: str, visibility: int | None,
                   robots: Any, meeting: Any, lights: str | None, started: float,
                   parts: list[str] | None = None) -> dict[str, Any]:
    """The INCOMPLETE report of a check a limit stopped before its search could report
    (the setup, or the watchdog over the user's code): ``reason`` names the limit and the
    step, every property is unknown, nothing is claimed."""
    if parts is None:
        parts = list(get_task(task).parts) if task in TASKS else []
    names = [*parts, *PSEUDO]
    return {
        "verdict": "INCOMPLETE", "world": world, "task": task, "scheduler": scheduler,
        "algorithm": algorithm if isinstance(algorithm, str) else getattr(algorithm, "name", "?"),
        "detection": detection, "frames": frames, "visibility": visibility,
        "robots": robots, "meeting_nodes": meeting, "property": None, "reason": reason,
        "stopped": str(stop), "states": PROGRESS.states, "transitions": 0,
        "engine": "none (stopped before the search)", "lights": str(lights or 1),
        "reductions": "-",
        "properties": {name: {"holds": None, "reason": f"the check stopped ({stop})"}
                       for name in names},
        "trace": None, "seconds": time.perf_counter() - started,
    }


def distinct(world: World, nodes: list[int], what: str, rule: str) -> None:
    """One line naming the first node given twice (as the paper's world refuses it)."""
    seen: set[int] = set()
    for v in nodes:
        if v in seen:
            raise InvalidInput(f"{what}: node {world.format_node(v)} is given twice ({rule})")
        seen.add(v)


def check_colours(colours: list[int] | None, robots: list[int], k: int) -> None:
    """One initial colour per robot, each in ``0 .. k-1`` (one line for anything else)."""
    if colours is not None and (len(colours) != len(robots) or any(
            isinstance(c, bool) or not isinstance(c, int) or not 0 <= c < k
            for c in colours)):
        raise InvalidInput(f"initial colours {colours}: one per robot, each in 0..{k - 1}")


def check_task(task: Task, world: World, meeting: list[int]) -> None:
    """The task can run here: its meeting nodes given, its visited set small enough."""
    if task.needs_meeting and not meeting:
        raise InvalidInput(f"task {task.name} needs meeting nodes: give --meeting")
    if task.visits and world.size > 62:
        raise InvalidInput(f"task {task.name} tracks visited nodes in the state: {world.name} "
                           f"has {world.size} nodes, at most 62 are supported")


def reductions_used(stateful: bool) -> str:
    """What a reduced search merges (the report's ``reductions``): anonymity, as the scheduler
    relabels identical robots when it keeps a state of its own (round-robin: so that its
    order is the first it may fix), and the symmetries fixing the meeting nodes, which move
    the robots' nodes and leave that state alone."""
    if stateful:
        return ("anonymity (robots relabelled so that the scheduler's own state is its first "
                "start), the symmetries fixing the meeting nodes (which leave that state alone)")
    return "anonymity, the symmetries fixing the meeting nodes"


def _parts(task: Task, properties: list[str] | None, world: World) -> list[str]:
    """The task's parts to check: all of them, or those named (one line for any other)."""
    if not properties:
        return list(task.parts)
    out = []
    for name in properties:
        if name not in task.parts and name in plane_only():
            raise InvalidInput(f"property {name} is a property of the paper's world (Z² with "
                               f"meeting nodes, --world grid): {world.name} cannot support it")
        if name in PSEUDO:
            continue
        if name not in task.parts:
            raise InvalidInput(f"task {task.name} has no property {name!r}: use "
                               f"{', '.join(task.parts)}")
        out.append(name)
    return out


def trace_of(world: World, s: WorldSearch, finding: Finding, robots: list[int],
             meeting: list[int], algorithm: str, scheduler: str, task: str, detection: str,
             frames: str, visibility: int | None, lights: str = "1") -> dict[str, Any]:
    """The counterexample as JSON: the shortest path to the failing state (then, for a
    liveness part, the cycle the run can stay on; for a transition part, the failing
    event), every state in the world's node names, and the world's drawing
    (:meth:`~gather_verify.worlds.base.World.drawing`) so that a picture of the trace needs
    nothing but the trace. On a task that explores, each step names the nodes visited so far
    (from the state when the search carries them, else counted along the trace). Under a
    scheduler that keeps its own state (round-robin) the trace names the start its run began
    in (``round-robin:order=1 0 2``), as on Z², so that replay follows that start alone.

    Each state of the trace is the real successor of the one before (:func:`concrete_run`):
    the search stores a class by the first member it met, and under the reductions the
    target of the failing event can be stored as another member of its class."""
    ids = s.path_to(finding.state)
    hops = [_edge_between(s, a, b) for a, b in zip(ids, ids[1:], strict=False)]
    cycle_start = None
    if finding.cycle is not None:  # a fair closed walk through the component (§5)
        walk = (fair_walk(s, finding.component, len(robots), finding.state)
                if finding.component is not None else
                [_edge_between(s, a, b)
                 for a, b in zip(finding.cycle, finding.cycle[1:], strict=False)])
        if walk:
            cycle_start = len(ids) - 1
        hops += walk
    if finding.edge is not None:  # a transition part: the failing round itself
        hops.append(finding.edge)
    sched = get_scheduler(scheduler)
    run = concrete_run(s, sched, ids[0], hops, get_task(task).visits)
    keys = [state for _, state in run]
    scheduler = scheduler_from(scheduler, keys[0][2])
    steps = [_step(world, event, key) for event, key in run]
    if get_task(task).explores and not any("visited" in step for step in steps):
        seen = 0
        for step, key in zip(steps, keys, strict=True):
            for v, *_ in key[0]:
                seen |= 1 << v
            step["visited"] = [world.node_to_json(v) for v in range(world.size) if seen >> v & 1]
    return {
        "world": world.name, "task": task, "algorithm": algorithm, "scheduler": scheduler,
        "detection": detection, "frames": frames, "visibility": visibility, "lights": lights,
        "property": finding.property, "reason": finding.reason,
        "detail": {k: (world.node_to_json(v) if k == "node" else v)
                   for k, v in finding.detail.items()},
        "robots": [world.node_to_json(v) for v in robots],
        "meeting_nodes": [world.node_to_json(v) for v in meeting],
        "steps": steps, "cycle_start": cycle_start, "drawing": world.drawing(),
        **({"graph_digest": digest} if isinstance(digest := getattr(world, "digest", None), str)
           else {}),
    }


def concrete_run(s: WorldSearch, sched: Any, start: int, hops: list[tuple[int, int]],
                 visits: bool) -> list[tuple[Any, WorldState]]:
    """The run that follows ``hops`` (per step, a stored state's id and the index of an edge
    of it) from the stored state ``start``, as ``(event, state)`` pairs (the first event
    None): each state the event applied to the state before, the scheduler's own state
    advanced by the scheduler, as on Z² (:meth:`~gather_verify.engine.explore.Exploration.concretise`).

    A stored state is the first member of its class the search met, the successor of its
    BFS parent's, so along BFS parents (and everywhere in an unreduced search) each real
    state is the stored one. A hop's target need not be: under the reductions it may be
    stored as another member of its class (an image by anonymity or Aut(G)); the run goes
    on from the real one. A hop whose source is not its stored state is a bug of ours: its
    events were read off the stored state."""
    state: WorldState = s.keys[start]
    run: list[tuple[Any, WorldState]] = [(None, state)]
    for a, k in hops:
        if state != s.keys[a]:  # pragma: no cover - the hops leave the stored states last
            raise AssertionError(f"state {a} of the run is not its stored state")
        target, _, event = s.edges[a][k]
        state = successor(sched, state, event, visits)
        if s.canonical(state) != s.canonical(s.keys[target]):  # pragma: no cover
            raise AssertionError(f"edge {k} of state {a} does not reach the class of {target}")
        run.append((event, state))
    return run


def successor(sched: Any, state: WorldState, event: Any, visits: bool) -> WorldState:
    """The state ``event`` leads to from ``state``: the robots as the event moves them, the
    nodes visited (when the search carries them) and the scheduler's own state after it."""
    from gather_verify.world_replay import scheduler_after  # a trace's need, not a search's

    robots, visited, extra = state
    after = _apply(state, event)
    extra = next(iter(scheduler_after(sched, robots, extra, event, after)))
    if visits:
        for v, _, _ in after:
            visited |= 1 << v
    return after, visited, extra


def scheduler_from(scheduler: str, start: object) -> str:
    """The scheduler's name as a trace whose run began in the scheduler's own state ``start``
    gives it: its start fixed when it keeps one (round-robin's ``pinned`` order), else as
    it is."""
    pinned = getattr(get_scheduler(scheduler), "pinned", None)
    return scheduler if start is None or pinned is None else str(pinned(start))


def _edge_between(s: WorldSearch, a: int, b: int) -> tuple[int, int]:
    """The edge from state ``a`` to ``b`` as ``(a, its index)``, the one whose event takes the
    stored ``a`` to the stored ``b`` (along BFS parents and inside an unreduced cycle, each
    stored state is the concrete successor of the one before)."""
    for k, (target, _, event) in enumerate(s.edges[a]):
        if target == b and _apply(s.keys[a], event) == s.keys[b][0]:
            return a, k
    raise AssertionError(f"no edge from state {a} to {b}")  # pragma: no cover


def _apply(state: Any, event: Any) -> tuple[tuple[int, int | None, int], ...]:
    robots = list(state[0])
    for i, _, new in event.lights:
        robots[i] = (robots[i][0], robots[i][1], new)
    for i, src, dst in event.moves:
        if event.kind == "look":
            robots[i] = (src, dst, robots[i][2])
        else:
            robots[i] = (dst, None, robots[i][2])
    return tuple(robots)


def _step(world: World, event: Any, state: Any) -> dict[str, Any]:
    from gather_verify.world_replay import event_json

    name = world.node_to_json
    out: dict[str, Any] = {
        "event": None if event is None else event_json(world, event),
        "robots": [[name(v), None if p is None else name(p)] for v, p, _ in state[0]],
    }
    if any(c for _, _, c in state[0]) or (event is not None and event.lights):
        out["colours"] = [c for _, _, c in state[0]]
    if state[1]:
        out["visited"] = [name(v) for v in range(world.size) if state[1] >> v & 1]
    return out


def render_world_trace(trace: dict[str, Any]) -> str:
    """The trace as text, one line per step (``*`` marks where the cycle starts)."""
    lines = [f"{trace['property']}: {trace['reason']}"]
    for k, step in enumerate(trace["steps"]):
        colours = step.get("colours")
        robots = "  ".join(f"r{i}@{_txt(v)}" + ("" if p is None else f"->{_txt(p)}")
                           + ("" if colours is None else f"[{colours[i]}]")
                           for i, (v, p) in enumerate(step["robots"]))
        event = step["event"]
        if event is None:
            what = "start"
        else:
            changes = [f"r{i} {_txt(a)}->{_txt(b)}" for i, a, b in event["moves"]]
            changes += [f"r{i} light {a}->{b}" for i, a, b in event.get("lights", [])]
            what = event["kind"] + " " + (", ".join(changes) or
                                          "r" + ",r".join(map(str, event["robots"])))
        mark = "*" if trace.get("cycle_start") == k else " "
        lines.append(f"{mark}{k:3d}  {what:28}  {robots}")
    if trace.get("cycle_start") is not None:
        lines.append(f"  (from * the run can repeat the cycle forever: steps "
                     f"{trace['cycle_start']}..{len(trace['steps']) - 1})")
    elif trace.get("property") == "perpetual-exploration":
        lines.append("  (every robot is idle and may stay: a fair run can stay in the last "
                     "state for ever)")
    return "\n".join(lines)


def _txt(node: Any) -> str:
    return ",".join(map(str, node)) if isinstance(node, list) else str(node)
