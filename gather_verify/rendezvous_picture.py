"""A rendezvous trace in the viewer (:mod:`gather_verify.viewer`): the data its page embeds,
with a picture per state read at a glance.

Each state is drawn as the two robots on a horizontal segment (long when ``far``, short
when ``near``, one point when ``same``), each disc filled with its light (a light being
changed shows the new colour as a ring), the robot's phase under it, and its pending move
as an arrow: to the midpoint, to the other, or dashed and crossed for a ``miss``. The
robots that took the step are outlined in blue. The viewer steps through the pictures as
through the other worlds' traces (buttons, slider, arrow keys, the timeline, the cycle).

The trace is read field by field (one line, exit 2, for a trace that is none); only what
was read reaches a picture.

>>> from gather_verify.rendezvous_check import run_rendezvous_check
>>> t = run_rendezvous_check("to-other", "fsync", movement="rigid")["trace"]
>>> data = annotate(t)
>>> len(data["pictures"]) == len(t["steps"]), data["states"][0]["summary"]
(True, 'near')
>>> data["events"][0]["text"]
'A+B: look+begin-compute+end-compute+begin-move+end-move: A sees black, decides to-other; B sees black, decides to-other; A near -> same; B same -> near'
"""

from __future__ import annotations

from typing import Any

from gather_verify.errors import InvalidInput
from gather_verify.worlds.rendezvous import state_from_json, state_to_json
from gather_verify.worlds.rendezvous_rules import MOVES, POSITIONS, colour_name
from schedulers.phases import PHASES

FILL = {"black": "#222", "white": "#fff", "red": "#d62728", "yellow": "#f2c500",
        "green": "#2ca02c"}
SPAN = {"far": 360, "near": 180, "same": 0}
"""The segment's length per relative position (pixels)."""
PHASE = {"look": "idle", "begin-compute": "looked", "end-compute": "computing",
         "begin-move": "computed", "end-move": "moving"}
"""What a robot is doing before its next step (its phase names the next step)."""
Y = 80
WIDTH, HEIGHT = 500, 150
COLUMNS = ["robot", "doing", "light", "pending move"]
"""The viewer's table of robots, one row per robot."""
LEGEND = (
    "<svg width='22' height='16'><circle cx='10' cy='8' r='6' fill='#fff' stroke='#555'/>"
    "</svg> a robot, filled with its light "
    "<svg width='26' height='18'><circle cx='12' cy='9' r='8' fill='#d62728' stroke='#555'/>"
    "<circle cx='12' cy='9' r='5' fill='#222'/></svg> a light being changed (ring: the new "
    "colour, shown at End-Compute) "
    "<svg width='34' height='16'><line x1='2' y1='8' x2='26' y2='8' stroke='#444' "
    "stroke-width='2'/><path d='M24,3 L32,8 L24,13 z' fill='#444'/></svg> pending move "
    "<svg width='34' height='16'><line x1='2' y1='8' x2='26' y2='8' stroke='#444' "
    "stroke-width='2' stroke-dasharray='6 4'/><path d='M10,2 L18,14 M10,14 L18,2' "
    "stroke='#d62728' stroke-width='2'/></svg> a miss (its target has moved) "
    "<svg width='22' height='16'><circle cx='10' cy='8' r='6' fill='#fff' stroke='#1f77b4' "
    "stroke-width='3'/></svg> stepped in this event ")
"""The pictures' legend (fixed markup: no text of a trace)."""


def _fill(c: int) -> str:
    return FILL.get(colour_name(c), "#8c564b")


def _robot(x: float, r: dict[str, Any], name: str, stepped: bool, dy: float) -> str:
    """A robot's disc (its light; a ring of the colour its Compute chose), name and phase
    (beside the disc when both stand at one point, under it otherwise)."""
    ring = ""
    if r["next"] != r["colour"]:
        ring = (f"<circle cx='{x}' cy='{Y + dy}' r='24' fill='{_fill(r['next'])}' "
                "stroke='#555' stroke-width='1'/>")
    edge = "#1f77b4" if stepped else "#555"
    label = (f"<text x='{x}' y='{Y + 44}' text-anchor='middle' font-size='12'>" if dy == 0 else
             f"<text x='{x + (-40 if dy < 0 else 40)}' y='{Y + dy + 5}' font-size='12' "
             f"text-anchor='{'end' if dy < 0 else 'start'}'>")
    return (f"<g class='robot' data-robot='{name}' data-light='{colour_name(r['colour'])}'>"
            f"{ring}<circle cx='{x}' cy='{Y + dy}' r='18' fill='{_fill(r['colour'])}' "
            f"stroke='{edge}' stroke-width='{4 if stepped else 1.5}'/>"
            f"<text x='{x}' y='{Y + dy + 5}' text-anchor='middle' font-size='14' "
            f"fill='{'#fff' if r['colour'] in (0, 2) else '#000'}'>{name}</text>"
            f"{label}{PHASE[r['phase']]}</text></g>")


def _arrow(x: float, to: float, move: str, i: int, dy: float) -> str:
    """Robot ``i``'s pending move as an arrow above the segment (A's lower, B's higher);
    at one point, a move (a miss) leaves sideways."""
    if move == "stay":
        return ""
    if x == to:
        to = x + (95 if i == 0 else -95)  # away from its phase label
    y = Y + dy - (30 if i == 0 else 52) if dy == 0 else Y + dy
    x += (to - x) / abs(to - x) * 26 if dy != 0 else 0
    dash = " stroke-dasharray='6 4'" if move == "miss" else ""
    line = (f"<line class='pending' x1='{x}' y1='{y}' x2='{to}' y2='{y}' stroke='#444' "
            f"stroke-width='2'{dash} marker-end='url(#rv-head)'/>")
    if move == "miss":
        m = (x + to) / 2
        line += (f"<path d='M{m - 6},{y - 6} L{m + 6},{y + 6} M{m - 6},{y + 6} L{m + 6},{y - 6}'"
                 f" stroke='#d62728' stroke-width='2.5'/>")
    return line + f"<text x='{(x + to) / 2}' y='{y - 8}' text-anchor='middle' font-size='11'>" \
        f"{move}</text>"


def frame(state: dict[str, Any], stepped: set[int]) -> dict[str, Any]:
    """One state as an SVG picture (``width``, ``height``, ``body``): the segment, the two
    robots, their pending moves; the robots in ``stepped`` outlined."""
    half = SPAN[state["position"]] / 2
    xa, xb = WIDTH / 2 - half, WIDTH / 2 + half
    a, b = state["robots"]
    dy = (-22, 22) if half == 0 else (0, 0)  # at one point: one above the other
    mid = WIDTH / 2
    target = {"to-half": (mid, mid), "to-other": (xb, xa), "miss": (mid, mid)}
    parts = ["<defs><marker id='rv-head' markerWidth='8' markerHeight='8' refX='7' refY='4' "
             "orient='auto'><path d='M0,0 L8,4 L0,8 z' fill='#444'/></marker></defs>",
             f"<line class='segment' x1='{xa}' y1='{Y}' x2='{xb}' y2='{Y}' stroke='#999' "
             "stroke-width='3'/>",
             f"<text x='{WIDTH - 10}' y='18' text-anchor='end' font-size='13' "
             f"fill='#666'>{state['position']}</text>"]
    for x, r, i in ((xa, a, 0), (xb, b, 1)):
        to = target.get(r["pending"], (x, x))[i]
        parts.append(_arrow(x, to, r["pending"], i, dy[i]))
        parts.append(_robot(x, r, "AB"[i], i in stepped, dy[i]))
    return {"width": WIDTH, "height": HEIGHT, "body": "".join(parts)}


def _bad(k: int, what: str) -> InvalidInput:
    return InvalidInput(f"bad rendezvous trace: step {k}: {what}")


def _who(i: Any) -> bool:
    return type(i) is int and i in (0, 1)


def _colour(c: Any, colours: int) -> bool:
    return type(c) is int and 0 <= c < colours


def _items(raw: dict[str, Any], field: str, k: int, form: str, ok: Any, size: int) -> list:
    """An event's list ``field`` (none: empty), each item a list of ``size`` that ``ok``
    accepts."""
    items = raw.get(field, [])
    if not isinstance(items, list) or not all(
            isinstance(x, list) and len(x) == size and ok(x) for x in items):
        raise _bad(k, f"an event's {field} are lists {form}")
    return items


def _event(raw: Any, k: int, colours: int) -> dict[str, Any]:
    """Step ``k``'s event, read: its kind (phases joined by ``+``), robots, moves (position
    before and after), lights (old and new colour) and chosen commands."""
    if not isinstance(raw, dict) or not isinstance(raw.get("kind"), str) or any(
            p not in PHASES for p in raw["kind"].split("+")):
        raise _bad(k, f"an event has a kind made of {', '.join(PHASES)} (joined by +)")
    robots = raw.get("robots")
    if not isinstance(robots, list) or not robots or not all(_who(i) for i in robots):
        raise _bad(k, "an event's robots are 0 and/or 1")
    moves = _items(raw, "moves", k, "[robot, position before, position after]",
                   lambda m: _who(m[0]) and m[1] in POSITIONS and m[2] in POSITIONS, 3)
    lights = _items(raw, "lights", k, "[robot, old colour, new colour]",
                    lambda x: _who(x[0]) and all(_colour(c, colours) for c in x[1:]), 3)
    chosen = _items(raw, "chosen", k, "[robot, move, new colour, [colours seen]]",
                    lambda c: _who(c[0]) and c[1] in MOVES and _colour(c[2], colours)
                    and isinstance(c[3], list) and all(_colour(x, colours) for x in c[3]), 4)
    return {"kind": raw["kind"], "robots": robots, "moves": moves, "lights": lights,
            "chosen": chosen}


def event_text(event: dict[str, Any]) -> str:
    """One line for an event: ``A: look: sees white, decides to-half, light -> black``.

    >>> event_text({"kind": "end-move", "robots": [1], "moves": [[1, "same", "near"]],
    ...             "lights": [], "chosen": []})
    'B: end-move: same -> near'
    """
    who = (lambda i: "AB"[i] + " ") if len(event["robots"]) > 1 else (lambda i: "")
    parts = [f"{who(i)}sees {'/'.join(colour_name(c) for c in seen)}, decides {move}"
             for i, move, _, seen in event["chosen"]]
    parts += [f"{who(i)}light {colour_name(a)} -> {colour_name(b)}"
              for i, a, b in event["lights"]]
    parts += [f"{who(i)}{a} -> {b}" for i, a, b in event["moves"]]
    head = "+".join("AB"[i] for i in event["robots"]) + ": " + event["kind"]
    return head + (": " + "; ".join(parts) if parts else "")


def _robot_row(name: str, r: dict[str, Any]) -> list[str]:
    light = colour_name(r["colour"]) + (f" (Compute chose {colour_name(r['next'])})"
                                        if r["next"] != r["colour"] else "")
    return [name, f"{PHASE[r['phase']]} (next: {r['phase']})", light, r["pending"]]


def _text(trace: dict[str, Any], key: str) -> str:
    value = trace.get(key)
    if not isinstance(value, str):
        raise InvalidInput(f"bad rendezvous trace: {key!r} must be a string")
    return value


def annotate(trace: dict[str, Any]) -> dict[str, Any]:
    """The data the viewer embeds for a rendezvous trace: the trace in the viewer's shape
    (``trace``: state 0, then one step per event), a picture per state (``pictures``), per
    state its position (``summary``, ``rows``) and one row per robot (``robots`` under
    :data:`COLUMNS`), per event its text, the settings (``meta``) and the legend."""
    steps, cs = trace.get("steps"), trace.get("cycle_start")
    if not isinstance(steps, list) or not steps:
        raise InvalidInput("bad rendezvous trace: 'steps' must be a non-empty list")
    if cs is not None and (type(cs) is not int or not 0 <= cs < len(steps)):
        raise InvalidInput("bad rendezvous trace: 'cycle_start' must be null or a step index")
    colours = trace.get("colours", 64)
    if type(colours) is not int or not 1 <= colours <= 64:
        raise InvalidInput("bad rendezvous trace: 'colours' must be a number of colours")
    states = [state_to_json(state_from_json(s.get("state") if isinstance(s, dict) else None,
                                            colours, f"step {k}"))
              for k, s in enumerate(steps)]
    events = [_event(s["event"], k, colours) for k, s in enumerate(steps) if k]
    normal: dict[str, Any] = {
        "initial": {"robots": [], "meeting_nodes": []}, "cycle_start": cs,
        "steps": [{"event": e, "state": s} for e, s in zip(events, states[1:], strict=True)],
        **{key: _text(trace, key) for key in ("algorithm", "scheduler", "property")},
        "reason": str(trace.get("reason") or ""), "detail": {}}
    meta = [["world", "rendezvous"], ["algorithm", normal["algorithm"]],
            ["scheduler", normal["scheduler"]],
            *[[key.replace("_", " "), str(trace[key])] for key in
              ("movement", "initial_colours", "lights", "colours") if key in trace]]
    return {
        "trace": normal,
        "pictures": [frame(s, set(events[k - 1]["robots"]) if k else set())
                     for k, s in enumerate(states)],
        "states": [{"summary": s["position"], "rows": [["position", s["position"]]],
                    "robots": [_robot_row("AB"[i], r) for i, r in enumerate(s["robots"])]}
                   for s in states],
        "events": [{"text": event_text(e), "decisions": [], "loop_decisions": []}
                   for e in events],
        "columns": COLUMNS, "meta": meta, "legend": LEGEND, "n": 2,
    }
