"""``check --world ring:N+``: a safety property of a gap-rule algorithm on every ring of N
nodes or more (:mod:`gather_verify.parametric`, docs/howto/rings.md)."""

from __future__ import annotations

import argparse
import re
from typing import Any

from gather_verify.cli.common import EXIT_INCOMPLETE, EXIT_OK, EXIT_VIOLATED, UsageError, print_json

PATTERN = re.compile(r"^ring:(\d+)\+$")


def every_size(world: str | None) -> int | None:
    """The least size of ``ring:N+`` (every ring of N nodes or more), else None."""
    m = PATTERN.match((world or "").strip())
    return int(m[1]) if m else None


def run(args: argparse.Namespace) -> int:
    from gather_verify.algorithms import get_algorithm
    from gather_verify.parametric import prove, round_text

    low = every_size(args.world)
    assert low is not None
    robots = (args.robots or "").strip()
    if not robots.isdigit():
        raise UsageError(f"--world {args.world}: --robots is a count (the proof covers every "
                         "start of that many robots on distinct nodes)")
    if (args.task or "exclusive-perpetual-exploration") != "exclusive-perpetual-exploration":
        raise UsageError(f"--world {args.world}: for every ring size, check decides "
                         "exclusivity, the safety part of --task exclusive-perpetual-exploration")
    if args.lights or args.visibility is not None or args.meeting:
        raise UsageError(f"--world {args.world}: gap rules read the whole ring, with no lights "
                         "and no meeting nodes")
    algorithm = get_algorithm(args.algorithm or "")
    scheduler = args.scheduler or "async"
    detection = args.multiplicity or "local-weak"
    frames = args.frames or "all"
    k = int(robots)
    got = prove(algorithm, k, scheduler, low=low, detection=detection, frames=frames,
                max_seconds=args.max_seconds)
    report = {"world": args.world, "sizes": f"n >= {got['low']}", **got,
              "not_decided": "perpetual-exploration (liveness): check each size with "
                             "--world ring:N"}
    if got["holds"] is False:
        report["checker"] = _confirm(args, algorithm, got, scheduler, detection, frames)
    if args.json:
        print_json(report if args.timings else {k2: v for k2, v in report.items()
                                                 if k2 != "seconds"})
    else:
        _print(report, round_text)
    if got["holds"] is None:
        return EXIT_INCOMPLETE
    return EXIT_OK if got["holds"] else EXIT_VIOLATED


def _confirm(args: argparse.Namespace, algorithm: Any, got: dict, scheduler: str,
             detection: str, frames: str) -> dict:
    """The ordinary checker from the counterexample's configuration, at its size."""
    from gather_verify.world_check import run_world_check

    report = run_world_check(f"ring:{got['n']}", list(got["robots_at"]), [], algorithm,
                             scheduler, task="exclusive-perpetual-exploration",
                             properties=["exclusivity"], detection=detection, frames=frames,
                             reduction=False, max_seconds=args.max_seconds)
    return {"verdict": report["verdict"], "property": report.get("property"),
            "states": report["states"]}


def _print(report: dict, round_text: object) -> None:
    what = (f"exclusivity  {report['robots']} robots  {report['scheduler']}  frames "
            f"{report['frames']}  every ring size {report['sizes']}")
    if report["holds"]:
        print(f"VERIFIED  {what}")
        print(f"proof: from any {report['robots']} robots on distinct nodes of a ring of any "
              f"size {report['sizes']}, one round of {report['scheduler']} keeps them on "
              "distinct nodes and crosses no edge (z3, linear integer arithmetic"
              + (f", {report['seconds']:.2f}s" if "seconds" in report else "") + "). Every "
              "start is such a configuration, so no run from any start breaks exclusivity.")
    elif report["holds"] is False:
        print(f"VIOLATED  {what}")
        checker = report["checker"]
        print(f"at ring:{report['n']}, robots on {' '.join(map(str, report['robots_at']))} "
              f"(gaps {' '.join(map(str, report['gaps']))}): "
              f"{round_text(report)}: two robots meet or cross "  # type: ignore[operator]
              f"(the ordinary checker from there: {checker['verdict']} {checker['property']})")
    else:
        print(f"INCOMPLETE  {what}: {report['reason']}")
    print(f"not decided here: {report['not_decided']}")
