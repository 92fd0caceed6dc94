"""Pictures of configurations and traces: ASCII grids for the terminal, an SVG storyboard.

Cells: ``.`` empty, ``M`` empty meeting node, a robot count (``1``, ``2`` ...)
off meeting nodes and ``[k]`` on a meeting node; ``y`` grows upwards. The SVG
is plain hand-written SVG (no dependency).

>>> print(ascii_grid([(0, 0), (1, 1)], [(1, 1)]))
 . [1]
 1  .
"""

from __future__ import annotations

from collections import Counter
from collections.abc import Iterable, Sequence
from typing import Any

from gather_verify.model.geometry import Node, bounding_box


def ascii_grid(robots: Sequence[Node], meeting: Iterable[Node],
               box: tuple[int, int, int, int] | None = None) -> str:
    """The configuration as text rows (top row = largest y)."""
    meeting = set(meeting)
    counts = Counter(robots)
    x0, y0, x1, y1 = box or bounding_box([*robots, *meeting])
    rows = []
    for y in range(y1, y0 - 1, -1):
        cells = []
        for x in range(x0, x1 + 1):
            k = counts.get((x, y), 0)
            if (x, y) in meeting:
                cells.append(f"[{k}]" if k else " M ")
            else:
                cells.append(f" {k} " if k else " . ")
        rows.append("".join(cells).rstrip())
    return "\n".join(rows)


def _states(trace: dict[str, Any]) -> list[list[dict[str, Any]]]:
    first = [{"node": r, "pending": None} for r in trace["initial"]["robots"]]
    return [first] + [step["state"] for step in trace["steps"]]


def _box(trace: dict[str, Any]) -> tuple[int, int, int, int]:
    nodes = [tuple(m) for m in trace["initial"]["meeting_nodes"]]
    for state in _states(trace):
        nodes += [tuple(r["node"]) for r in state]
    return bounding_box(nodes)  # type: ignore[arg-type]


def _event_text(event: dict[str, Any]) -> str:
    moves = ", ".join(f"r{i} {tuple(a)}->{tuple(b)}" for i, a, b in event["moves"])
    robots = ",".join(f"r{i}" for i in event["robots"])
    return f"{event['kind']}({robots})" + (f": {moves}" if moves else ": all stay")


def render_trace(trace: dict[str, Any]) -> str:
    """The whole trace as ASCII grids with the events between them."""
    meeting = [tuple(m) for m in trace["initial"]["meeting_nodes"]]
    box = _box(trace)
    out = [f"trace: {trace['property']} - {trace.get('reason', '')}"]
    for k, state in enumerate(_states(trace)):
        if k:
            out.append(f"step {k}: {_event_text(trace['steps'][k - 1]['event'])}")
        if trace.get("cycle_start") == k:
            out.append("-- the cycle starts here --")
        robots = [tuple(r["node"]) for r in state]
        out.append(ascii_grid(robots, meeting, box))  # type: ignore[arg-type]
        pending = [f"r{i}->{tuple(r['pending'])}" for i, r in enumerate(state) if r["pending"]]
        if pending:
            out.append("pending: " + " ".join(pending))
    if trace["property"] == "crash":
        out.append(crash_text(trace))
    return "\n".join(out)


def view_grid(robots: Sequence[Node], meeting: Iterable[Node]) -> str:
    """A robot's view as text rows: ``@`` the robot (at the origin of its frame), ``o`` another
    occupied node, ``M`` a meeting node (``[@]``, ``[o]`` when occupied).

    >>> print(view_grid([(0, 0), (2, 1)], [(1, 1)]))
     .  M  o
     @  .  .
    """
    meeting, occupied = set(meeting), set(robots)
    x0, y0, x1, y1 = bounding_box([(0, 0), *occupied, *meeting])
    rows = []
    for y in range(y1, y0 - 1, -1):
        cells = []
        for x in range(x0, x1 + 1):
            mark = "@" if (x, y) == (0, 0) else "o" if (x, y) in occupied else ""
            cells.append((f"[{mark}]" if mark else " M ") if (x, y) in meeting
                         else f" {mark or '.'} ")
        rows.append("".join(cells).rstrip())
    return "\n".join(rows)


def crash_text(trace: dict[str, Any]) -> str:
    """Who crashed in the last state of a ``crash`` trace: the robot, its view (its own frame,
    the robot at ``(0, 0)``), the exception and the frames of the algorithm's own code."""
    detail = trace.get("detail") or {}
    last = _states(trace)[-1]
    node = detail.get("robot_node")
    out = []
    if node is not None:
        robots = [f"r{i}" for i, r in enumerate(last) if list(r["node"]) == list(node)]
        out.append(f"crash in {detail.get('call', 'decide')} of robot {'/'.join(robots) or '?'} "
                   f"at {tuple(node)}, frame {detail.get('frame')}; its view in its own frame "
                   "(@ the robot, o another robot, M a meeting node):")
        view = detail.get("view") or {}
        out.append(view_grid([tuple(v) for v in view.get("robots", [])],
                             [tuple(m) for m in view.get("meeting_nodes", [])]))
    else:
        out.append(f"crash in {detail.get('call', 'target')} on the last configuration")
    out.append(f"exception: {detail.get('exception', trace.get('reason', ''))}")
    out += [f"  at {frame}" for frame in detail.get("traceback", [])]
    return "\n".join(out)


def trace_svg(trace: dict[str, Any]) -> str:
    """An SVG storyboard: one panel per state, robots as numbered discs, meeting nodes as
    squares, pending moves as arrows."""
    meeting = [tuple(m) for m in trace["initial"]["meeting_nodes"]]
    x0, y0, x1, y1 = _box(trace)
    cell, pad = 28, 20
    pw, ph = (x1 - x0) * cell + 2 * pad, (y1 - y0) * cell + 2 * pad + 30
    states = _states(trace)
    cols = min(len(states), 6)
    rows = (len(states) + cols - 1) // cols
    width, height = cols * pw, rows * ph + 30
    out = [f'<svg xmlns="http://www.w3.org/2000/svg" width="{width}" height="{height}" '
           f'font-family="sans-serif" font-size="11">',
           f'<text x="5" y="18" font-size="13">{_esc(trace["property"])}: '
           f'{_esc(str(trace.get("reason", "")))}</text>']
    for k, state in enumerate(states):
        ox, oy = (k % cols) * pw, 30 + (k // cols) * ph

        def at(v: Any, ox: int = ox, oy: int = oy) -> tuple[int, int]:
            return ox + pad + (v[0] - x0) * cell, oy + pad + (y1 - v[1]) * cell

        label = "initial" if k == 0 else _esc(_event_text(trace["steps"][k - 1]["event"]))[:40]
        if trace.get("cycle_start") == k:
            label = "cycle start | " + label
        out.append(f'<rect x="{ox + 2}" y="{oy}" width="{pw - 4}" height="{ph - 4}" '
                   'fill="none" stroke="#ccc"/>')
        out.append(f'<text x="{ox + 5}" y="{oy + ph - 10}">{k}: {label}</text>')
        for x in range(x0, x1 + 1):
            for y in range(y0, y1 + 1):
                cx, cy = at((x, y))
                out.append(f'<circle cx="{cx}" cy="{cy}" r="1.5" fill="#999"/>')
        for m in meeting:
            cx, cy = at(m)
            out.append(f'<rect x="{cx - 9}" y="{cy - 9}" width="18" height="18" fill="#ffe9a8" '
                       'stroke="#c90"/>')
        counts = Counter(tuple(r["node"]) for r in state)
        for v, c in counts.items():
            cx, cy = at(v)
            out.append(f'<circle cx="{cx}" cy="{cy}" r="7" fill="#36c"/>')
            out.append(f'<text x="{cx}" y="{cy + 4}" fill="white" text-anchor="middle">{c}</text>')
        for r in state:
            if r["pending"]:
                (ax, ay), (bx, by) = at(r["node"]), at(r["pending"])
                out.append(f'<line x1="{ax}" y1="{ay}" x2="{(ax + bx) / 2 + (bx - ax) / 4}" '
                           f'y2="{(ay + by) / 2 + (by - ay) / 4}" stroke="#c33" stroke-width="2"/>')
    out.append("</svg>")
    return "\n".join(out) + "\n"


def _esc(text: str) -> str:
    return text.replace("&", "&amp;").replace("<", "&lt;").replace(">", "&gt;")
