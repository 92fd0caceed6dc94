#!/usr/bin/env python3
"""Generate a Promela model of `go-to-target` on the ring `ring:N` under the ASYNC adversary.

Semantics (normative: SEMANTICS.md §4 and §9; see bench/spin/README.md):
  * robots on the cycle of N nodes 0 .. N-1, one meeting node m, identities kept;
  * a state is, per robot, its node and its pending destination (none when idle);
  * Look(i) on an idle robot that is not on m: the adversary chooses any
    neighbour strictly closer to m in graph distance and makes it pending (one
    transition per choice; on an even ring the node opposite m has two). A Look
    that ends in staying changes nothing and is therefore not a transition;
  * Move(i) on a robot with a pending destination: it goes there, becomes idle.

The algorithm's decisions are a table computed here from that definition (breadth-
first distances on the cycle), independently of gather_verify: per node, whether
the step to v+1 and the step to v-1 get strictly closer to m.

Encoding (lean state vector, all bytes):
  * x = the robot's node, p = its pending step (0 idle, 1 to x+1, 2 to x-1, mod N);
    the destination is a neighbour, so (node, step) is in bijection with
    (node, destination), and "pending reset when idle" is p == 0;
  * the table is two macros, UP(v) and DOWN(v), over node constants: it takes
    no room in the state vector;
  * one process, one `do` loop, one `d_step` per (robot, Look step) and one per
    (robot, Move), so every adversary action is exactly one SPIN transition.

Standard library only.
"""
from __future__ import annotations

import argparse
import sys
from collections import deque


def parse_world(text: str) -> int:
    """``ring:N`` -> N (3 <= N <= 255: nodes are bytes)."""
    kind, _, size = text.partition(":")
    if kind != "ring" or not size.isdigit():
        raise argparse.ArgumentTypeError(f"bad world {text!r}, expected ring:N")
    n = int(size)
    if not 3 <= n <= 255:
        raise argparse.ArgumentTypeError(f"ring:{n}: N must be in [3, 255]")
    return n


def parse_nodes(text: str) -> list[int]:
    try:
        nodes = [int(tok) for tok in text.replace(",", " ").split()]
    except ValueError:
        raise argparse.ArgumentTypeError(f"bad nodes {text!r}, expected e.g. \"0 3 5\"") from None
    if not nodes:
        raise argparse.ArgumentTypeError("no nodes given")
    return nodes


def distances(n: int, meeting: int) -> list[int]:
    """Graph distance of every node of the cycle to ``meeting`` (breadth-first)."""
    dist = [-1] * n
    dist[meeting] = 0
    queue = deque([meeting])
    while queue:
        v = queue.popleft()
        for u in ((v + 1) % n, (v - 1) % n):
            if dist[u] < 0:
                dist[u] = dist[v] + 1
                queue.append(u)
    return dist


def steps(n: int, meeting: int) -> list[tuple[int, ...]]:
    """Per node, the pending codes go-to-target allows: 1 (to v+1) and/or 2 (to v-1)
    when that neighbour is strictly closer to ``meeting``; none on ``meeting``."""
    dist = distances(n, meeting)
    return [tuple(code for code, u in ((1, (v + 1) % n), (2, (v - 1) % n))
                  if dist[u] < dist[v]) for v in range(n)]


def check_instance(n: int, robots: list[int], meeting: int) -> None:
    for v in [*robots, meeting]:
        if not 0 <= v < n:
            raise ValueError(f"node {v} is not on ring:{n} (nodes 0..{n - 1})")


def closed_form_counts(n: int, robots: list[int], meeting: int) -> tuple[int, int]:
    """Exact (states, transitions) of the ASYNC go-to-target space on ring:N.

    Independent of SPIN, used to validate it. Robots do not interact, so the
    reachable space is the product of the per-robot spaces and its edges are
    sum_i edges_i * prod_{j != i} states_j. A robot reaches every node on a
    shortest path from its start to m; a node with c strictly-closer neighbours
    (c = 0, 1, or 2 on the node opposite m of an even ring) gives 1 idle state
    + c pending states, c Look edges and c Move edges. So a robot at distance
    d < N/2 has 2d + 1 states and 2d edges; one opposite m has 2N and 2N.
    """
    check_instance(n, robots, meeting)
    table = steps(n, meeting)
    states_i, edges_i = [], []
    for start in robots:
        seen, todo = {start}, [start]
        while todo:  # the nodes on shortest paths from start to m
            v = todo.pop()
            for code in table[v]:
                u = (v + 1) % n if code == 1 else (v - 1) % n
                if u not in seen:
                    seen.add(u)
                    todo.append(u)
        states_i.append(sum(1 + len(table[v]) for v in seen))
        edges_i.append(sum(2 * len(table[v]) for v in seen))
    total = 1
    for s in states_i:
        total *= s
    edges = sum(e * (total // s) for s, e in zip(states_i, edges_i, strict=True))
    return total, edges


def longest_path(n: int, robots: list[int], meeting: int) -> int:
    """Length of the longest execution: a Look and a Move per hop to m."""
    dist = distances(n, meeting)
    return sum(2 * dist[v] for v in robots)


def _member(nodes: list[int]) -> str:
    return "(" + " || ".join(f"(v) == {v}" for v in nodes) + ")" if nodes else "(0)"


def make_model(n: int, robots: list[int], meeting: int) -> str:
    check_instance(n, robots, meeting)
    table = steps(n, meeting)
    up = [v for v in range(n) if 1 in table[v]]
    down = [v for v in range(n) if 2 in table[v]]
    out: list[str] = []
    w = out.append
    w(f"/* go-to-target on ring:{n}, ASYNC adversary, identities kept, no reduction.")
    w(f" * robots  : {' '.join(map(str, robots))}")
    w(f" * meeting : {meeting}")
    w(" * x = node, p = pending step (0 idle, 1 to x+1, 2 to x-1, mod N).")
    w(" * UP(v): v+1 is strictly closer to the meeting node; DOWN(v): v-1 is.")
    w(" * Generated by make_ring_model.py. */")
    w("")
    w(f"#define N {n}")
    w(f"#define UP(v) {_member(up)}")
    w(f"#define DOWN(v) {_member(down)}")
    w("")
    for i, v in enumerate(robots):
        w(f"byte x{i} = {v}; byte p{i} = 0;")
    w("")
    w("active proctype adversary()")
    w("{")
    w("end:")
    w("\tdo")
    for i in range(len(robots)):
        # Look(i): idle robot, choose a strictly-closer neighbour.
        w(f"\t:: d_step {{ p{i} == 0 && UP(x{i}) -> p{i} = 1 }}")
        w(f"\t:: d_step {{ p{i} == 0 && DOWN(x{i}) -> p{i} = 2 }}")
        # Move(i): go to the pending destination, become idle.
        w(f"\t:: d_step {{ p{i} == 1 -> x{i} = (x{i} + 1) % N; p{i} = 0 }}")
        w(f"\t:: d_step {{ p{i} == 2 -> x{i} = (x{i} + N - 1) % N; p{i} = 0 }}")
    w("\tod")
    w("}")
    return "\n".join(out) + "\n"


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--world", required=True, type=parse_world, help="ring:N, e.g. ring:14")
    ap.add_argument("--robots", required=True, type=parse_nodes,
                    help='robot nodes, e.g. "5 6 7 8 9"')
    ap.add_argument("--meeting", required=True, type=int, help="meeting node, e.g. 0")
    ap.add_argument("-o", "--output", default="-",
                    help="output .pml file (default: stdout)")
    args = ap.parse_args(argv)
    try:
        text = make_model(args.world, args.robots, args.meeting)
    except ValueError as exc:
        ap.error(str(exc))
    if args.output == "-":
        sys.stdout.write(text)
    else:
        with open(args.output, "w", encoding="ascii") as fh:
            fh.write(text)
    return 0


if __name__ == "__main__":
    sys.exit(main())
