"""Counterexample traces: one JSON format (docs/traces.md), built, loaded and validated.

A trace names the initial configuration, algorithm, scheduler, detection and
frames, then lists every event with the state after it (each robot's node and
pending destination, robots in the order of the initial configuration's
sorted robot list), the failing property, why it fails, and for a cycle the
index of the state where the cycle starts (``states[0]`` is the initial state).

>>> from gather_verify.model.configuration import Configuration
>>> t = build_trace(Configuration([(0, 0)], [(1, 0)]), "go-to-target", "async", "local-weak",
...                 "all", [], "final", "example")
>>> load_trace(t)["property"]
'final'
"""

from __future__ import annotations

import json
from collections.abc import Sequence
from pathlib import Path
from typing import Any, NoReturn

from gather_verify.errors import InvalidInput
from gather_verify.inputs import read_text
from gather_verify.model.configuration import Configuration, _as_node
from gather_verify.model.geometry import Node
from schedulers import SCHEDULERS, Event, State

FORMAT = "gather-verify-trace"
VERSION = 1
KINDS = tuple(dict.fromkeys(kind for s in SCHEDULERS.values() for kind in s.kinds))
"""Every event kind of the registered schedulers (``round``, ``look``, ``move``)."""


def state_json(state: State) -> list[dict[str, Any]]:
    """Each robot's node and pending destination, and its colour in a state with lights."""
    out: list[dict[str, Any]] = []
    for robot in state:
        v, p = robot[0], robot[1]
        out.append({"node": list(v), "pending": None if p is None else list(p)})
        if len(robot) > 2:
            out[-1]["colour"] = robot[2]
    return out


def build_trace(initial: Configuration, algorithm: str, scheduler: str, detection: str,
                frames: str, steps: Sequence[tuple[Event, State]], prop: str, reason: str,
                cycle_start: int | None = None, **detail: Any) -> dict[str, Any]:
    """The JSON object of a trace (``steps`` = (event, state after it))."""
    return {
        "format": FORMAT, "version": VERSION,
        "initial": {"robots": [list(r) for r in initial.robots],
                    "meeting_nodes": sorted(list(m) for m in initial.meeting_nodes)},
        "algorithm": algorithm, "scheduler": scheduler, "detection": detection, "frames": frames,
        "steps": [{"event": ev.to_json(), "state": state_json(st)} for ev, st in steps],
        "property": prop, "reason": reason, "cycle_start": cycle_start, "detail": detail,
    }


def _fail(message: str) -> NoReturn:
    raise InvalidInput(f"bad trace: {message}")


def _node(value: object, what: str) -> Node:
    try:
        return _as_node(value, what)
    except ValueError as error:
        raise InvalidInput(f"bad trace: {error}") from None


def parse_state(raw: object, n: int, where: str) -> State:
    if not isinstance(raw, list) or len(raw) != n:
        _fail(f"{where}: expected a list of {n} robots")
    out: list[Any] = []
    for r in raw:
        if not isinstance(r, dict) or set(r) - {"colour"} != {"node", "pending"}:
            _fail(f"{where}: each robot is an object with 'node' and 'pending' (and, with "
                  "lights, 'colour')")
        p = r["pending"]
        robot: tuple[Any, ...] = (_node(r["node"], "node"), None if p is None else _node(p, "pending"))
        if "colour" in r:
            c = r["colour"]
            if isinstance(c, bool) or not isinstance(c, int) or c < 0:
                _fail(f"{where}: a robot's 'colour' is an integer >= 0")
            robot = (*robot, c)
        out.append(robot)
    return tuple(out)


def parse_event(raw: object, where: str) -> Event:
    if not isinstance(raw, dict) or set(raw) - {"lights"} != {"kind", "robots", "moves"}:
        _fail(f"{where}: an event is an object with 'kind', 'robots' and 'moves' (and, with "
              "lights, 'lights')")
    if raw["kind"] not in KINDS:
        _fail(f"{where}: event kind must be one of {', '.join(KINDS)}")
    robots, moves = raw["robots"], raw["moves"]
    if not isinstance(robots, list) or not all(isinstance(i, int) and not isinstance(i, bool)
                                               for i in robots):
        _fail(f"{where}: 'robots' must be a list of robot indices")
    if not isinstance(moves, list) or not all(
            isinstance(m, list) and len(m) == 3 and isinstance(m[0], int)
            and not isinstance(m[0], bool) for m in moves):
        _fail(f"{where}: 'moves' must be a list of [robot, [x, y], [x, y]]")
    lights = raw.get("lights", [])
    if not isinstance(lights, list) or not all(
            isinstance(x, list) and len(x) == 3 and all(
                isinstance(c, int) and not isinstance(c, bool) for c in x) for x in lights):
        _fail(f"{where}: 'lights' must be a list of [robot, old colour, new colour]")
    return Event(raw["kind"], tuple(robots),
                 tuple((int(i), _node(a, "node"), _node(b, "node")) for i, a, b in moves),
                 tuple((i, a, b) for i, a, b in lights))


def load_trace(source: str | Path | dict[str, Any]) -> dict[str, Any]:
    """A validated trace (from a file path or an already parsed object, a trace or a
    scenario holding one under ``trace``); ValueError names the first problem."""
    if isinstance(source, dict):
        data = source
    else:
        try:
            data = json.loads(read_text(source, "trace"))
        except json.JSONDecodeError as error:
            raise InvalidInput(f"bad trace {source}: not JSON ({error.msg} at line {error.lineno})") from None
        except RecursionError:
            raise InvalidInput(f"bad trace {source}: not JSON (nested too deeply)") from None
    if isinstance(data, dict) and "robots" in data and isinstance(data.get("trace"), dict):
        data = data["trace"]  # a scenario file that stores its counterexample
    if not isinstance(source, dict) and isinstance(data, dict) \
            and isinstance(data.get("algorithm"), str):  # a file path is relative to the file
        from gather_verify.algorithms.loading import confined_spec

        data = {**data, "algorithm": confined_spec(data["algorithm"],
                                                   Path(source).resolve().parent, str(source))}
    if isinstance(data, dict) and "format" not in data and isinstance(data.get("world"), str):
        _fail(f"a trace of the finite world {data['world'][:80]!r}, not of Z² (replay, "
              "--html and --svg read it)")
    if not isinstance(data, dict) or data.get("format") != FORMAT:
        _fail(f"not a {FORMAT} object")
    if data.get("version") != VERSION:
        _fail(f"unsupported version {data.get('version')!r} (this verifier reads {VERSION})")
    for key in ("initial", "algorithm", "scheduler", "detection", "frames", "steps", "property"):
        if key not in data:
            _fail(f"missing {key!r}")
    for key in ("algorithm", "scheduler", "detection", "frames", "property"):
        if not isinstance(data[key], str):
            _fail(f"{key!r} must be a string, not {type(data[key]).__name__}")
    from gather_verify.model.view import DETECTION_MODELS, FRAME_SETS

    if data["detection"] not in DETECTION_MODELS:
        _fail(f"unknown detection {data['detection']!r}: one of {', '.join(DETECTION_MODELS)}")
    if data["frames"] not in FRAME_SETS:
        _fail(f"unknown frames {data['frames']!r}: one of {', '.join(FRAME_SETS)}")
    if not isinstance(data.get("detail", {}), dict):
        _fail("'detail' must be an object")
    init = data["initial"]
    if not isinstance(init, dict) or not isinstance(init.get("robots"), list) \
            or not isinstance(init.get("meeting_nodes"), list):
        _fail("'initial' needs 'robots' and 'meeting_nodes' lists")
    try:
        Configuration(init["robots"], init["meeting_nodes"], initial=True)
    except ValueError as error:
        _fail(f"initial configuration: {error}")
    if not isinstance(data["steps"], list):
        _fail("'steps' must be a list")
    cs = data.get("cycle_start")
    if cs is not None and (not isinstance(cs, int) or isinstance(cs, bool)
                           or not 0 <= cs <= len(data["steps"])):
        _fail("'cycle_start' must be null or a state index 0..len(steps)")
    return data


def initial_of(trace: dict[str, Any]) -> Configuration:
    return Configuration(trace["initial"]["robots"], trace["initial"]["meeting_nodes"], initial=True)


def steps_of(trace: dict[str, Any]) -> list[tuple[Event, State]]:
    n = len(trace["initial"]["robots"])
    out = []
    for k, step in enumerate(trace["steps"]):
        if not isinstance(step, dict) or set(step) != {"event", "state"}:
            _fail(f"step {k}: expected an object with 'event' and 'state'")
        out.append((parse_event(step["event"], f"step {k}"), parse_state(step["state"], n, f"step {k}")))
    return out
