"""Views up to isomorphism (SEMANTICS.md §12): the canonical key of what a robot sees.

This module imports nothing of gather-verify: a synthesised algorithm carries a copy of its
source, so the witness reads exactly what the search read, through the public view API only
(``view.me``, ``view.graph``, ``view.robots``, ``view.meeting_nodes``, and the multiplicity
and light reads its detection model and lights allow).

A *presentation* is the view in one frame: the robot's node, its own light (or -1 when hidden)
and, per visible node, its label with what lies on it. The frames of a robot are one
presentation moved by a group of label maps (``GROUP``: the ring's two directions, D4 on a
grid or torus, Aut(G) on a graph file; the identity under a compass). The key is the least
image of the presentation under the group; the map that gives it (the first in the group's
order) carries an answer from the key's labels back to the view's. Two presentations of one
view therefore have one key, and the answer moves with the frame: the algorithm is a
deterministic function of the view up to isomorphism, and its move set is the answer's orbit
under the view's own symmetries (§9).

>>> group = build(["ring", 6, [1, -1]])
>>> image(group, 1, 2), inverse(group, 1, 4)
(4, 2)
"""

import json

DETECTIONS = ("none", "local-weak", "local-strong", "global-weak", "global-strong")


def build(description):
    """The group from its description (JSON-ready): ``["ring", N, [signs]]``, ``["d4",
    [[a, b, c, d], ...]]`` (matrices acting on ``(x, y)`` labels) or ``["perm", [[[label,
    image], ...], ...]]`` (one list of pairs per element)."""
    kind = description[0]
    if kind == "ring":
        return ("ring", int(description[1]), tuple(description[2]))
    if kind == "d4":
        return ("d4", tuple(tuple(m) for m in description[1]))
    if kind == "perm":
        forward = []
        for pairs in description[1]:
            forward.append({_label(a): _label(b) for a, b in pairs})
        return ("perm", tuple(forward), tuple({b: a for a, b in f.items()} for f in forward))
    raise ValueError(f"unknown group kind {kind!r}")


def size(group):
    """How many label maps the group holds."""
    return len(group[2]) if group[0] == "ring" else len(group[1])


def image(group, t, label):
    """Label ``label`` under the group's ``t``-th map."""
    kind = group[0]
    if kind == "ring":
        return (group[2][t] * label) % group[1]
    if kind == "d4":
        a, b, c, d = group[1][t]
        x, y = label
        return (a * x + b * y, c * x + d * y)
    return group[1][t][label]


def inverse(group, t, label):
    """The label that the ``t``-th map sends to ``label``."""
    kind = group[0]
    if kind == "ring":
        return (group[2][t] * label) % group[1]  # a sign is its own inverse
    if kind == "d4":
        a, b, c, d = group[1][t]  # orthogonal: the inverse is the transpose
        x, y = label
        return (a * x + c * y, b * x + d * y)
    return group[2][t][label]


def _label(value):
    """A label from JSON (a list is a pair)."""
    return tuple(value) if isinstance(value, list) else value


def observe(view, detection, colours, variant):
    """The presentation of ``view`` in its own frame: ``(me, own light, ((label, content),
    ...))``, content = (meeting node, occupied, multiplicity or count (-1: not shown), the
    colours shown). Reads exactly what ``detection`` and the lights let the robot read."""
    me = view.me
    robots, meeting = view.robots, view.meeting_nodes
    own = view.light if colours > 1 and variant != "external" else -1
    global_ = detection.startswith("global")
    strong = detection.endswith("strong")
    out = []
    for label in view.graph.nodes:
        occupied = label in robots
        shown = occupied and detection != "none" and (global_ or label == me)
        many = -1
        if shown:
            many = view.count(label) if strong else int(view.multiplicity(label))
        lit = ()
        if colours > 1 and variant != "internal" and (occupied or label == me):
            if shown and strong:
                lit = tuple(sorted(view.colour_counts(label).items()))
            else:
                lit = tuple(sorted(view.colours(label)))
        out.append((label, (int(label in meeting), int(occupied), many, lit)))
    return me, own, out


def observe_plane(view, detection):
    """The presentation of a view of the paper's world Z² (``gather_verify.model.view.View``)
    in its own frame: ``((0, 0), -1, ((label, content), ...))`` over the occupied nodes and
    the meeting nodes (every other node of Z² is empty), content as in :func:`observe`.
    Reads exactly what ``detection`` lets the robot read."""
    robots, meeting = view.robots, view.meeting_nodes
    global_ = detection.startswith("global")
    strong = detection.endswith("strong")
    out = []
    for label in sorted(robots | meeting):
        occupied = label in robots
        many = -1
        if occupied and detection != "none" and (global_ or label == (0, 0)):
            many = view.count(label) if strong else int(view.multiplicity(label))
        out.append((label, (int(label in meeting), int(occupied), many, ())))
    return (0, 0), -1, out


def moved(group, t, seen):
    """A presentation under the group's ``t``-th map (labels sorted)."""
    me, own, nodes = seen
    return (image(group, t, me), own,
            tuple(sorted((image(group, t, label), content) for label, content in nodes)))


def canonical(group, seen):
    """``(key, t)``: the least image of the presentation and the first map giving it."""
    best, first = None, 0
    for t in range(size(group)):
        got = moved(group, t, seen)
        if best is None or got < best:
            best, first = got, t
    return best, first


def key_text(key):
    """The key as text (JSON, stable): what a table is indexed by."""
    return json.dumps(key, separators=(",", ":"))
