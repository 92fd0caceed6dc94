"""``gather-verify bench``: the explorer against SPIN on the bench instance (or ``--quick``),
and the finite-world check against SPIN on a ring."""

from __future__ import annotations

import argparse

from gather_verify.cli.common import bounded_float, bounded_int, print_json
from gather_verify.errors import InvalidInput
from schedulers import plane_schedulers

HELP = ("measure explorer states/s, bytes per state and time to a verdict, beside SPIN; "
        "and a ring world's check beside SPIN")


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("--quick", action="store_true",
                        help="the small yardstick instances (Z² and ring:9)")
    parser.add_argument("--max-seconds", type=bounded_float(0.1, 10**6), default=3600.0)
    parser.add_argument("--no-spin", action="store_true",
                        help="do not run SPIN; compare with its stored results")
    parser.add_argument("--sweep", type=bounded_int(0, 10**6), default=0, metavar="K",
                        help="also time the paper sweep (n=3, m=3, 4x4, async) on K configurations")
    parser.add_argument("--scheduler", action="append", metavar="NAME", default=[],
                        choices=[name for name in plane_schedulers() if name != "async"],
                        help="also run the search under NAME (repeat for several) beside ASYNC "
                             "on the bench instance, its 3- and 4-robot prefixes and a second "
                             "5-robot instance, and the union engine's sweep of a 4x4 box: "
                             "transitions/s and the ratio to ASYNC's")
    parser.add_argument("--schedulers-only", action="store_true",
                        help="with --scheduler: only those rows (no SPIN, verdict or ring)")
    parser.add_argument("--json", action="store_true")


def run(args: argparse.Namespace) -> int:
    from gather_verify.bench import bench, format_bench

    if args.schedulers_only and not args.scheduler:
        raise InvalidInput("--schedulers-only needs --scheduler NAME")
    result = bench(quick=args.quick, max_seconds=args.max_seconds, run_spin=not args.no_spin,
                   sweep_limit=args.sweep, schedulers=args.scheduler,
                   schedulers_only=args.schedulers_only)
    if args.json:
        print_json(result)
    else:
        format_bench(result)
    return 0
