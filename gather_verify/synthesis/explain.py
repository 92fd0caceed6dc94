"""A certificate of ``none`` in words (SEMANTICS.md §12): the starts it rests on, and the
adversary's strategy along each branch of its decision tree.

A certificate is a decision tree over views: whatever an algorithm answers on the views the
tree branches on, it reaches a leaf, and the leaf's counterexample is an execution that
algorithm has. :func:`explain` reads the tree from its root: per branch, the answer taken
there; per leaf, the execution told round by round (which robots move, in which direction,
and where the adversary chose because the robot's view is mirror-symmetric), and how it
fails. Nothing here is trusted: it reads a certificate that ``--verify`` re-checks.
"""

from __future__ import annotations

from typing import Any

from gather_verify.synthesis.certificate import (
    apply_event,
    event_from_json,
    load_certificate,
    replay,
)
from gather_verify.synthesis.starts import describe
from gather_verify.synthesis.views import Views
from gather_verify.words import counted

MAX_LEAVES = 6
"""Leaves told in full; a larger tree is summed up after them."""


def explain_certificate(path: str, max_leaves: int = MAX_LEAVES) -> list[str]:
    """:func:`explain` of the certificate in ``path`` (re-check it first: this reads it)."""
    doc, inst = load_certificate(path)
    return explain(doc, Views(inst), max_leaves)


def explain(doc: dict[str, Any], views: Views, max_leaves: int = MAX_LEAVES) -> list[str]:
    """Lines for a person: the starts the certificate rests on, then its tree, each leaf's
    execution in words (at most ``max_leaves`` of them)."""
    inst = views.inst
    cexs = doc["counterexamples"]
    listed = [v["key"] for v in doc["views"]]
    proof = "proof" in doc
    leaves = list(range(len(cexs))) if proof else _leaves(doc["tree"])
    used = sorted({int(cexs[leaf]["configuration"]) for leaf in leaves})
    lines = [f"rests on {len(used)} of {counted(len(inst.configurations), 'start')}: "
             + "; ".join(_start(views, j) for j in used)]
    if len(used) == 1 and len(inst.configurations) > 1:
        lines.append("  no algorithm solves the task from that start alone")
    if proof:
        lemmas = sum(1 for s in doc["proof"]["steps"] if not s or s[0] != 0)
        lines.append(f"  every algorithm has one of these {counted(len(cexs), 'execution')}: "
                     f"a resolution proof of {counted(lemmas, 'lemma')} shows it (a decision "
                     "tree would be too large); the first ones:")
        lines += [f"  from {_start(views, int(c['configuration']))}: {tell(views, c)}"
                  for c in cexs[:max_leaves]]
        if len(cexs) > max_leaves:
            lines.append(f"... and {counted(len(cexs) - max_leaves, 'more execution')} "
                         "(--json has them all)")
        return lines
    for cex in cexs:  # every view the tree names gets its number in ``views``
        replay(views, cex)
    told = [0]

    def walk(node: Any, depth: int, path: str) -> None:
        pad = "  " * depth
        if isinstance(node, int):
            told[0] += 1
            if told[0] <= max_leaves:
                lines.append(f"{pad}{path}then: " + tell(views, cexs[node]))
            return
        k, children = node
        name = view_text(inst.world, listed[k], inst.detection)
        for o, child in enumerate(children):
            answer = _option(views, listed[k], o)
            walk(child, depth + 1, f"if {name} answers {answer}: ")
    walk(doc["tree"], 0, "")
    if told[0] > max_leaves:
        lines.append(f"... and {counted(told[0] - max_leaves, 'more leaf', 'more leaves')} "
                     "(--json has them all)")
    return lines


def view_text(world: Any, key: str, detection: str = "global-weak") -> str:
    """A view in words: on a ring, the gaps (hops) from the robot to the next occupied node,
    and on round, in the view's frame (``*`` marks a tower where the view shows one)."""
    import json

    me, _own, nodes = json.loads(key)
    if world.kind != "ring" or not isinstance(me, int):
        return f"the view {key[:60]}"
    n = world.size
    occupied = sorted((label - me) % n for label, (_, occ, _m, _l) in nodes if occ)
    strong = detection.endswith("strong")
    towers = {(label - me) % n for label, (_, occ, many, _l) in nodes
              if occ and (many > 1 if strong else many == 1)}
    stops = [p for p in occupied if p != 0] + [n]
    gaps, last = [], 0
    for p in stops:
        gaps.append(f"{p - last}{'*' if p % n in towers else ''}")
        last = p
    return f"a robot{'*' if 0 in towers else ''} seeing gaps {' '.join(gaps)}"


def tell(views: Views, cex: dict[str, Any]) -> str:
    """One counterexample in words: its start, its events, and how it fails."""
    inst = views.inst
    w = inst.world
    events = [event_from_json(w, e) for e in cex["events"]]
    robots: tuple[tuple[int, int | None, int], ...] = tuple(
        (v, None, c) for v, c in zip(*inst.configurations[int(cex["configuration"])],
                                     strict=True))
    parts = []
    loop = cex.get("loop")
    for j, e in enumerate(events):
        if loop is not None and j == loop:
            parts.append("then, for ever")
        parts.append(_event(views, robots, e))
        robots = apply_event(robots, e)
    told = "; ".join(p for p in parts if p).replace("then, for ever; ", "for ever: ", 1) \
        if loop == 0 else "; ".join(p for p in parts if p)
    still = loop is not None and loop == len(events)  # the cycle is every robot staying
    tail = _failure(views, cex, robots, still)
    then = "then " if tail.startswith("every robot stays") else ""
    return (told + "; " + then if told else "") + tail


def _event(views: Views, robots: tuple[Any, ...], e: Any) -> str:
    """One event in words: the robots that step, grouped by direction, and whether the
    adversary chose the direction (the robot's move set holds both: its view is
    mirror-symmetric)."""
    w = views.inst.world
    if e.kind == "look" or not e.moves:
        return ""  # a Look is told by its Move
    per = views.robots(robots) if e.kind == "round" else None
    ways: dict[str, list[str]] = {}
    chosen = 0
    for i, a, b in e.moves:
        ways.setdefault(_way(w, a, b), []).append(f"{w.format_node(a)}->{w.format_node(b)}")
        if per is not None:
            _, acts = per[i]
            option = next(opts for opts in acts if any(d == b for d, _ in opts))
            chosen += len({d for d, _ in option if d != a}) > 1
    everyone = len(e.moves) == len(robots) and len(ways) == 1
    said = []
    for way, steps in ways.items():
        one = everyone or len(steps) == 1
        who = "every robot" if everyone else ("robot" if one else "robots")
        said.append(f"{who} {way if one else way.replace('steps', 'step', 1)} "
                    f"({', '.join(steps)})")
    text = ("round: " if e.kind == "round" else "") + "; ".join(said)
    if chosen and chosen == len(e.moves):
        text += " [the adversary picks each direction: every moving robot's view is " \
                "mirror-symmetric]"
    return text


def _way(w: Any, a: int, b: int) -> str:
    """A step's direction in words: on a ring, clockwise (+1) or anticlockwise."""
    if w.kind == "ring":
        return "steps clockwise" if (a + 1) % w.size == b else "steps anticlockwise"
    return "steps"


def _failure(views: Views, cex: dict[str, Any], robots: tuple[Any, ...],
             still: bool = False) -> str:
    """How the execution fails; ``still``: its cycle is every robot staying."""
    w = views.inst.world
    prop = cex["property"]
    nodes = " ".join(w.format_node(v) for v, _, _ in robots)
    if still and prop == "perpetual-exploration":
        return (f"every robot stays for ever (robots on {nodes}): node {cex.get('node')} is "
                "never visited again")
    if prop == "exclusivity":
        return f"two robots on one node, or crossing one edge (robots on {nodes})"
    if prop == "termination":
        return "and that cycle repeats for ever, every robot acting or free to stay: it never ends"
    if prop == "perpetual-exploration":
        return (f"and that cycle repeats for ever without visiting node "
                f"{cex.get('node')}")
    if prop == "explored-when-final":
        return f"every robot stays for ever (robots on {nodes}) before every node was visited"
    return f"every robot stays for ever, robots on {nodes}: not gathered"


def _start(views: Views, j: int) -> str:
    inst = views.inst
    robots = inst.configurations[j][0]
    w = inst.world
    return (" ".join(w.format_node(v) for v in robots) + f" ({describe(w, robots, inst.meeting)})")


def _option(views: Views, key: str, o: int) -> str:
    """Option ``o`` of the view keyed ``key`` in words (stay, or a step in the key's frame)."""
    k = views.index.get(key)
    if k is None:
        return f"option {o}"
    label, colour = views.options[k][o]
    me = _me(key)
    word = "stay" if label == me else f"step to {label}"
    if views.inst.world.kind == "ring" and label != me:
        word = "step forward" if label == 1 else "step back"
    return word if colour is None else f"{word}, colour {colour}"


def _me(key: str) -> Any:
    import json

    first = json.loads(key)[0]
    return tuple(first) if isinstance(first, list) else first


def _leaves(tree: Any) -> list[int]:
    out, stack = [], [tree]
    while stack:
        node = stack.pop()
        if isinstance(node, int):
            out.append(node)
        else:
            stack.extend(node[1])
    return out
