"""``gather-verify simulate``: one execution under a seeded random fair adversary
(a thin wrapper around :func:`gather_verify.simulate.simulate`)."""

from __future__ import annotations

import argparse

from gather_verify.cli.common import (
    UsageError,
    add_configuration_arguments,
    bounded_int,
    load_configuration,
    print_json,
)
from schedulers import SCHEDULERS

HELP = "run one execution under a random fair adversary and show it step by step"


def add_arguments(parser: argparse.ArgumentParser) -> None:
    add_configuration_arguments(parser)
    parser.add_argument("--algorithm", help="algorithm name (default: the scenario's, else paper)")
    parser.add_argument("--scheduler", choices=tuple(SCHEDULERS))
    parser.add_argument("--multiplicity", help="multiplicity detection model (default local-weak)")
    parser.add_argument("--frames", choices=("all", "compass", "chirality"))
    parser.add_argument("--seed", type=bounded_int(0, 2**63 - 1), default=0)
    parser.add_argument("--max-steps", type=bounded_int(0, 10**7), default=10_000)
    parser.add_argument("--json", action="store_true", help="print one JSON object")


def run(args: argparse.Namespace) -> int:
    from gather_verify.algorithms import get_algorithm
    from gather_verify.model.geometry import bounding_box
    from gather_verify.paper.classes import classify_configuration
    from gather_verify.render import ascii_grid
    from gather_verify.simulate import simulate
    from schedulers.base import configuration_of

    configuration, scenario = load_configuration(args)
    if args.algorithm is not None and not args.algorithm.strip():
        raise UsageError("--algorithm is empty: name an algorithm (e.g. paper, or FILE.py:NAME)")
    name = args.algorithm or (scenario.algorithm if scenario else "paper")
    scheduler = args.scheduler or (scenario.scheduler if scenario else "async")
    detection = args.multiplicity or (scenario.multiplicity if scenario else "local-weak")
    frames = args.frames or (scenario.frames if scenario else "all")
    algorithm = get_algorithm(name)
    run_ = simulate(configuration, algorithm, scheduler, detection=detection, frames=frames,
                    seed=args.seed, max_steps=args.max_steps)
    klass = classify_configuration(configuration).name
    if args.json:
        print_json({"algorithm": name, "scheduler": scheduler, "multiplicity": detection,
                    "frames": frames, "seed": args.seed, "class": klass, **run_.to_json()})
        return 0
    meeting = configuration.meeting_nodes
    box = bounding_box([v for s in run_.states for v, _ in s] + list(meeting))
    print(f"{klass} configuration, {name} under {scheduler} ({detection}, frames {frames}), "
          f"seed {args.seed}")
    print("step 0")
    print(ascii_grid(configuration.robots, meeting, box))
    for k, (event, state) in enumerate(zip(run_.events, run_.states[1:], strict=True), 1):
        what = ", ".join(f"r{i} {list(a)}->{list(b)}" for i, a, b in event.moves) or "no move"
        print(f"step {k}: {event.kind} {list(event.robots)}: {what}")
        if event.kind != "look":
            print(ascii_grid(configuration_of(state), meeting, box))
    where = "" if run_.meeting_node is None else f" on {list(run_.meeting_node)}"
    message = f": {run_.message}" if run_.message else ""
    print(f"outcome: {run_.outcome}{where}{message}; {run_.moves} moves in {run_.steps} steps")
    return 0
