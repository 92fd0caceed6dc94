"""``gather-verify census``: how many configurations of a box fall in each class."""

from __future__ import annotations

import argparse

from gather_verify.cli.common import bounded_int, parse_box, print_json
from gather_verify.paper.classes import CLASS_NAMES, UNGATHERABLE
from gather_verify.sweeps.census import MAX_SIDE, census

HELP = "count the configurations of a WxH box (up to translation and D4) per class"


def add_arguments(p: argparse.ArgumentParser) -> None:
    limit = MAX_SIDE * MAX_SIDE
    p.add_argument("--robots", type=bounded_int(1, limit), required=True, metavar="N",
                   help="number of robots n (distinct nodes)")
    p.add_argument("--meeting", type=bounded_int(1, limit), required=True, metavar="M",
                   help="number of meeting nodes m")
    p.add_argument("--box", type=parse_box, required=True, metavar="WxH",
                   help=f"box of nodes, e.g. 4x4 (sides 1..{MAX_SIDE})")
    p.add_argument("--frames", choices=("all", "chirality", "compass"), default="all",
                   help="count up to the isometries the robots' frames allow, as sweep does "
                        "(all: D4; chirality: rotations; compass: translations only)")
    p.add_argument("--examples", type=bounded_int(0, 1000), default=0, metavar="K",
                   help="also print the first K representatives of each class")
    p.add_argument("--json", action="store_true",
                   help='print {"total": int, "classes": {"I11": int, ...}}')


def run(args: argparse.Namespace) -> int:
    w, h = args.box
    result = census(args.robots, args.meeting, w, h, keep=args.examples > 0, frames=args.frames)
    if args.json:
        out = result.to_json()
        if args.examples:
            out["examples"] = {name: [c.to_json() for c in result.examples(name)[:args.examples]]
                               for name in CLASS_NAMES}
        print_json(out)
        return 0
    print(f"census: n={args.robots} robots, m={args.meeting} meeting nodes, {w}x{h} box of nodes, "
          "up to translation and " + {"all": "D4", "chirality": "the rotations",
                                      "compass": "nothing else"}[args.frames])
    print(f"{'class':<13} {'count':>10} {'share':>8}")
    for name in CLASS_NAMES:
        count = result.counts[name]
        share = 100.0 * count / result.total if result.total else 0.0
        mark = "  (U)" if name in UNGATHERABLE else (
            "  (in U when its axis is empty)" if name == "UNCLASSIFIED" else "")
        print(f"{name:<13} {count:>10} {share:>7.2f}%{mark}")
        for c in result.examples(name)[:args.examples]:
            print(f"    robots {' '.join(f'{x},{y}' for x, y in c.robots)}  "
                  f"meeting {' '.join(f'{x},{y}' for x, y in sorted(c.meeting_nodes))}")
    print(f"{'total':<13} {result.total:>10}")
    return 0
