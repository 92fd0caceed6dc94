"""``gather-verify replay TRACE.json``: re-execute a trace from scratch and confirm its violation.

Exit 1 when the violation is confirmed (it stands, as ``check`` said); 5 when it no longer
reproduces, of one of two kinds, and the output says which (``why`` under ``--json``):
``step-not-taken``, the algorithm no longer takes one of its steps, or ``property-holds``,
every step is still taken but the property no longer fails at its end (the algorithm was
changed since); 2 when the trace does not match its configuration or is malformed."""

from __future__ import annotations

import argparse
from pathlib import Path
from typing import Any

from gather_verify.cli.common import (
    EXIT_NO_LONGER_REPRODUCES,
    EXIT_VIOLATED,
    print_json,
    writable_outputs,
)
from gather_verify.errors import InvalidInput

HELP = "re-execute a counterexample trace and confirm its violation independently"

WHY = {
    "step-not-taken": "the algorithm no longer takes one of its steps",
    "property-holds": "its steps replay, but the property no longer fails at the end",
}
"""The two kinds of exit 5: the ``why`` of ``--json``, and the words the text output says."""


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("trace", help="trace JSON file (docs/traces.md)")
    parser.add_argument("--svg", metavar="FILE", help="write the trace as an SVG storyboard")
    parser.add_argument("--html", metavar="FILE",
                        help="write the trace as an interactive viewer (one self-contained HTML "
                             "file: step through it, stale snapshots, the cycle of a livelock)")
    parser.add_argument("--quiet", action="store_true", help="no ASCII grids")
    parser.add_argument("--json", action="store_true", help="print one JSON object")
    parser.add_argument("--property", action="append", default=[], metavar="FILE.py:NAME",
                        help="load a property defined in a file (for a trace of a property "
                             "checked with check --property FILE.py:NAME); repeatable")


def run(args: argparse.Namespace) -> int:
    from gather_verify.render import render_trace
    from gather_verify.replay import NoLongerReproduces, Replayed, replay
    from gather_verify.trace import load_trace

    writable_outputs(svg=args.svg, html=args.html)
    for spec in args.property:
        from gather_verify.properties.registry import load_property

        if ":" not in spec:
            raise InvalidInput(f"--property {spec}: expected FILE.py:NAME")
        load_property(spec)
    from gather_verify.viewer import is_world_trace
    from gather_verify.world_replay import read_trace

    raw = read_trace(args.trace)
    if isinstance(raw, dict) and raw.get("world") == "rendezvous":
        return run_rendezvous(args, raw)
    if is_world_trace(raw):
        return run_world(args, raw)
    trace = load_trace(args.trace)
    try:
        result = replay(trace)
        why = "property-holds"
    except NoLongerReproduces as error:
        result = Replayed(False, str(error), len(trace["steps"]))
        why = "step-not-taken"
    return _answer(args, trace, result, why, render_trace, {})


def _answer(args: argparse.Namespace, trace: dict[str, Any], result: Any, why: str,
            render: Any, extra: dict[str, Any]) -> int:
    """The pictures asked for, then the answer (``--json`` or text) and the exit code of a
    replay: ``extra`` is what a world's trace adds (its ``world``)."""
    if args.svg:
        from gather_verify.render import trace_svg

        Path(args.svg).write_text(trace_svg(trace), encoding="utf-8")
    if args.html:
        from gather_verify.viewer import write_viewer

        write_viewer(trace, args.html)
    if args.json:
        print_json({"confirmed": result.confirmed, "message": result.message,
                    "steps": result.steps, "property": trace["property"], **extra,
                    **({} if result.confirmed else {"why": why})})
    else:
        if not args.quiet:
            print(render(trace))
        word = "CONFIRMED" if result.confirmed else f"NO LONGER REPRODUCES ({WHY[why]})"
        where = f" on {extra['world']}" if "world" in extra else ""
        print(f"{word}: {trace['property']}{where} ({result.steps} steps) - {result.message}")
    return EXIT_VIOLATED if result.confirmed else EXIT_NO_LONGER_REPRODUCES


def run_rendezvous(args: argparse.Namespace, trace: dict[str, Any]) -> int:
    """``replay`` of a rendezvous trace (:func:`gather_verify.rendezvous_check.replay_rendezvous`)."""
    from gather_verify.rendezvous_check import render_rendezvous_trace, replay_rendezvous
    from gather_verify.replay import NoLongerReproduces, Replayed

    if args.property or args.svg:
        raise InvalidInput("a rendezvous trace takes no --property or --svg (--html draws it)")
    try:
        result = replay_rendezvous(trace)
        why = "property-holds"
    except NoLongerReproduces as error:
        result = Replayed(False, str(error), len(trace["steps"]) - 1)
        why = "step-not-taken"
    return _answer(args, trace, result, why, render_rendezvous_trace, {"world": "rendezvous"})


def run_world(args: argparse.Namespace, trace: dict[str, Any]) -> int:
    """``replay`` of a finite world's trace (:mod:`gather_verify.world_replay`)."""
    from gather_verify.world_check import render_world_trace
    from gather_verify.world_replay import NoLongerReproduces, WorldReplayed, replay_world

    if args.property:
        raise InvalidInput("--property loads a property of the paper's world (Z²): a trace of "
                           f"{trace['world'][:80]} names one of its task's parts")
    try:
        result = replay_world(trace, Path(args.trace).resolve().parent)
        why = "property-holds"
    except NoLongerReproduces as error:
        result = WorldReplayed(False, str(error), len(trace["steps"]) - 1)
        why = "step-not-taken"
    return _answer(args, trace, result, why, render_world_trace, {"world": trace["world"]})
