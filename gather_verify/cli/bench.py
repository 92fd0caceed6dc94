"""``gather-verify bench``: explorer throughput on the issue-4 instance (or ``--quick``)."""

from __future__ import annotations

import argparse

from gather_verify.cli.common import bounded_float, print_json

HELP = "measure explorer states/s, transitions/s and bytes per state"


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("--quick", action="store_true", help="the small yardstick instance")
    parser.add_argument("--max-seconds", type=bounded_float(0.1, 10**6), default=3600.0)
    parser.add_argument("--json", action="store_true")


def run(args: argparse.Namespace) -> int:
    from gather_verify.bench import bench

    rows = [bench(quick=args.quick, max_seconds=args.max_seconds),
            bench(quick=args.quick, reduction=True, max_seconds=args.max_seconds)]
    if args.json:
        print_json({"runs": rows})
        return 0
    print(f"{'instance':10} {'reduction':9} {'states':>10} {'transitions':>12} {'seconds':>8} "
          f"{'states/s':>9} {'trans/s':>9} {'B/state':>8} complete")
    for r in rows:
        print(f"{r['instance']:10} {str(r['reduction']):9} {r['states']:>10} {r['transitions']:>12} "
              f"{r['seconds']:>8} {r['states_per_second']:>9} {r['transitions_per_second']:>9} "
              f"{r['bytes_per_state']:>8} {r['complete']}")
    return 0
