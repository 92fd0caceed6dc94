"""``gather-verify check``: explore every execution and decide the properties (a thin wrapper
around :func:`gather_verify.plane_check.run_check`)."""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path
from typing import TYPE_CHECKING, Any

from gather_verify.cli.common import (
    EXIT_INTERRUPTED,
    EXIT_OK,
    EXIT_VIOLATED,
    VERDICT_EXIT,
    UsageError,
    Words,
    add_configuration_arguments,
    add_json_arguments,
    bounded_float,
    bounded_int,
    load_configuration,
    print_json,
    without_timings,
    writable_outputs,
)
from gather_verify.engine.encoding import (
    DEFAULT_MAX_MEMORY_MB,
    DEFAULT_MAX_SECONDS,
    DEFAULT_MAX_STATES,
)
from gather_verify.engine.region import PLANE
from gather_verify.progress import Reporter, default_every
from gather_verify.worlds.base import decimal
from schedulers import SCHEDULERS

if TYPE_CHECKING:
    from collections.abc import Callable

    from gather_verify.engine.explore import Exploration
    from gather_verify.scenario import Scenario

HELP = ("verify an algorithm from one initial configuration against every adversary; on a "
        "scenario with an expectation for the algorithm and scheduler, exit 0 when it is met")


def add_arguments(parser: argparse.ArgumentParser) -> None:
    add_configuration_arguments(parser)
    _what_arguments(parser)
    _limit_arguments(parser)
    _output_arguments(parser)


def _what_arguments(parser: argparse.ArgumentParser) -> None:
    """What is checked: the world, the robots' lights and sight, the algorithm, its adversary,
    the properties, the reductions and the engine."""
    parser.add_argument("--world", help="the graph the robots live on: grid (Z², the paper's, "
                        "default), grid:WxH, ring:N, torus:WxH or graph:FILE (docs/worlds.md)")
    _rendezvous_options(parser)
    parser.add_argument("--task", help="on a finite world: gathering, "
                        "gathering-on-meeting-nodes (default with meeting nodes), "
                        "exclusive-perpetual-exploration or exploration-with-stop")
    parser.add_argument("--lights", default=None, metavar="K[:external|internal]",
                        help="luminous robots with K colours, on every world (external: a "
                             "robot does not see its own light; internal: only its own; "
                             "docs/worlds.md)")
    parser.add_argument("--colours", default=None, metavar="C", nargs="+", action=Words,
                        help="with --lights: each robot's initial colour (default 0)")
    parser.add_argument("--visibility", type=bounded_int(-10**6, 10**6), default=None,
                        metavar="HOPS", help="on a finite world: robots see only the nodes "
                        "within this many hops (default: the whole world)")
    parser.add_argument("--algorithm", help="a name, FILE.py:NAME or package.module:NAME "
                        "(default: the scenario's, else paper)")
    parser.add_argument("--scheduler", metavar="NAME",
                        help=f"the adversary: {', '.join(SCHEDULERS)} (round-robin:order=2 0 1 "
                             "fixes its order; default: the scenario's, else async)")
    parser.add_argument("--multiplicity", help="multiplicity detection model (default local-weak)")
    parser.add_argument("--frames", choices=("all", "compass", "chirality"))
    parser.add_argument("--property", action="append", dest="properties", metavar="P",
                        help="property to check, repeatable, default all: on the paper's world a "
                             "name or FILE.py:NAME (a Property object defined in that file, "
                             "docs/properties.md); on a finite world a part of the --task")
    parser.add_argument("--no-reduction", action="store_true",
                        help="switch off the anonymity and Aut(M) reductions")
    parser.add_argument("--engine", choices=("auto", "bulk", "reference"), default="auto",
                        help="the search: bulk (numpy and compiled kernels), reference (plain "
                             "Python, the engine the bulk one is tested against), or auto "
                             "(default: bulk when it can run the request); both give the same "
                             "states, verdict and trace (docs/explorer.md, docs/worlds.md)")


def _limit_arguments(parser: argparse.ArgumentParser) -> None:
    """The limits of the check, and the paper's world's own options (its region, keep going,
    the move bound, force)."""
    parser.add_argument("--max-states", type=bounded_int(1, 10**10), default=DEFAULT_MAX_STATES,
                        help="states the search may store (default %(default)s): past it, "
                        "INCOMPLETE (docs/reliability.md)")
    parser.add_argument("--max-seconds", type=bounded_float(0.001, 10**7),
                        default=DEFAULT_MAX_SECONDS,
                        help="seconds of the whole check, building the world included "
                        "(default %(default)g): past it, INCOMPLETE")
    parser.add_argument("--max-memory-mb", "--max-memory", type=bounded_float(1, 10**7),
                        default=None, metavar="MB", dest="max_memory",
                        help="resident memory limit of the check, building the world included "
                             "(default: a share of this "
                             f"machine's memory, at most {DEFAULT_MAX_MEMORY_MB})")
    parser.add_argument("--margin", type=bounded_int(0, 1000), default=None,
                        help="the paper's world only: region bound: the initial MER grown by this many nodes "
                             f"(default: {PLANE.initial}, doubled up to {PLANE.maximum} "
                             "while the region stops the search before any violation)")
    parser.add_argument("--keep-growing", action="store_true",
                        help="the paper's world only: grow the region even after a violation "
                             "is found, up to the "
                             "margin whose search the region does not stop, to look for "
                             "violations of other properties (slower: the verdict is the same)")
    parser.add_argument("--keep-going", action="store_true",
                        help="the paper's world only, with --property: search on after every "
                             "requested property has "
                             "its counterexample (by default the search stops there, as SPIN "
                             "stops at its first error)")
    parser.add_argument("--move-bound-c", type=bounded_float(0, 10**6), default=None,
                        metavar="C", help="the paper's world: move-bound holds when the total "
                        "moves are at most C * D * n (default 4)")
    parser.add_argument("--force", action="store_true",
                        help="the paper's world only: check even when the initial "
                             "configuration is in U or UNCLASSIFIED")


_FILE_OUTPUTS = (
    ("--trace-out", "write the counterexample trace (JSON)"),
    ("--svg", "write the trace as an SVG storyboard"),
    ("--html", "write the trace as an interactive viewer (one self-contained HTML file: step "
               "through it, stale snapshots, the cycle of a livelock)"),
    ("--graph-out", "the paper's world only: write the reachable state graph: GraphML "
                    "(.graphml) or DOT (.dot, .gv); with reductions on, a node is a class of "
                    "states (docs/explorer.md)"),
    ("--junit", "the paper's world only: write the verdict as a JUnit XML test case (for CI "
                "servers)"),
)
"""The files a check writes, with the help of each (``--FLAG FILE``)."""


def _output_arguments(parser: argparse.ArgumentParser) -> None:
    """What the check writes: the trace and its pictures, the graph, JUnit, the readings'
    table, progress lines, JSON."""
    for flag, text in _FILE_OUTPUTS:
        parser.add_argument(flag, metavar="FILE", help=text)
    parser.add_argument("--readings", metavar="all|OPTION[=V1|V2],...",
                        help="the paper's world only: run the paper's algorithm under every "
                             "reading of its ambiguous "
                             "passages (docs/interpretations.md) and report the robustness")
    parser.add_argument("--progress", type=bounded_float(0, 10**6), default=None,
                        metavar="SECONDS",
                        help="print a progress line on stderr every SECONDS (states so far, "
                             "seconds, what is being done); default: every 2 s when stderr is "
                             "a terminal, never otherwise; 0: never")
    add_json_arguments(parser, "print one JSON object", "the wall-clock seconds and peak memory")


def _rendezvous_options(parser: argparse.ArgumentParser) -> None:
    """The options of the rendezvous world (two robots with lights in the plane)."""
    parser.add_argument("--movement", choices=("rigid", "non-rigid"), help="on the "
                        "rendezvous world (docs/rendezvous.md): default non-rigid")
    parser.add_argument("--initial-colours", choices=("all", "same"), help="on the "
                        "rendezvous world: every pair, or one colour for both (default all)")


def run(args: argparse.Namespace) -> int:
    from gather_verify.cli import check_rings
    from gather_verify.worlds import FINITE, entry_of

    if _plane_of_lights(args):
        return run_rendezvous(args)
    if check_rings.every_size(args.world) is not None:  # ring:N+, every size at once
        return check_rings.run(args)
    if entry_of(args.world) == FINITE:
        if not args.scenario:
            return run_world(args)
        from gather_verify.scenario import load_scenario

        scenario = load_scenario(args.scenario)  # never ignored: it is read, and must agree
        if scenario.world != args.world.strip():
            raise UsageError(f"{args.scenario} is a scenario of {scenario.world or 'grid'}, "
                             f"not of --world {args.world}: give the scenario alone, or "
                             "--world with --robots")
        return run_world(args, scenario)
    if args.scenario:
        from gather_verify.scenario import load_scenario

        scenario = load_scenario(args.scenario)
        if scenario.world == "rendezvous":
            return run_rendezvous(args, scenario)
        if entry_of(scenario.world) == FINITE:
            return run_world(args, scenario)
    return _run_plane(args)


def _run_plane(args: argparse.Namespace) -> int:
    """``check`` on the paper's world (Z²): its engines, imported here, not by a finite
    world's check."""
    from gather_verify.engine.export import graph_format, write_graph
    from gather_verify.plane_check import run_check

    if args.task not in (None, "gathering-on-meeting-nodes") or args.visibility is not None:
        raise UsageError("--task and --visibility need a finite world "
                         "(--world ring:N, grid:WxH, torus:WxH or graph:FILE); on Z² the task "
                         "is the paper's and robots see the whole grid")
    configuration, scenario = load_configuration(args)
    writable_outputs(trace_out=args.trace_out, svg=args.svg, html=args.html, junit=args.junit,
                     graph_out=args.graph_out)
    if args.graph_out:
        graph_format(args.graph_out)  # refuse an unknown suffix before the search
    options = _plane_options(args, scenario)
    explored: list[Exploration] = []
    if args.readings:  # every reading (gather_verify.paper.readings), the first one reported in full
        from functools import partial

        from gather_verify.paper.readings import check_readings

        run_check = partial(check_readings, readings=args.readings)
    try:
        with _progress(args):
            report = run_check(
                configuration, properties=args.properties, reduction=not args.no_reduction,
                max_states=args.max_states, max_seconds=args.max_seconds,
                move_bound_c=4.0 if args.move_bound_c is None else args.move_bound_c,
                force=args.force, max_memory_mb=args.max_memory,
                keep_growing=args.keep_growing, keep_going=args.keep_going,
                engine={"bulk": "fast"}.get(args.engine, args.engine),
                on_exploration=explored.append if args.graph_out else None, **options)
    except KeyboardInterrupt:
        print("interrupted: check keeps no partial results (nothing was written); run the same "
              "command again to start over, with --max-seconds or --max-states to stop with "
              "INCOMPLETE and the statistics so far", file=sys.stderr)
        return EXIT_INTERRUPTED
    algorithm, scheduler = options["algorithm"], options["scheduler"]
    expected = _expectation(scenario, algorithm, scheduler, report)
    if args.graph_out:
        if explored:
            write_graph(explored[-1], args.graph_out)
        else:
            print(f"note: nothing was explored ({report['verdict']}): {args.graph_out} not "
                  "written", file=sys.stderr)
    _write_pictures(args, report)
    if args.junit:
        from gather_verify.junit import write_junit

        name = (f"{report['class']} robots={sorted(map(list, configuration.robots))} "
                f"meeting={sorted(map(list, configuration.meeting_nodes))}")
        write_junit(args.junit, f"check.{algorithm}.{scheduler}", [{**report, "name": name}])
    _show(args, report, expected, lambda: _print_plane(report, f"{algorithm} / {scheduler}"))
    if args.readings:
        from gather_verify.paper.readings import ROBUSTNESS_EXIT, format_readings

        if not args.json:
            format_readings(report)
        return ROBUSTNESS_EXIT[report["robustness"]]
    return _exit_code(report, expected)


def _plane_options(args: argparse.Namespace, scenario: Any) -> dict[str, Any]:
    """The algorithm, adversary, multiplicity detection, frames, lights and colours of a
    check on Z²: each as given, else the scenario's, else the default."""
    if args.algorithm is not None and not args.algorithm.strip():
        raise UsageError("--algorithm is empty: name an algorithm (e.g. paper, or FILE.py:NAME)")
    out = dict(algorithm=args.algorithm or (scenario.algorithm if scenario else "paper"),
               scheduler=args.scheduler or (scenario.scheduler if scenario else "async"),
               detection=args.multiplicity or (scenario.multiplicity if scenario
                                               else "local-weak"),
               frames=args.frames or (scenario.frames if scenario else "all"))
    lights = args.lights if args.lights is not None else (scenario.lights if scenario else None)
    colours = _colours(args.colours) if args.colours is not None else (
        scenario.colours if scenario else None)
    if colours is not None:  # given robot by robot as written; run_check takes sorted robots
        from gather_verify.model.geometry import parse_nodes
        from gather_verify.plane_check import sorted_colours

        written = parse_nodes(args.robots) if args.robots is not None else [
            tuple(v) for v in scenario.raw["robots"]]
        colours = sorted_colours(written, colours)
    if lights is not None:
        out["lights"] = lights
    if colours is not None:
        out["colours"] = colours
    if args.margin is not None:
        out["margin"] = args.margin
    return out


def _print_plane(report: dict[str, Any], what: str) -> None:
    """The text report of a check on Z²: verdict, counts, each property, the trace."""
    from gather_verify.plane_check import drift_line
    from gather_verify.render import render_trace

    ratio = "-" if report["ratio"] is None else f"{report['ratio']:.3f}"
    moves = ("infinite" if report["max_moves_infinite"] else
             "-" if report["max_moves"] is None else report["max_moves"])  # never 'None'
    print(f"{report['verdict']}  class {report['class']}  {what}")
    if report["property"]:
        print(f"property {report['property']}: {report['reason']}")
        print(f"cause: {report['cause']}")
    elif report["reason"]:
        print(f"reason: {report['reason']}")
    if report.get("drift"):
        print(drift_line(report["drift"]))
    print(f"states {report['states']}  transitions {report['transitions']}  max_moves {moves}"
          f"  D {report['D']}  n {report['n']}  ratio {ratio}  {report['seconds']:.2f}s")
    for name, result in report["properties"].items():
        holds = {True: "holds", False: "FAILS", None: "unknown"}[result["holds"]]
        print(f"  {name:18} {holds}  {result.get('reason', '')}".rstrip())
    for name, why in report.get("not_applicable", {}).items():
        print(f"  {name:18} not applicable: {why}")
    if report["trace"] is not None:
        print(render_trace(report["trace"]))


def _plane_of_lights(args: argparse.Namespace) -> bool:
    """Whether ``--world rendezvous`` is asked for (its options refused on any other world)."""
    from gather_verify.worlds import entry_of
    from gather_verify.worlds.rendezvous import RENDEZVOUS

    if entry_of(args.world) == RENDEZVOUS:
        return True
    if args.movement or args.initial_colours:
        raise UsageError("--movement and --initial-colours are options of the rendezvous "
                         "world (--world rendezvous)")
    return False


def _progress(args: argparse.Namespace) -> Reporter:
    """The progress lines of ``check --progress`` (default: every 2 s on a terminal)."""
    return Reporter(default_every() if args.progress is None else args.progress)


def _colours(text: str) -> list[int]:
    try:
        return [decimal(part) for part in text.split()]
    except ValueError:
        raise UsageError(f"--colours {text!r}: write one integer colour per robot") from None


PLANE_ONLY = ("readings", "margin", "keep_growing", "force", "graph_out", "junit",
              "move_bound_c", "keep_going")
"""Options of the paper's world (Z²) that a finite world does not take."""


def run_world(args: argparse.Namespace, scenario: Scenario | None = None) -> int:
    """``check --world W`` (or a scenario file with a ``world``): the finite-world search
    (:mod:`gather_verify.world_check`)."""
    from gather_verify.world_check import run_world_check
    from gather_verify.worlds import FINITE, entry_of

    world = args.world if entry_of(args.world) == FINITE else scenario.raw["world"]
    for option in PLANE_ONLY:
        if getattr(args, option):
            raise UsageError(f"--{option.replace('_', '-')} is an option of the paper's world "
                             f"(Z²), not of {world}")
    if args.robots is None and scenario is None:
        raise UsageError("give --robots (and --meeting for meeting nodes)")
    if scenario is not None and world.startswith("graph:"):  # a file beside the scenario
        world = "graph:" + str(Path(args.scenario).resolve().parent / world[6:])
    robots = args.robots if args.robots is not None else list(scenario.nodes[0])
    meeting = args.meeting if args.meeting is not None else (
        list(scenario.nodes[1]) if scenario else "")
    algorithm = args.algorithm or (scenario.algorithm if scenario else "go-to-target")
    scheduler = args.scheduler or (scenario.scheduler if scenario else "async")
    writable_outputs(trace_out=args.trace_out, svg=args.svg, html=args.html)
    try:
        with _progress(args):
            report = run_world_check(
                world, robots, meeting, algorithm, scheduler,
                task=args.task or (scenario.task if scenario else None), properties=args.properties,
                detection=args.multiplicity or (scenario.multiplicity if scenario else "local-weak"),
                frames=args.frames or (scenario.frames if scenario else "all"),
                visibility=args.visibility if args.visibility is not None else (
                    scenario.visibility if scenario else None),
                lights=args.lights if args.lights is not None else (
                    scenario.lights if scenario else None),
                colours=_colours(args.colours) if args.colours is not None else (
                    scenario.colours if scenario else None),
                reduction=not args.no_reduction, engine=args.engine,
                max_states=args.max_states, max_seconds=args.max_seconds,
                **({} if args.max_memory is None else {"max_memory_mb": args.max_memory}))
    except KeyboardInterrupt:
        print("interrupted: check keeps no partial results (nothing was written)",
              file=sys.stderr)
        return EXIT_INTERRUPTED
    expected = _expectation(scenario, algorithm, scheduler, report)
    _write_pictures(args, report)
    _show(args, report, expected, lambda: _print_world(report))
    return _exit_code(report, expected)


def _print_world(report: dict[str, Any]) -> None:
    """The text report of a check on a finite world: verdict, counts, each property, the
    trace."""
    from gather_verify.world_check import render_world_trace

    print(f"{report['verdict']}  {report['world']}  task {report['task']}  "
          f"{report['algorithm']} / {report['scheduler']}")
    if report["reason"]:
        print(f"{'property ' + report['property'] if report['property'] else 'reason'}: "
              f"{report['reason']}")
    print(f"states {report['states']}  transitions {report['transitions']}  "
          f"reductions {report['reductions']}  {report['seconds']:.2f}s  "
          f"engine {report['engine']}")
    if report.get("engine_fallback"):
        print(f"(the bulk engine cannot run this check: {report['engine_fallback']})")
    for name, result in report["properties"].items():
        holds = {True: "holds", False: "FAILS", None: "unknown"}[result["holds"]]
        print(f"  {name:24} {holds}  {result.get('reason', '')}".rstrip())
    if report["trace"] is not None:
        print(render_world_trace(report["trace"]))


RENDEZVOUS_TAKES = ("algorithm", "scheduler", "movement", "initial_colours", "max_states",
                    "max_seconds", "max_memory", "json", "timings", "trace_out", "progress",
                    "world", "engine", "html")
"""The options the rendezvous world takes; any other given is refused in one line."""


def run_rendezvous(args: argparse.Namespace, scenario: Scenario | None = None) -> int:
    """``check --world rendezvous`` (or a rendezvous scenario file): two robots with lights in
    the plane under one of §13's synchrony models (:mod:`gather_verify.rendezvous_check`)."""
    from gather_verify.rendezvous_check import run_rendezvous_check

    defaults = {"engine": "auto", "max_states": DEFAULT_MAX_STATES,
                "max_seconds": DEFAULT_MAX_SECONDS, "move_bound_c": 4.0}
    for option, value in vars(args).items():
        if option in RENDEZVOUS_TAKES or option in ("command", "func", "scenario") or callable(
                value):
            continue
        if value not in (None, False, [], defaults.get(option)):
            raise UsageError(f"--{option.replace('_', '-')} is no option of the rendezvous "
                             "world: it takes --algorithm, --scheduler, --movement, "
                             "--initial-colours and the limits")
    if args.engine == "bulk":
        raise UsageError("the bulk engine cannot run the rendezvous world: use --engine auto "
                         "or reference")
    raw = scenario.raw if scenario is not None else {}
    algorithm = args.algorithm or (scenario.algorithm if scenario else None)
    scheduler = args.scheduler or (scenario.scheduler if scenario else None)
    if not algorithm or not scheduler:
        raise UsageError("give --algorithm and --scheduler on the rendezvous world")
    writable_outputs(trace_out=args.trace_out, html=args.html)
    with _progress(args):
        report = run_rendezvous_check(
            algorithm, scheduler, movement=args.movement or raw.get("movement", "non-rigid"),
            initial_colours=args.initial_colours or raw.get("initial_colours", "all"),
            max_states=args.max_states,
            max_seconds=args.max_seconds,
            **({} if args.max_memory is None else {"max_memory_mb": args.max_memory}))
    if args.trace_out and report["trace"] is not None:
        Path(args.trace_out).write_text(json.dumps(report["trace"], indent=1) + "\n",
                                        encoding="utf-8")
    if args.html and report["trace"] is not None:
        from gather_verify.viewer import write_viewer

        write_viewer(report["trace"], args.html)
    expected = _expectation(scenario, algorithm, scheduler, report)
    _show(args, report, expected, lambda: _print_rendezvous(report))
    return _exit_code(report, expected)


def _print_rendezvous(report: dict[str, Any]) -> None:
    """The text report of a check on the rendezvous world: verdict, counts, the trace."""
    from gather_verify.rendezvous_check import render_rendezvous_trace

    print(f"{report['verdict']}  rendezvous  {report['algorithm']} / {report['scheduler']}  "
          f"{report['movement']}, initial colours {report['initial_colours']}")
    if report["reason"]:
        print(f"reason: {report['reason']}")
    print(f"states {report['states']}  transitions {report['transitions']}  "
          f"initial states {report['initial_states']}  {report['seconds']:.2f}s")
    if report["trace"] is not None:
        print(render_rendezvous_trace(report["trace"]))


def _expectation(scenario: Scenario | None, algorithm: str, scheduler: str,
                 report: dict[str, Any]) -> dict[str, Any] | None:
    """Whether ``report`` meets the scenario's expectation for this algorithm and scheduler
    (and its expected class), also kept in the report as ``expectation``; None when the
    scenario has none."""
    if scenario is None:
        return None
    from gather_verify.scenario_tests import expectation_for, expectation_mismatch

    expectation = expectation_for(scenario, algorithm, scheduler)
    if not expectation:
        return None
    why = expectation_mismatch(expectation, report)
    if why is None and scenario.expected_class not in (None, report.get("class")):
        why = f"expected class {scenario.expected_class}, got {report['class']}"
    report["expectation"] = {"matched": why is None, "mismatch": why,
                             "verdict": expectation.verdict, "property": expectation.property}
    return report["expectation"]


def _show(args: argparse.Namespace, report: dict[str, Any], expected: dict[str, Any] | None,
          text: Callable[[], None]) -> None:
    """Print the report: one JSON object, or ``text``'s lines and the scenario's expectation
    met or not."""
    if args.json:
        print_json(report if args.timings else without_timings(report))
        return
    text()
    if expected is not None:
        print(f"expectation of {args.scenario}: "
              + ("matched" if expected["matched"] else f"NOT matched: {expected['mismatch']}"))


def _exit_code(report: dict[str, Any], expected: dict[str, Any] | None) -> int:
    """The verdict's exit code; on a scenario with an expectation, met is success whatever
    the verdict."""
    if expected is not None:
        return EXIT_OK if expected["matched"] else EXIT_VIOLATED
    return VERDICT_EXIT[report["verdict"]]


def _write_pictures(args: argparse.Namespace, report: dict[str, Any]) -> None:
    """The counterexample's trace, SVG and viewer, where asked for; a note for each file
    that a result with no counterexample leaves unwritten."""
    trace = report["trace"]
    if trace is not None and args.trace_out:
        Path(args.trace_out).write_text(json.dumps(trace, indent=1) + "\n", encoding="utf-8")
    if trace is not None and args.svg:
        from gather_verify.render import trace_svg

        Path(args.svg).write_text(trace_svg(trace), encoding="utf-8")
    if trace is not None and args.html:
        from gather_verify.viewer import write_viewer

        write_viewer(trace, args.html)
    unwritten = [f for f in (args.trace_out, args.svg, args.html) if f and trace is None]
    if unwritten:
        print(f"note: {report['verdict']} has no counterexample trace: "
              f"{', '.join(unwritten)} not written", file=sys.stderr)
