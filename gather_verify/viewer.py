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

>>> from gather_verify.check import run_check
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
from importlib import resources
from typing import Any

from gather_verify.model.configuration import Configuration
from gather_verify.model.geometry import bounding_box
from gather_verify.trace import load_trace

MAX_ANNOTATED_STATES = 5000
"""Longer traces are shown without move sets (they cost one view per robot and frame)."""


def _node(v: Any) -> list[int] | None:
    return None if v is None else [int(v[0]), int(v[1])]


def _states(trace: dict[str, Any]) -> list[list[dict[str, Any]]]:
    first = [{"node": list(r), "pending": None} for r in trace["initial"]["robots"]]
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
    from gather_verify.model.classes import classify_configuration

    meeting = frozenset(tuple(m) for m in trace["initial"]["meeting_nodes"])
    conf = Configuration.trusted(tuple(sorted(robots)), meeting)
    out: dict[str, Any] = {"class": None, "in_U": None, "target": None, "phase": None,
                           "guard": None, "moves": None, "unhandled": None}
    try:
        cls = classify_configuration(conf)
        out["class"], out["in_U"] = cls.name, bool(cls.in_U)
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
            out["moves"] = {f"{v[0]},{v[1]}": sorted(_node(d) for d in s)  # type: ignore[type-var]
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
    return sorted(tuple(r["node"]) for r in state)  # type: ignore[misc]


def _decision(states: list, robot: int, look: int, now: int) -> dict[str, Any]:
    """The Look (event ``look``) behind a Move of ``robot`` made from state ``now``: the
    snapshot it saw (state ``look - 1``) and whether the robots have moved since (stale)."""
    seen, now_state = states[look - 1], states[now]
    moved = [f"r{i}" for i, (a, b) in enumerate(zip(seen, now_state, strict=True))
             if a["node"] != b["node"]]
    return {"robot": robot, "look": look, "snapshot": look - 1,
            "stale": _positions(seen) != _positions(now_state), "moved_since": moved}


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
    algorithm was loaded at all."""
    trace = load_trace(trace)
    states = _states(trace)
    steps = trace["steps"]
    algorithm = _load_algorithm(trace["algorithm"], load_code)
    with_moves = len(states) <= MAX_ANNOTATED_STATES
    cache: dict[tuple, dict[str, Any]] = {}
    infos = []
    for state in states:
        key = tuple(_positions(state))
        if key not in cache:
            cache[key] = _state_info(algorithm, trace, list(key), with_moves)
        infos.append(cache[key])
    cs = trace.get("cycle_start")
    events = []
    for k, step in enumerate(steps, 1):
        ev = step["event"]
        item: dict[str, Any] = {"text": event_text(ev), "decisions": [], "loop_decisions": []}
        if ev["kind"] == "move":
            for i in ev["robots"]:
                look = _look_before(steps, i, k, 0)
                if look is not None:
                    item["decisions"].append(_decision(states, i, look, k - 1))
                if cs is not None and k > cs:
                    # when the cycle repeats, the Look is the last one of the cycle before this
                    # Move, cyclically (the robot is idle after its Move, and the cycle ends
                    # in the state it started from, so it looked again in the cycle)
                    loop = _look_before(steps, i, k, cs) or _look_before(steps, i, len(steps) + 1, k)
                    if loop is not None:
                        item["loop_decisions"].append(_decision(states, i, loop, k - 1))
        events.append(item)
    pending_since = []  # per state, per robot: the event of the Look behind its pending move
    since: list[int | None] = [None] * len(states[0])
    pending_since.append(list(since))
    for k, step in enumerate(steps, 1):
        ev = step["event"]
        for i in ev["robots"]:
            since[i] = k if ev["kind"] == "look" and step["state"][i]["pending"] else None
        pending_since.append(list(since))
    nodes = [tuple(m) for m in trace["initial"]["meeting_nodes"]]
    for state in states:
        nodes += [tuple(r["node"]) for r in state]
        nodes += [tuple(r["pending"]) for r in state if r["pending"]]
    return {
        "trace": trace,
        "states": infos,
        "events": events,
        "pending_since": pending_since,
        "box": list(bounding_box(nodes)),  # type: ignore[arg-type]
        "n": len(states[0]),
        "provides": provides(algorithm),
        "loaded": algorithm is not None,
    }


def _template() -> str:
    return resources.files("gather_verify").joinpath("viewer.html").read_text(encoding="utf-8")


def viewer_html(trace: dict[str, Any], title: str | None = None, load_code: bool = True) -> str:
    """The viewer page for ``trace`` (a complete HTML document, nothing external);
    ``load_code``: see :func:`annotate`."""
    data = annotate(trace, load_code)
    text = json.dumps(data, separators=(",", ":"), sort_keys=True)
    # "<" only occurs inside JSON strings; as \u003c it cannot end the <script> element
    text = text.replace("<", "\\u003c")
    name = title or (f"{trace['property']} fails: {trace['algorithm']} / {trace['scheduler']}")
    return (_template().replace("/*DATA*/null", text)
            .replace("<!--TITLE-->", html.escape(name)))


def write_viewer(trace: dict[str, Any], path: str, title: str | None = None,
                 load_code: bool = True) -> None:
    """Write the viewer page for ``trace`` to ``path``."""
    from pathlib import Path

    Path(path).write_text(viewer_html(trace, title, load_code), encoding="utf-8")
