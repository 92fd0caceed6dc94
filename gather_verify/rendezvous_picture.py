"""A rendezvous trace as a picture read at a glance, step by step (one self-contained HTML
file: ``check --world rendezvous --html FILE``, ``replay TRACE --html FILE``).

Each step draws the two robots on a horizontal segment (long when ``far``, short when
``near``, one point when ``same``), each disc filled with its light (a light being changed
shows the new colour as a ring), the robot's phase under it, and its pending move as an
arrow: to the midpoint, to the other, or dashed and crossed for a ``miss``. The robots that
took the step are outlined in blue; the steps from the cycle's start are marked.

>>> from gather_verify.rendezvous_check import run_rendezvous_check
>>> t = run_rendezvous_check("to-other", "fsync", movement="rigid")["trace"]
>>> html = trace_html(t)
>>> html.count("<svg") == len(t["steps"]), "to-other" in html
(True, True)
"""

from __future__ import annotations

import html as escape
import json
from typing import Any

from gather_verify.worlds.rendezvous_rules import colour_name

FILL = {"black": "#222", "white": "#fff", "red": "#d62728", "yellow": "#f2c500",
        "green": "#2ca02c"}
SPAN = {"far": 360, "near": 180, "same": 0}
"""The segment's length per relative position (pixels)."""
PHASE = {"look": "idle", "begin-compute": "looked", "end-compute": "computing",
         "begin-move": "computed", "end-move": "moving"}
"""What a robot is doing before its next step (its phase names the next step)."""
Y = 90


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
    return (f"{ring}<circle cx='{x}' cy='{Y + dy}' r='18' fill='{_fill(r['colour'])}' "
            f"stroke='{edge}' stroke-width='{4 if stepped else 1.5}'/>"
            f"<text x='{x}' y='{Y + dy + 5}' text-anchor='middle' font-size='14' "
            f"fill='{'#fff' if r['colour'] in (0, 2) else '#000'}'>{name}</text>"
            + (f"<text x='{x}' y='{Y + 48}' text-anchor='middle' font-size='12'>"
               if dy == 0 else
               f"<text x='{x + (-40 if dy < 0 else 40)}' y='{Y + dy + 5}' font-size='12' "
               f"text-anchor='{'end' if dy < 0 else 'start'}'>") + f"{PHASE[r['phase']]}</text>")


def _arrow(x: float, to: float, move: str, i: int, dy: float, head: str) -> str:
    """Robot ``i``'s pending move as an arrow above the segment (A's lower, B's higher);
    at one point, a move (a miss) leaves sideways."""
    if move == "stay":
        return ""
    if x == to:
        to = x + (95 if i == 0 else -95)  # away from its phase label
    y = Y + dy - (30 if i == 0 else 52) if dy == 0 else Y + dy
    x += (to - x) / abs(to - x) * 26 if dy != 0 else 0
    dash = " stroke-dasharray='6 4'" if move == "miss" else ""
    line = (f"<line x1='{x}' y1='{y}' x2='{to}' y2='{y}' stroke='#444' stroke-width='2'"
            f"{dash} marker-end='url(#{head})'/>")
    if move == "miss":
        m = (x + to) / 2
        line += (f"<path d='M{m - 6},{y - 6} L{m + 6},{y + 6} M{m - 6},{y + 6} L{m + 6},{y - 6}'"
                 f" stroke='#d62728' stroke-width='2.5'/>")
    return line + f"<text x='{(x + to) / 2}' y='{y - 8}' text-anchor='middle' font-size='11'>" \
        f"{move}</text>"


def frame(step: dict[str, Any], k: int, cycle: int | None) -> str:
    """One step as an SVG: the segment, the two robots, their pending moves, the event."""
    state, event = step["state"], step["event"]
    half = SPAN[state["position"]] / 2
    xa, xb = 250 - half, 250 + half
    stepped = set(event["robots"]) if event else set()
    a, b = state["robots"]
    dy = (-22, 22) if half == 0 else (0, 0)  # at one point: one above the other
    target = {"to-half": (250, 250), "to-other": (xb, xa), "miss": (250, 250)}
    parts = [f"<line x1='{xa}' y1='{Y}' x2='{xb}' y2='{Y}' stroke='#999' stroke-width='3'/>"]
    for x, r, i in ((xa, a, 0), (xb, b, 1)):
        to = target.get(r["pending"], (x, x))[i]
        parts.append(_arrow(x, to, r["pending"], i, dy[i], f"head{k}"))
        parts.append(_robot(x, r, "AB"[i], i in stepped, dy[i]))
    what = "start" if event is None else "+".join("AB"[i] for i in event["robots"]) + ": " + \
        event["kind"]
    mark = " (the cycle starts here)" if k == cycle else " (in the cycle)" if (
        cycle is not None and k > cycle) else ""
    return (f"<svg class='step' data-k='{k}' width='500' height='190' viewBox='0 0 500 190'>"
            f"<defs><marker id='head{k}' markerWidth='8' markerHeight='8' refX='7' refY='4' "
            "orient='auto'><path d='M0,0 L8,4 L0,8 z' fill='#444'/></marker></defs>"
            f"<text x='10' y='20' font-size='14'>step {k}: {escape.escape(what)}{mark}</text>"
            f"<text x='490' y='20' text-anchor='end' font-size='13'>{state['position']}</text>"
            + "".join(parts) + "</svg>")


def trace_html(trace: dict[str, Any]) -> str:
    """The whole trace: one frame per step, shown one at a time (buttons, arrow keys)."""
    cycle = trace.get("cycle_start")
    frames = "".join(frame(step, k, cycle) for k, step in enumerate(trace["steps"]))
    data = json.dumps(trace).replace("</", "<\\/")  # the trace itself, for a reader's tools
    title = (f"{trace['algorithm']} under {trace['scheduler']} ({trace.get('movement')}, "
             f"initial colours {trace.get('initial_colours')})")
    return f"""<!DOCTYPE html>
<html><head><meta charset='utf-8'><title>{escape.escape(title)}</title>
<style>body{{font-family:sans-serif;margin:16px}} svg.step{{display:none;border:1px solid #ddd}}
svg.step.on{{display:block}} button{{font-size:15px;margin-right:6px}}</style></head>
<body><h3>rendezvous: {escape.escape(title)}</h3>
<p>{escape.escape(str(trace.get('reason', '')))}</p>
<div>{frames}</div>
<p><button id='prev'>&#9664; prev</button><button id='next'>next &#9654;</button>
<span id='where'></span></p>
<p style='font-size:12px;color:#555'>Disc: the robot's light (a ring: the colour its Compute
chose, shown at End-Compute). Arrow: its pending move (dashed and crossed: a miss). Blue
outline: the robots of this step.</p>
<script>
const steps = [...document.querySelectorAll('svg.step')];
let k = 0;
function show(j) {{ k = Math.max(0, Math.min(steps.length - 1, j));
  steps.forEach((s, i) => s.classList.toggle('on', i === k));
  document.getElementById('where').textContent = 'step ' + k + ' of ' + (steps.length - 1); }}
document.getElementById('prev').onclick = () => show(k - 1);
document.getElementById('next').onclick = () => show(k + 1);
document.addEventListener('keydown', e => {{ if (e.key === 'ArrowLeft') show(k - 1);
  if (e.key === 'ArrowRight') show(k + 1); }});
const start = new URLSearchParams(location.search).get('step');
show(start === null ? 0 : Number(start));
</script>
<script type='application/json' id='trace'>{data}</script>
</body></html>
"""
