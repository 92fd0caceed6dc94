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

ROBOT_OFFSETS = {2: ((-1, 0), (1, 0)), 3: ((-1, -1), (1, -1), (0, 1))}
CROWD_OFFSETS = ((-1, -1), (1, -1), (-1, 1), (1, 1), (0, 0), (0, -1), (0, 1), (-1, 0), (1, 0))


def robot_spots(count: int, unit: float) -> tuple[float, list[tuple[float, float]]]:
    """How ``count`` robots on one node are drawn: their radius and each one's offset from the
    node's centre (one robot in the middle; two side by side; three in a triangle; more in
    the corners and the middle of the cell), for a cell ``unit`` wide."""
    if count == 1:
        return unit * 0.3, [(0.0, 0.0)]
    place = ROBOT_OFFSETS.get(count, CROWD_OFFSETS)
    return unit * 0.21, [(place[j % len(place)][0] * unit * 0.21,
                          place[j % len(place)][1] * unit * 0.21) for j in range(count)]

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
    first: list[dict[str, Any]] = [{"node": r, "pending": None} for r in trace["initial"]["robots"]]
    colours = trace["initial"].get("colours")
    if isinstance(colours, list) and len(colours) == len(first):  # a trace with lights
        for robot, colour in zip(first, colours, strict=True):
            robot["colour"] = colour
    return [first] + [step["state"] for step in trace["steps"]]


def _box(trace: dict[str, Any]) -> tuple[int, int, int, int]:
    nodes = [tuple(m) for m in trace["initial"]["meeting_nodes"]]
    for state in _states(trace):
        nodes += [tuple(r["node"]) for r in state]
    return bounding_box(nodes)


def _event_text(event: dict[str, Any]) -> str:
    changes = [f"r{i} {tuple(a)}->{tuple(b)}" for i, a, b in event["moves"]]
    changes += [f"r{i} light {a}->{b}" for i, a, b in event.get("lights", [])]
    robots = ",".join(f"r{i}" for i in event["robots"])
    return f"{event['kind']}({robots})" + (f": {', '.join(changes)}" if changes else ": all stay")


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
        out.append(ascii_grid(robots, meeting, box))
        pending = [f"r{i}->{tuple(r['pending'])}" for i, r in enumerate(state) if r["pending"]]
        if pending:
            out.append("pending: " + " ".join(pending))
        if any("colour" in r for r in state):
            out.append("lights: " + " ".join(f"r{i}={r['colour']}" for i, r in enumerate(state)))
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


PALETTE = ("#1f6fd1", "#e8710a", "#1e8e3e", "#9334e6", "#d01884", "#12a4af", "#8d6e00", "#5f6368")
"""Robot colours by identity (robot i gets ``PALETTE[i % 8]``), the same as the viewer's."""
FONT = 11
CHAR = 0.62 * FONT
"""Width of one character of the monospace captions: wrapping by count never clips."""


def wrap(text: str, width: int) -> list[str]:
    """``text`` cut into lines of at most ``width`` characters, at spaces where it can.

    >>> wrap("final: deadlock: no robot can move", 16)
    ['final: deadlock:', 'no robot can', 'move']
    """
    lines: list[str] = []
    for word in text.split():
        while len(word) > width:  # a word longer than a line is cut
            if lines and len(lines[-1]) + 1 < width:
                room = width - len(lines[-1]) - 1
                lines[-1] += " " + word[:room]
                word = word[room:]
            else:
                lines.append(word[:width])
                word = word[width:]
        if lines and len(lines[-1]) + 1 + len(word) <= width:
            lines[-1] += " " + word
        elif word:
            lines.append(word)
    return lines or [""]


def _text_lines(x: float, y: float, lines: Sequence[str], size: int = FONT, **attrs: Any) -> str:
    extra = "".join(f' {k.replace("_", "-")}="{v}"' for k, v in attrs.items())
    spans = "".join(f'<tspan x="{x:g}" dy="{0 if i == 0 else size * 1.3:g}">{_esc(line)}</tspan>'
                    for i, line in enumerate(lines))
    return f'<text x="{x:g}" y="{y:g}" font-size="{size}"{extra}>{spans}</text>'


def _marker(uid: str, colour: str) -> str:
    return (f'<marker id="{uid}" viewBox="0 0 10 10" refX="8" refY="5" markerWidth="4" '
            f'markerHeight="4" orient="auto-start-reverse"><path d="M0,0 L10,5 L0,10 z" '
            f'fill="{colour}"/></marker>')


def grid_svg(state: Sequence[dict[str, Any]], meeting: Sequence[Node],
             box: tuple[int, int, int, int], cell: int = 30, target: Node | None = None,
             event: dict[str, Any] | None = None, ox: float = 0, oy: float = 0,
             uid: str = "g", labels: bool = True) -> tuple[str, float, float]:
    """One configuration as SVG elements at ``(ox, oy)``: coordinates (``labels``), meeting
    nodes (the target with a red border), robots as discs labelled with their identity
    (several on one node side by side), pending moves as dashed arrows with heads, and the
    moves of ``event`` (what led here) as grey arrows. Returns (elements, width, height)."""
    x0, y0, x1, y1 = box
    margin = cell * 0.55 + 3
    left = margin + (14 if labels else 0)
    width = left + (x1 - x0) * cell + margin
    height = margin + (y1 - y0) * cell + margin + (14 if labels else 0)

    def at(v: Sequence[int]) -> tuple[float, float]:
        return ox + left + (v[0] - x0) * cell, oy + margin + (y1 - v[1]) * cell

    out = []
    for x in range(x0, x1 + 1):
        cx, _ = at((x, y0))
        out.append(f'<line x1="{cx:g}" y1="{oy + 3:g}" x2="{cx:g}" y2="{oy + height - (14 if labels else 0) - 3:g}" stroke="#e6e6e6"/>')
        if labels:
            out.append(f'<text x="{cx:g}" y="{oy + height - 3:g}" font-size="10" fill="#777" '
                       f'text-anchor="middle">{x}</text>')
    for y in range(y0, y1 + 1):
        _, cy = at((x0, y))
        out.append(f'<line x1="{ox + left - margin + 3:g}" y1="{cy:g}" x2="{ox + width - 3:g}" y2="{cy:g}" stroke="#e6e6e6"/>')
        if labels:
            out.append(f'<text x="{ox + 12:g}" y="{cy + 3.5:g}" font-size="10" fill="#777" '
                       f'text-anchor="end">{y}</text>')
    s = cell * 0.36
    for m in meeting:
        cx, cy = at(m)
        is_target = target is not None and tuple(m) == tuple(target)
        out.append(f'<rect x="{cx - s:g}" y="{cy - s:g}" width="{2 * s:g}" height="{2 * s:g}" rx="2" '
                   f'fill="#ffe9a8" stroke="{"#b3261e" if is_target else "#c9a227"}" '
                   f'stroke-width="{2.5 if is_target else 1.2}"/>')
    if event and event["kind"] != "look":
        for _, a, b in event["moves"]:
            (ax, ay), (bx, by) = at(a), at(b)
            out.append(f'<line x1="{ax:g}" y1="{ay:g}" x2="{ax + (bx - ax) * 0.6:g}" '
                       f'y2="{ay + (by - ay) * 0.6:g}" stroke="#999" stroke-width="2" '
                       f'marker-end="url(#{uid}-m-done)"/>')
    by_node: dict[tuple[int, int], list[int]] = {}
    for i, r in enumerate(state):
        by_node.setdefault(tuple(r["node"]), []).append(i)
    for v, ids in by_node.items():
        cx, cy = at(v)
        radius, spots = robot_spots(len(ids), cell)
        for i, (dx, dy) in zip(ids, spots, strict=True):
            px, py = cx + dx, cy + dy
            out.append(f'<circle cx="{px:g}" cy="{py:g}" r="{radius:g}" fill="{PALETTE[i % 8]}" '
                       'stroke="#fff"/>')
            if cell >= 20:
                size = max(7, round(radius * (0.95 if i < 10 else 0.75)))
                out.append(f'<text x="{px:g}" y="{py + size * 0.35:g}" font-size="{size}" '
                           f'font-weight="bold" fill="#fff" text-anchor="middle">r{i}</text>')
            colour = state[i].get("colour")
            if isinstance(colour, int):  # a trace with lights: the colour as a badge
                b = max(3.5, radius * 0.45)
                out.append(f'<circle cx="{px + radius * 0.8:g}" cy="{py - radius * 0.8:g}" '
                           f'r="{b:g}" fill="{LIGHTS[colour % len(LIGHTS)]}" stroke="#222" '
                           f'stroke-width="0.8" class="light" data-colour="{colour}"/>')
                if cell >= 20:
                    out.append(f'<text x="{px + radius * 0.8:g}" y="{py - radius * 0.8 + 2.5:g}" '
                               f'font-size="{max(6, round(b * 1.2))}" fill="#111" '
                               f'text-anchor="middle">{colour}</text>')
    for i, r in enumerate(state):
        if r["pending"]:
            (ax, ay), (bx, by) = at(r["node"]), at(r["pending"])
            d = max(1.0, ((bx - ax) ** 2 + (by - ay) ** 2) ** 0.5)
            ux, uy = (bx - ax) / d, (by - ay) / d
            stop = 0.3 if tuple(r["pending"]) in by_node else 0.08
            out.append(f'<line x1="{ax + ux * cell * 0.28:g}" y1="{ay + uy * cell * 0.28:g}" '
                       f'x2="{bx - ux * cell * stop:g}" y2="{by - uy * cell * stop:g}" '
                       f'stroke="{PALETTE[i % 8]}" stroke-width="2.5" stroke-dasharray="5 2" '
                       f'marker-end="url(#{uid}-m{i % 8})"/>')
    return "\n".join(out), width, height


def _defs(uid: str) -> str:
    return ("<defs>" + _marker(f"{uid}-m-done", "#999")
            + "".join(_marker(f"{uid}-m{i}", c) for i, c in enumerate(PALETTE)) + "</defs>")


def _panel_head(data: dict[str, Any], k: int) -> tuple[str, list[str]]:
    """The head line of panel ``k`` (the event that led to it) and, where the trace's cycle
    starts, that note."""
    trace = data["trace"]
    head = "initial" if k == 0 else data["events"][k - 1]["text"]
    notes = []
    if trace.get("cycle_start") == k:
        notes.append(f"cycle starts (state {len(trace['steps'])} = state {k})")
    return head, notes


def _caption(data: dict[str, Any], k: int) -> tuple[str, list[str]]:
    """The head line of panel ``k`` and its notes (stale snapshot, class and phase)."""
    head, notes = _panel_head(data, k)
    if k:
        for d in data["events"][k - 1]["decisions"]:
            if d["stale"]:
                notes.append(f"STALE: r{d['robot']} moves on its Look at event {d['look']}; "
                             f"since then {', '.join(d['moved_since'])} moved")
    info = data["states"][k]
    line = info["class"] or "?"
    if info.get("phase"):
        line += f" - {info['phase']}"
    if info.get("target"):
        line += f" - target {tuple(info['target'])}"
    notes.append(line)
    return f"{k}: {head}", notes


def trace_svg(trace: dict[str, Any]) -> str:
    """An SVG storyboard: one panel per state with coordinates, meeting nodes (the target
    meeting node with a red border), robots labelled with their identity, pending moves as
    dashed arrows with heads, the moves just made as grey arrows; each panel captioned with
    its event, stale snapshots, the class, the phase and the target (captions wrapped, never
    clipped); the failing property and its reason above, wrapped too. A finite world's trace
    is drawn from the world's drawing (:func:`world_svg`)."""
    from gather_verify.viewer import annotate

    data = annotate(trace)
    trace = data["trace"]
    if "drawing" in data:
        return _storyboard(data, *_world_panels(data))
    meeting = [tuple(m) for m in trace["initial"]["meeting_nodes"]]
    box = tuple(data["box"])
    x0, y0, x1, y1 = box
    cell = max(22, min(40, 220 // max(x1 - x0, y1 - y0, 1)))
    states = _states(trace)
    _, gw, gh = grid_svg(states[0], meeting, box, cell)

    def panel(k: int, ox: float, oy: float) -> str:
        event = trace["steps"][k - 1]["event"] if k else None
        info = data["states"][k]
        body, _, _ = grid_svg(states[k], meeting, box, cell,
                              target=tuple(info["target"]) if info.get("target") else None,
                              event=event, ox=ox, oy=oy, uid="s")
        return body

    sub = (f"{trace['algorithm']} / {trace['scheduler']} / {trace['detection']} / frames "
           f"{trace['frames']}: {len(states) - 1} events; robot ri keeps its identity; "
           "dashed arrow = pending move (decided at a Look, not done yet)")
    return _storyboard(data, panel, gw, gh, [_caption(data, k) for k in range(len(states))], sub,
                       _defs("s"))


def _storyboard(data: dict[str, Any], panel: Any, gw: float, gh: float,
                captions: list[tuple[str, list[str]]], sub_text: str, defs: str) -> str:
    """Panels of ``gw`` x ``gh`` (``panel(k, ox, oy)`` draws state k there) in rows, each with
    its caption, under the failing property and ``sub_text``."""
    trace = data["trace"]
    n_states = len(captions)
    pw = max(gw, 210) + 12
    chars = int((pw - 12) // CHAR)
    cols = min(n_states, max(1, 1200 // int(pw)))
    rows = (n_states + cols - 1) // cols
    line_h = FONT * 1.3
    wrapped = [(wrap(h, chars), [x for n in notes for x in wrap(n, chars)]) for h, notes in captions]
    row_h = []
    for r in range(rows):
        part = wrapped[r * cols:(r + 1) * cols]
        row_h.append(gh + 10 + line_h * max(len(h) + len(n) for h, n in part) + 8)
    width = max(cols * pw + 8, 560)
    title = wrap(f"{trace['property']} fails: {trace.get('reason', '')}", int((width - 12) // (0.62 * 13)))
    sub = wrap(sub_text, int((width - 12) // CHAR))
    top = 8 + 13 * 1.3 * len(title) + line_h * len(sub) + 6
    height = top + sum(row_h) + 4
    out = [f'<svg xmlns="http://www.w3.org/2000/svg" width="{width:g}" height="{height:g}" '
           f'viewBox="0 0 {width:g} {height:g}" font-family="DejaVu Sans Mono, Menlo, Consolas, '
           f'monospace" font-size="{FONT}">', defs,
           '<rect width="100%" height="100%" fill="#fff"/>',
           _text_lines(6, 20, title, 13, font_weight="bold", fill="#b3261e"),
           _text_lines(6, 20 + 13 * 1.3 * len(title), sub, FONT, fill="#555")]
    oy = top
    for r in range(rows):
        for c in range(cols):
            k = r * cols + c
            if k >= n_states:
                break
            ox = 4 + c * pw
            in_cycle = trace.get("cycle_start") is not None and k >= trace["cycle_start"]
            frame = 'stroke="#6a3dba" stroke-width="2"' if in_cycle else 'stroke="#ccc"'
            out.append(f'<rect x="{ox + 2:g}" y="{oy:g}" width="{pw - 4:g}" '
                       f'height="{row_h[r] - 6:g}" rx="4" fill="none" {frame}/>')
            out.append(panel(k, ox + (pw - gw) / 2, oy + 4))
            head, notes = wrapped[k]
            y = oy + gh + 4 + FONT + 4
            out.append(_text_lines(ox + 8, y, head, FONT, fill="#111"))
            stale = any(note.startswith("STALE") for note in captions[k][1])
            out.append(_text_lines(ox + 8, y + line_h * len(head), notes, FONT,
                                   fill="#8a5a00" if stale else "#555"))
        oy += row_h[r]
    out.append("</svg>")
    return "\n".join(out) + "\n"




def thumbnail_svg(trace: dict[str, Any], cell: int = 26, uid: str = "t") -> str:
    """A small picture of a counterexample (for reports): the initial and the last
    configuration side by side, robots coloured by identity, pending moves as arrows
    (``uid`` keeps the arrowhead ids of several thumbnails on one page apart)."""
    from gather_verify.viewer import annotate_world, is_world_trace

    if is_world_trace(trace):
        data = annotate_world(trace)
        pic = WorldPicture(data["drawing"], 130, cell, 8, names=False)
        first, w, h = world_svg(pic, data, 0, uid=uid)
        final, _, _ = world_svg(pic, data, len(data["robots"]) - 1, ox=w + 18, uid=uid)
        width, mid = 2 * w + 18, w + 9
        arrow = (f'<line x1="{_f(mid - 6)}" y1="{_f(h / 2)}" x2="{_f(mid + 4)}" y2="{_f(h / 2)}" '
                 f'stroke="#555" stroke-width="1.5" marker-end="url(#{uid}-m-done)"/>')
        return (f'<svg xmlns="http://www.w3.org/2000/svg" width="{_f(width)}" height="{_f(h)}" '
                f'viewBox="0 0 {_f(width)} {_f(h)}">{_defs(uid)}{first}{arrow}{final}</svg>')
    states = _states(trace)
    meeting = [tuple(m) for m in trace["initial"]["meeting_nodes"]]
    box = bounding_box([*meeting, *(tuple(r[key]) for st in states for r in st
                                    for key in ("node", "pending") if r[key])])
    first, w, h = grid_svg(states[0], meeting, box, cell, uid=uid, labels=False)
    last, _, _ = grid_svg(states[-1], meeting, box, cell, ox=w + 18, uid=uid, labels=False,
                          event=trace["steps"][-1]["event"] if trace["steps"] else None)
    width, mid = 2 * w + 18, w + 9
    arrow = (f'<line x1="{mid - 6:g}" y1="{h / 2:g}" x2="{mid + 4:g}" y2="{h / 2:g}" stroke="#555" '
             f'stroke-width="1.5" marker-end="url(#{uid}-m-done)"/>')
    return (f'<svg xmlns="http://www.w3.org/2000/svg" width="{width:g}" height="{h:g}" '
            f'viewBox="0 0 {width:g} {h:g}">{_defs(uid)}{first}{arrow}{last}</svg>')


# -- finite worlds -------------------------------------------------------------------------
# A finite world's trace carries the world's drawing (gather_verify.worlds.base.World.drawing):
# where each node is, how each edge is drawn (and whether it wraps), the line around the
# world. The pictures below draw from it alone, as the viewer does, and never ask which world
# it is.

LIGHTS = ("#ffffff", "#ffd23f", "#3fc1ff", "#ff6b6b", "#8fdc5a", "#c39bff", "#ff9f1c", "#a0a0a0")
"""A robot's light (a numbered badge on its disc) by colour number, the same as the viewer's."""


def _f(x: float) -> str:
    """A coordinate as the SVG writes it (two decimals at most: the same bytes every run)."""
    out = round(x, 2)
    return f"{0.0 if out == 0 else out:g}"


def trim(line: Sequence[tuple[float, float]], start: float, end: float
         ) -> list[tuple[float, float]]:
    """A polyline shortened by ``start`` at its beginning and ``end`` at its end (never to
    less than 4 long).

    >>> trim([(0, 0), (10, 0), (10, 10)], 5, 5)
    [(5.0, 0.0), (10, 0), (10.0, 5.0)]
    """
    lens = [((b[0] - a[0]) ** 2 + (b[1] - a[1]) ** 2) ** 0.5 for a, b in zip(line, line[1:],
                                                                             strict=False)]
    total = sum(lens)
    if start + end > total - 4:
        f = max(0.0, total - 4) / ((start + end) or 1)
        start, end = start * f, end * f

    def point_at(s: float) -> tuple[float, float]:
        j = 0
        while j < len(lens) - 1 and s > lens[j]:
            s -= lens[j]
            j += 1
        t = min(1.0, s / lens[j]) if lens[j] else 0.0
        (ax, ay), (bx, by) = line[j], line[j + 1]
        return ax + (bx - ax) * t, ay + (by - ay) * t

    out = [point_at(start)]
    acc = 0.0
    for j in range(1, len(line) - 1):
        acc += lens[j - 1]
        if start < acc < total - end:
            out.append(line[j])
    out.append(point_at(total - end))
    return out


class WorldPicture:
    """A world's drawing placed in pixels: ``unit`` pixels to the drawing's unit, as many as
    fit the drawing in ``size`` pixels, within ``[low, high]``; nodes named when ``names``
    and there is room. The same geometry as the viewer's."""

    def __init__(self, drawing: dict[str, Any], size: int = 220, high: int = 56, low: int = 14,
                 names: bool = True):
        self.drawing = drawing
        nodes = drawing["nodes"]
        pts = [(n["x"], n["y"]) for n in nodes]
        pts += [tuple(p) for e in drawing["edges"] for line in e.get("lines", ()) for p in line]
        if drawing["outline"]:
            pts += [tuple(p) for p in drawing["outline"]["points"]]
        xs, ys = [p[0] for p in pts], [p[1] for p in pts]
        self.x0, self.y1 = min(xs), max(ys)
        span = max(max(xs) - self.x0, self.y1 - min(ys), 1)
        self.unit = max(low, min(high, int(size // span)))
        self.names = names and self.unit >= 22
        self.margin = self.unit * 0.5 + (16 if self.names else 4)
        self.width = 2 * self.margin + (max(xs) - self.x0) * self.unit
        self.height = 2 * self.margin + (self.y1 - min(ys)) * self.unit
        self.routes: dict[tuple[int, int], list[list[tuple[float, float]]]] = {}
        for e in drawing["edges"]:
            a, b = e["ends"]
            lines = [[self.place(p) for p in line] for line in e.get("lines") or
                     [[(nodes[a]["x"], nodes[a]["y"]), (nodes[b]["x"], nodes[b]["y"])]]]
            self.routes[a, b] = lines
            self.routes[b, a] = [line[::-1] for line in lines[::-1]]

    def place(self, p: Sequence[float]) -> tuple[float, float]:
        return (self.margin + (p[0] - self.x0) * self.unit,
                self.margin + (self.y1 - p[1]) * self.unit)

    def at(self, v: int) -> tuple[float, float]:
        node = self.drawing["nodes"][v]
        return self.place((node["x"], node["y"]))

    def route(self, a: int, b: int, start: float, end: float) -> list[list[tuple[float, float]]]:
        """The edge from ``a`` to ``b`` as lines, ``start`` pixels off ``a``, ``end`` off ``b``."""
        lines = self.routes.get((a, b)) or [[self.at(a), self.at(b)]]
        return [trim(line, start if j == 0 else 0, end if j == len(lines) - 1 else 0)
                for j, line in enumerate(lines)]


def _poly(line: Sequence[tuple[float, float]], ox: float, oy: float, attrs: str) -> str:
    if len(line) == 2:
        (ax, ay), (bx, by) = line
        return (f'<line x1="{_f(ax + ox)}" y1="{_f(ay + oy)}" x2="{_f(bx + ox)}" '
                f'y2="{_f(by + oy)}" {attrs}/>')
    points = " ".join(f"{_f(x + ox)},{_f(y + oy)}" for x, y in line)
    return f'<polyline points="{points}" fill="none" {attrs}/>'


def world_svg(pic: WorldPicture, data: dict[str, Any], k: int, ox: float = 0, oy: float = 0,
              uid: str = "w") -> tuple[str, float, float]:
    """State ``k`` of an annotated world trace (:func:`gather_verify.viewer.annotate_world`) as
    SVG elements at ``(ox, oy)``: the outline (a border, or a dashed seam), the edges (those
    that wrap dashed), the nodes (visited ones green), their names, the node the failing
    property names (a red dashed ring), meeting nodes, the moves of the event that led here
    (grey), the robots (labelled with their identity, side by side on a shared node with the
    count, a numbered light badge), pending moves as dashed arrows along their edge. Returns
    (elements, width, height)."""
    state = data["robots"][k]
    by_node: dict[int, list[int]] = {}
    for i, r in enumerate(state):
        by_node.setdefault(r["node"], []).append(i)
    out = _world_ground(pic, data, k, ox, oy)
    out += _world_moves(pic, data, k, ox, oy, uid)
    out += _world_robots(pic, data, k, by_node, ox, oy)
    for i, r in enumerate(state):  # the pending moves, as dashed arrows along their edge
        if r["pending"] is None or r["pending"] == r["node"]:
            continue
        stop = 0.3 if r["pending"] in by_node else 0.08
        lines = pic.route(r["node"], r["pending"], pic.unit * 0.28, pic.unit * stop)
        for j, line in enumerate(lines):
            last = j == len(lines) - 1
            out.append(_poly(line, ox, oy, f'stroke="{PALETTE[i % 8]}" stroke-width="2.5" '
                             f'stroke-dasharray="5 2" class="{"pending" if last else "pending-part"}"'
                             + (f' marker-end="url(#{uid}-m{i % 8})"' if last else "")))
    return "\n".join(out), pic.width, pic.height


def _world_ground(pic: WorldPicture, data: dict[str, Any], k: int, ox: float, oy: float
                  ) -> list[str]:
    """What state ``k`` of :func:`world_svg` stands on: the outline, the edges, the nodes
    (visited ones green) and their names, the focus ring and the meeting nodes."""
    d, u = pic.drawing, pic.unit
    nodes = d["nodes"]
    out = []
    if d["outline"]:
        o = d["outline"]
        points = " ".join(f"{_f(x + ox)},{_f(y + oy)}" for x, y in map(pic.place, o["points"]))
        style = ('stroke="#9b87d6" stroke-width="1.5" stroke-dasharray="6 4" class="outline seam"'
                 if o["wraps"] else 'stroke="#777" stroke-width="2.5" class="outline border"')
        out.append(f'<polygon points="{points}" fill="none" {style}><title>{_esc(o["title"])}'
                   '</title></polygon>')
    for e in d["edges"]:
        style = ('stroke="#9b87d6" stroke-width="2" stroke-dasharray="4 3" class="edge wrap"'
                 if e.get("wraps") else 'stroke="#cfcfcf" stroke-width="2.5" class="edge"')
        out += [_poly(line, ox, oy, style) for line in pic.routes[tuple(e["ends"])]]
    visited = set(data["states"][k]["visited"] or ())
    for v in range(len(nodes)):
        x, y = _at(pic, v, ox, oy)
        fill, stroke = ("#bfe3c0", "#3d8b40") if v in visited else ("#fff", "#9a9a9a")
        out.append(f'<circle cx="{_f(x)}" cy="{_f(y)}" r="{_f(max(2.5, u * 0.1))}" fill="{fill}" '
                   f'stroke="{stroke}" stroke-width="1.2" class="node'
                   f'{" visited" if v in visited else ""}" data-node="{_attr(nodes[v]["text"])}"/>')
        if pic.names:  # on the side the drawing gives (away from the edges)
            (dx, dy), off = nodes[v]["side"], u * 0.36 + 8
            out.append(f'<text x="{_f(x + dx * off)}" y="{_f(y - dy * off + 3)}" '
                       f'font-size="9" fill="#777" text-anchor="middle">'
                       f'{_esc(nodes[v]["text"])}</text>')
    if data.get("focus") is not None:
        x, y = _at(pic, data["focus"], ox, oy)
        out.append(f'<circle cx="{_f(x)}" cy="{_f(y)}" r="{_f(u * 0.46)}" fill="none" '
                   'stroke="#b3261e" stroke-width="2" stroke-dasharray="4 2" class="focus"/>')
    s = u * 0.36
    for m in data["trace"]["initial"]["meeting_nodes"]:
        x, y = _at(pic, m, ox, oy)
        out.append(f'<rect x="{_f(x - s)}" y="{_f(y - s)}" width="{_f(2 * s)}" height="{_f(2 * s)}" '
                   'rx="2" fill="#ffe9a8" stroke="#c9a227" stroke-width="1.2" class="meeting"/>')
    return out


def _at(pic: WorldPicture, v: int, ox: float, oy: float) -> tuple[float, float]:
    """Where node ``v`` is drawn, the picture moved by ``(ox, oy)``."""
    x, y = pic.at(v)
    return x + ox, y + oy


def _world_moves(pic: WorldPicture, data: dict[str, Any], k: int, ox: float, oy: float,
                 uid: str) -> list[str]:
    """The moves of the event that led to state ``k`` (grey arrows), for :func:`world_svg`."""
    event = data["trace"]["steps"][k - 1]["event"] if k else None
    out: list[str] = []
    if event and event["kind"] != "look":
        for _, a, b in event["moves"]:
            if a == b:
                continue
            lines = pic.route(a, b, 0, pic.unit * 0.38)
            out += [_poly(line, ox, oy, 'stroke="#999" stroke-width="2"' +
                          (f' marker-end="url(#{uid}-m-done)"' if j == len(lines) - 1 else ""))
                    for j, line in enumerate(lines)]
    return out


def _world_robots(pic: WorldPicture, data: dict[str, Any], k: int,
                  by_node: dict[int, list[int]], ox: float, oy: float) -> list[str]:
    """The robots of state ``k`` for :func:`world_svg`: labelled with their identity, side
    by side on a shared node with the count, a numbered light badge."""
    u, names = pic.unit, [n["text"] for n in pic.drawing["nodes"]]
    colours = data["states"][k]["colours"]
    out = []
    for v, ids in by_node.items():
        cx, cy = _at(pic, v, ox, oy)
        radius, spots = robot_spots(len(ids), u)
        for i, (dx, dy) in zip(ids, spots, strict=True):
            x, y = cx + dx, cy + dy
            out.append(f'<circle cx="{_f(x)}" cy="{_f(y)}" r="{_f(radius)}" '
                       f'fill="{PALETTE[i % 8]}" stroke="#fff" class="robot" data-robot="{i}" '
                       f'data-node="{_attr(names[v])}"/>')
            if u >= 20:
                size = max(7, round(radius * (0.95 if i < 10 else 0.75)))
                out.append(f'<text x="{_f(x)}" y="{_f(y + size * 0.35)}" font-size="{size}" '
                           f'font-weight="bold" fill="#fff" text-anchor="middle">r{i}</text>')
            if colours is not None:
                c, b = colours[i], max(3.5, radius * 0.45)
                out.append(f'<circle cx="{_f(x + radius * 0.8)}" cy="{_f(y - radius * 0.8)}" '
                           f'r="{_f(b)}" fill="{LIGHTS[c % len(LIGHTS)]}" stroke="#222" '
                           f'stroke-width="0.8" class="light" data-colour="{c}"/>')
                if u >= 20:
                    out.append(f'<text x="{_f(x + radius * 0.8)}" y="{_f(y - radius * 0.8 + 2.5)}" '
                               f'font-size="{max(6, round(b * 1.2))}" fill="#111" '
                               f'text-anchor="middle">{c}</text>')
        if len(ids) > 1:
            out.append(f'<text x="{_f(cx + u * 0.42)}" y="{_f(cy - u * 0.3)}" font-size="10" '
                       'font-weight="bold" fill="#333" stroke="#fff" stroke-width="2.5" '
                       f'paint-order="stroke" text-anchor="middle" class="count">'
                       f'\u00d7{len(ids)}</text>')
    return out


def _world_caption(data: dict[str, Any], k: int) -> tuple[str, list[str]]:
    """The head line of panel ``k`` of a world trace and its notes (the cycle, stale
    snapshots, robots sharing a node, the nodes visited)."""
    names = [n["text"] for n in data["drawing"]["nodes"]]
    head, notes = _panel_head(data, k)
    if k:
        for d in data["events"][k - 1]["decisions"]:
            if d["stale"]:
                changed = [f"{', '.join(d['moved_since'])} moved"] if d["moved_since"] else []
                changed += [f"{', '.join(d['relit_since'])} changed colour"] \
                    if d["relit_since"] else []
                notes.append(f"STALE: r{d['robot']} moves on its Look at event {d['look']}; "
                             f"since then {' and '.join(changed)}")
    at: dict[int, list[str]] = {}
    for i, r in enumerate(data["robots"][k]):
        at.setdefault(r["node"], []).append(f"r{i}")
    notes += [f"{' '.join(ids)} on {names[v]}" for v, ids in at.items() if len(ids) > 1]
    visited = data["states"][k]["visited"]
    if visited is not None:
        notes.append(f"visited {len(visited)}/{len(names)}")
    return f"{k}: {head}", notes


def _world_panels(data: dict[str, Any]) -> tuple[Any, float, float, list, str, str]:
    """What :func:`_storyboard` needs for a world trace."""
    pic = WorldPicture(data["drawing"])
    trace, world = data["trace"], data["world"]

    def panel(k: int, ox: float, oy: float) -> str:
        return world_svg(pic, data, k, ox, oy, uid="s")[0]

    seen = "" if world["visibility"] is None else f" / visibility {world['visibility']}"
    lights = "" if world["lights"] == "1" else f" / lights {world['lights']}"
    sub = (f"{world['name']} / task {world['task']} / {trace['algorithm']} / "
           f"{trace['scheduler']} / {trace['detection']} / frames {trace['frames']}{seen}"
           f"{lights}: {len(trace['steps'])} events; robot ri keeps its identity; dashed arrow "
           "= pending move (decided at a Look, not done yet)"
           + ("; green node = visited so far" if any(s["visited"] for s in data["states"])
              else "")
           + ("; red dashed ring = the node the property names"
              if data.get("focus") is not None else ""))
    captions = [_world_caption(data, k) for k in range(len(data["robots"]))]
    return panel, pic.width, pic.height, captions, sub, _defs("s")


def _esc(text: str) -> str:
    return text.replace("&", "&amp;").replace("<", "&lt;").replace(">", "&gt;")


def _attr(text: str) -> str:
    """Text for an attribute value in double quotes."""
    return _esc(text).replace('"', "&quot;")
