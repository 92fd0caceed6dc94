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
        by_node.setdefault(tuple(r["node"]), []).append(i)  # type: ignore[arg-type]
    offsets = {2: ((-1, 0), (1, 0)), 3: ((-1, -1), (1, -1), (0, 1))}
    corners = ((-1, -1), (1, -1), (-1, 1), (1, 1), (0, 0), (0, -1), (0, 1), (-1, 0), (1, 0))
    for v, ids in by_node.items():
        cx, cy = at(v)
        many = len(ids) > 1
        radius = cell * (0.21 if many else 0.3)
        for j, i in enumerate(ids):
            place = offsets.get(len(ids), corners)
            dx, dy = place[j % len(place)] if many else (0, 0)
            x, y = cx + dx * cell * 0.21, cy + dy * cell * 0.21
            out.append(f'<circle cx="{x:g}" cy="{y:g}" r="{radius:g}" fill="{PALETTE[i % 8]}" '
                       'stroke="#fff"/>')
            if cell >= 20:
                size = max(7, round(radius * (0.95 if i < 10 else 0.75)))
                out.append(f'<text x="{x:g}" y="{y + size * 0.35:g}" font-size="{size}" '
                           f'font-weight="bold" fill="#fff" text-anchor="middle">r{i}</text>')
    for i, r in enumerate(state):
        if r["pending"]:
            (ax, ay), (bx, by) = at(r["node"]), at(r["pending"])
            d = max(1.0, ((bx - ax) ** 2 + (by - ay) ** 2) ** 0.5)
            ux, uy = (bx - ax) / d, (by - ay) / d
            stop = 0.3 if tuple(r["pending"]) in by_node else 0.08  # type: ignore[arg-type]
            out.append(f'<line x1="{ax + ux * cell * 0.28:g}" y1="{ay + uy * cell * 0.28:g}" '
                       f'x2="{bx - ux * cell * stop:g}" y2="{by - uy * cell * stop:g}" '
                       f'stroke="{PALETTE[i % 8]}" stroke-width="2.5" stroke-dasharray="5 2" '
                       f'marker-end="url(#{uid}-m{i % 8})"/>')
    return "\n".join(out), width, height


def _defs(uid: str) -> str:
    return ("<defs>" + _marker(f"{uid}-m-done", "#999")
            + "".join(_marker(f"{uid}-m{i}", c) for i, c in enumerate(PALETTE)) + "</defs>")


def _caption(data: dict[str, Any], k: int) -> tuple[str, list[str]]:
    """The head line of panel ``k`` and its notes (stale snapshot, class and phase)."""
    trace = data["trace"]
    head = "initial" if k == 0 else data["events"][k - 1]["text"]
    notes = []
    if trace.get("cycle_start") == k:
        notes.append(f"cycle starts (state {len(trace['steps'])} = state {k})")
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
    clipped); the failing property and its reason above, wrapped too."""
    from gather_verify.viewer import annotate

    data = annotate(trace)
    trace = data["trace"]
    meeting = [tuple(m) for m in trace["initial"]["meeting_nodes"]]
    box = tuple(data["box"])
    x0, y0, x1, y1 = box
    cell = max(22, min(40, 220 // max(x1 - x0, y1 - y0, 1)))
    states = _states(trace)
    _, gw, gh = grid_svg(states[0], meeting, box, cell)  # type: ignore[arg-type]
    pw = max(gw, 210) + 12
    chars = int((pw - 12) // CHAR)
    captions = [_caption(data, k) for k in range(len(states))]
    cols = min(len(states), max(1, 1200 // int(pw)))
    rows = (len(states) + cols - 1) // cols
    line_h = FONT * 1.3
    wrapped = [(wrap(h, chars), [x for n in notes for x in wrap(n, chars)]) for h, notes in captions]
    row_h = []
    for r in range(rows):
        part = wrapped[r * cols:(r + 1) * cols]
        row_h.append(gh + 10 + line_h * max(len(h) + len(n) for h, n in part) + 8)
    width = max(cols * pw + 8, 560)
    title = wrap(f"{trace['property']} fails: {trace.get('reason', '')}", int((width - 12) // (0.62 * 13)))
    sub = wrap(f"{trace['algorithm']} / {trace['scheduler']} / {trace['detection']} / frames "
               f"{trace['frames']}: {len(states) - 1} events; robot ri keeps its identity; "
               "dashed arrow = pending move (decided at a Look, not done yet)",
               int((width - 12) // CHAR))
    top = 8 + 13 * 1.3 * len(title) + line_h * len(sub) + 6
    height = top + sum(row_h) + 4
    out = [f'<svg xmlns="http://www.w3.org/2000/svg" width="{width:g}" height="{height:g}" '
           f'viewBox="0 0 {width:g} {height:g}" font-family="DejaVu Sans Mono, Menlo, Consolas, '
           f'monospace" font-size="{FONT}">', _defs("s"),
           '<rect width="100%" height="100%" fill="#fff"/>',
           _text_lines(6, 20, title, 13, font_weight="bold", fill="#b3261e"),
           _text_lines(6, 20 + 13 * 1.3 * len(title), sub, FONT, fill="#555")]
    oy = top
    for r in range(rows):
        for c in range(cols):
            k = r * cols + c
            if k >= len(states):
                break
            ox = 4 + c * pw
            in_cycle = trace.get("cycle_start") is not None and k >= trace["cycle_start"]
            frame = 'stroke="#6a3dba" stroke-width="2"' if in_cycle else 'stroke="#ccc"'
            out.append(f'<rect x="{ox + 2:g}" y="{oy:g}" width="{pw - 4:g}" '
                       f'height="{row_h[r] - 6:g}" rx="4" fill="none" {frame}/>')
            event = trace["steps"][k - 1]["event"] if k else None
            info = data["states"][k]
            body, _, _ = grid_svg(states[k], meeting, box, cell,  # type: ignore[arg-type]
                                  target=tuple(info["target"]) if info.get("target") else None,
                                  event=event, ox=ox + (pw - gw) / 2, oy=oy + 4, uid="s")
            out.append(body)
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
    states = _states(trace)
    meeting = [tuple(m) for m in trace["initial"]["meeting_nodes"]]
    box = bounding_box([*meeting, *(tuple(r[key]) for st in states for r in st  # type: ignore[misc]
                                    for key in ("node", "pending") if r[key])])
    first, w, h = grid_svg(states[0], meeting, box, cell, uid=uid, labels=False)
    last, _, _ = grid_svg(states[-1], meeting, box, cell, ox=w + 18, uid=uid, labels=False,
                          event=trace["steps"][-1]["event"] if trace["steps"] else None)
    width, mid = 2 * w + 18, w + 9
    arrow = (f'<line x1="{mid - 6:g}" y1="{h / 2:g}" x2="{mid + 4:g}" y2="{h / 2:g}" stroke="#555" '
             f'stroke-width="1.5" marker-end="url(#{uid}-m-done)"/>')
    return (f'<svg xmlns="http://www.w3.org/2000/svg" width="{width:g}" height="{h:g}" '
            f'viewBox="0 0 {width:g} {h:g}">{_defs(uid)}{first}{arrow}{last}</svg>')


def _esc(text: str) -> str:
    return text.replace("&", "&amp;").replace("<", "&lt;").replace(">", "&gt;")
