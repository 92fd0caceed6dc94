"""``gather-verify sweep``: verify every small configuration and store the results."""

from __future__ import annotations

import argparse
import json
import os
import sys
from pathlib import Path
from typing import Any

from gather_verify.cli.common import (
    EXIT_INCOMPLETE,
    EXIT_INTERRUPTED,
    add_json_arguments,
    bounded_float,
    bounded_int,
    parse_box,
    print_json,
    without_timings,
    writable_outputs,
)
from gather_verify.errors import InvalidInput
from gather_verify.watchdog import allowance, deadline
from schedulers import SCHEDULERS

HELP = "verify every configuration of a box (up to symmetry) and store the results"
DEFAULT_DB = "gather-verify-results.sqlite"


def add_arguments(p: argparse.ArgumentParser) -> None:
    _what_arguments(p)
    _how_arguments(p)
    p.add_argument("--junit", metavar="FILE", help="also write JUnit XML, one test case per configuration")
    p.add_argument("--readings", metavar="all|OPTION[=V1|V2],...",
                   help="sweep the paper's algorithm under every reading of its ambiguous "
                        "passages and print the class x robustness table")
    p.add_argument("--readings-on", choices=("all", "violated"), default="all",
                   help="with --readings: run the other readings on every configuration, or "
                        "only on those the base reading violates (the rest: DEFAULT-ONLY)")
    p.add_argument("--readings-types", default=None, metavar="TYPE,...",
                   help="with --readings: only configurations whose M is of these types "
                        "(I1-ordered, I13, reflection, rotation; default all)")
    add_json_arguments(p, "print the summary as JSON",
                       "the slowest configurations and their seconds")


def _what_arguments(p: argparse.ArgumentParser) -> None:
    """What is swept: the configurations, the world, the algorithm and its adversary."""
    p.add_argument("--robots", type=count_range, default=None,
                   help="robots n, or a range A-B (every n from A to B); required but on the "
                        "rendezvous world")
    p.add_argument("--meeting", type=count_range, default=None,
                   help="meeting nodes m, or a range A-B (required on the paper's world; on a "
                        "finite world the default is 0: the task needs none)")
    p.add_argument("--box", type=parse_box, default=None,
                   help="box of nodes, WxH (the paper's world; a finite world needs none)")
    p.add_argument("--world", default="grid",
                   help="grid (Z², the paper's, default), or a finite world: grid:WxH, ring:N, "
                        "a range of rings ring:A-B, torus:WxH, graph:FILE (docs/worlds.md); "
                        "rendezvous: the table of two robots with lights in the plane "
                        "(docs/rendezvous.md)")
    p.add_argument("--task", default=None,
                   help="on a finite world: gathering, gathering-on-meeting-nodes (default "
                        "with meeting nodes), exclusive-perpetual-exploration, "
                        "exploration-with-stop")
    p.add_argument("--visibility", type=bounded_int(0, 10**6), default=None, metavar="HOPS",
                   help="on a finite world: robots see only the nodes within this many hops")
    p.add_argument("--lights", default=None, metavar="K[:external|internal]",
                   help="luminous robots with K colours, all starting at 0 (on Z² each "
                        "configuration is checked on its own, by the bulk engine)")
    p.add_argument("--initial-colours", choices=("all", "same"), help="with --lights: every "
                   "colouring up to symmetry, not only all 0; rendezvous: all or same")
    p.add_argument("--algorithm", default=None, help="a name, FILE.py:NAME or package."
                   "module:NAME (default paper); rendezvous: A,B,... or all (default)")
    p.add_argument("--scheduler", default=None, metavar="NAME", help=f"the adversary: "
                   f"{', '.join(SCHEDULERS)} (default async); rendezvous: M,N,... or all")
    _rendezvous_arguments(p)
    p.add_argument("--multiplicity", default="local-weak", help="detection model")
    p.add_argument("--frames", default="all", choices=("all", "chirality", "compass"))
    p.add_argument("--property", action="append", dest="properties", metavar="P",
                   help="property to check, a name or FILE.py:NAME (docs/properties.md); "
                        "repeat; default: all")
    p.add_argument("--no-reduction", action="store_true")


def _how_arguments(p: argparse.ArgumentParser) -> None:
    """How it runs: the store, the workers, the limits of each configuration, the engine."""
    p.add_argument("--db", default=DEFAULT_DB, help=f"results database (default {DEFAULT_DB})")
    p.add_argument("--fresh", action="store_true",
                   help="drop the stored rows of these settings and compute every one again "
                        "(rows of an edited algorithm are never reused anyway: they are keyed "
                        "by its source's fingerprint)")
    p.add_argument("--force", action="store_true",
                   help="check the configurations in U or UNCLASSIFIED too (skipped as "
                        "NOT-APPLICABLE otherwise), for an algorithm that handles them")
    p.add_argument("--fingerprint-extra", nargs="+", metavar="FILE", default=[],
                   help="files the algorithm reads (parameters, data): their contents join the "
                        "fingerprint, so an edit computes again")
    p.add_argument("--workers", type=bounded_int(1, 512), default=None,
                   help="local processes (default: the number of cores)")
    p.add_argument("--dask", metavar="local|ADDRESS", default=None,
                   help="run on a Dask cluster: 'local' starts one, else a scheduler address")
    p.add_argument("--max-states-per-config", type=bounded_int(1, 10**9), default=2_000_000,
                   help="states of one configuration's search (default %(default)s)")
    p.add_argument("--max-seconds-per-config", type=bounded_float(0.001, 86400.0), default=600.0,
                   help="seconds of one configuration's check (default %(default)g); on a "
                        "finite world they also bound building it and listing its "
                        "configurations")
    p.add_argument("--max-memory-mb", type=bounded_float(1, 10**7), default=None, metavar="MB",
                   help="resident memory limit of each worker process (default: a share of "
                        "this machine's memory); a configuration that hits it is INCOMPLETE")
    p.add_argument("--move-bound-c", type=bounded_float(0.0, 1e6), default=None, metavar="C",
                   help="the paper's world: move-bound holds when the total moves are at most "
                        "C * D * n (default 4)")
    p.add_argument("--engine", choices=("union", "per-config"), default="union",
                   help="union: one state graph per meeting-node set, shared by its "
                        "configurations (default; on a finite world too); per-config: one "
                        "search per configuration. Same results")
    p.add_argument("--limit", type=bounded_int(1, 10**9), default=None,
                   help="only the first N configurations of the enumeration")
    p.add_argument("--keep-growing", action="store_true",
                   help="grow a configuration's region even after a violation is found "
                        "(check --keep-growing; slower, the verdicts are the same)")


def count_range(text: str) -> range:
    """argparse type: ``N`` or ``A-B`` with 0 <= A <= B <= 16 (robots: at least 1)."""
    low, sep, high = text.partition("-")
    parse = bounded_int(0, 16)
    first = parse(low)
    last = parse(high) if sep else first
    if last < first:
        raise argparse.ArgumentTypeError(f"empty range {text!r}")
    return range(first, last + 1)


def _robots_world(args: argparse.Namespace) -> None:
    """A sweep of robots on nodes (Z² or a finite world): the rendezvous world's options
    refused, ``--robots`` required, the algorithm and scheduler defaults (paper, async)."""
    for option in ("movement", "spin", "traces", "markdown"):
        if getattr(args, option) is not None:
            raise InvalidInput(f"--{option} is an option of the rendezvous world "
                               "(--world rendezvous)")
    if args.initial_colours == "same":
        raise InvalidInput("--initial-colours same is an option of the rendezvous world")
    if args.robots is None:
        raise InvalidInput("gather-verify sweep: the following arguments are required: --robots")
    args.algorithm = "paper" if args.algorithm is None else args.algorithm
    args.scheduler = "async" if args.scheduler is None else args.scheduler


def _rendezvous_arguments(p: argparse.ArgumentParser) -> None:
    """The options of the rendezvous world's table."""
    p.add_argument("--movement", choices=("rigid", "non-rigid"), default=None,
                   help="on the rendezvous world: rigid or non-rigid moves (default: both)")
    p.add_argument("--spin", metavar="FILE",
                   help="on the rendezvous world: the SPIN harness's results "
                        "(bench/spin/light/results.json), put beside our verdicts")
    p.add_argument("--traces", metavar="DIR",
                   help="on the rendezvous world: write each failing cell's trace here")
    p.add_argument("--markdown", metavar="FILE",
                   help="on the rendezvous world: write the table as Markdown")


def _rendezvous(args: argparse.Namespace) -> int:
    """``sweep --world rendezvous``: the table, algorithm x synchrony model x movement x
    initial colours (:mod:`gather_verify.sweeps.rendezvous`); no database."""
    from gather_verify.sweeps import rendezvous as table

    defaults = {"db": DEFAULT_DB, "multiplicity": "local-weak", "frames": "all",
                "engine": "union", "move_bound_c": 4.0, "readings_on": "all"}
    takes = {"algorithm", "scheduler", "movement", "initial_colours", "spin", "traces",
             "markdown", "json", "timings", "world", "max_states_per_config",
             "max_seconds_per_config", "max_memory_mb", "command"}
    for option, value in vars(args).items():
        if option in takes or callable(value) or value in (None, False, []) or \
                value == defaults.get(option):
            continue
        raise InvalidInput(f"--{option.replace('_', '-')} is no option of the rendezvous world "
                           "(a table of milliseconds per cell, no database): it takes "
                           "--algorithm, --scheduler, --movement, --initial-colours, --spin, "
                           "--traces and --markdown")
    algorithms, models = table.check_known(args.algorithm, args.scheduler)
    spin = table.load_spin(args.spin) if args.spin else None
    result = table.table(algorithms, models,
                         [args.movement] if args.movement else ["rigid", "non-rigid"],
                         [args.initial_colours] if args.initial_colours else ["all", "same"],
                         spin=spin, traces=Path(args.traces) if args.traces else None,
                         max_states=args.max_states_per_config,
                         max_seconds=args.max_seconds_per_config)
    text = table.markdown(result)
    if args.markdown:
        Path(args.markdown).write_text(text, encoding="utf-8")
    if args.json:
        cells = result["cells"] if args.timings else [
            {k: v for k, v in c.items() if "seconds" not in k} for c in result["cells"]]
        print(json.dumps({**result, "cells": cells, "disagreements": [
            {k: c[k] for k in ("algorithm", "scheduler", "movement", "initial_colours",
                               "verdict", "spin")} for c in result["disagreements"]]},
            indent=1, sort_keys=True))
    else:
        print(text, end="")
    return 1 if result["disagreements"] else 0


def run(args: argparse.Namespace) -> int:
    """Every input read once, before anything runs: the extra files (which the algorithm may
    read at import), then the algorithm and property files, copied, so that what is loaded,
    fingerprinted and shipped to the workers is one snapshot (docs/reliability.md)."""
    from gather_verify.algorithms.loading import absolute_spec, snapshot
    from gather_verify.fingerprint import files_fingerprint
    from gather_verify.properties.registry import absolute_spec as absolute_property
    from gather_verify.sweeps.store import check_db_path
    from gather_verify.worlds import entry_of
    from gather_verify.worlds.rendezvous import RENDEZVOUS

    if entry_of(args.world) == RENDEZVOUS:
        return _rendezvous(args)
    _robots_world(args)
    check_db_path(args.db)
    args.fingerprint_extra = [os.path.abspath(f) for f in args.fingerprint_extra]
    files_fingerprint(args.fingerprint_extra)  # an unreadable file fails before any work
    args.algorithm = absolute_spec(args.algorithm)  # the workers load the same file
    args.properties = [absolute_property(p) for p in args.properties or ()] or None
    with snapshot({args.algorithm, *(args.properties or ())}):
        return _run(args)


def _run(args: argparse.Namespace) -> int:
    from gather_verify.algorithms import get_algorithm
    from gather_verify.algorithms.moves import frames_for
    from gather_verify.model.view import check_detection
    from gather_verify.sweeps.census import validate_census_arguments
    from gather_verify.sweeps.sweep import SweepSettings, format_summary
    from gather_verify.worlds import FINITE, entry_of
    from schedulers import get_scheduler

    get_scheduler(args.scheduler)  # an unknown name fails before any work
    if entry_of(args.world) == FINITE:
        return _worlds(args)
    if args.box is None or args.meeting is None:
        raise InvalidInput(f"--{'box' if args.box is None else 'meeting'} is required in the "
                           "paper's world (or give a finite --world)")
    if args.task is not None or args.visibility is not None:
        raise InvalidInput("--task and --visibility need a finite world (--world ring:N, "
                           "grid:WxH, torus:WxH or graph:FILE)")
    if args.lights is not None or args.initial_colours is not None:
        _lights(args)
    if 0 in args.robots:
        raise InvalidInput("--robots: at least one robot")
    if args.readings_types is not None and not args.readings:
        raise InvalidInput("--readings-types needs --readings (it picks which configurations the "
                           "readings run on)")
    with deadline(allowance(args.max_seconds_per_config)):  # an endless import ends (watchdog)
        algorithm = get_algorithm(args.algorithm)  # unknown names fail before any work
    writable_outputs(junit=args.junit)
    check_detection(args.multiplicity)
    frames_for(args.frames)
    for n in args.robots:
        for m in args.meeting:
            validate_census_arguments(n, m, *args.box)
    if args.properties:
        from gather_verify.properties.registry import check_property_names

        with deadline(allowance(args.max_seconds_per_config)):
            check_property_names(args.properties)
        from gather_verify.plane_check import refuse_inapplicable
        from gather_verify.worlds.moves import parse_lights

        refuse_inapplicable(args.properties, algorithm, args.frames,
                            None if args.lights is None else parse_lights(args.lights))
    settings = [SweepSettings(
        robots=n, meeting=m, box=args.box, algorithm=args.algorithm,
        scheduler=args.scheduler, detection=args.multiplicity, frames=args.frames,
        properties=tuple(args.properties or ()), max_states=args.max_states_per_config,
        max_seconds=args.max_seconds_per_config,
        move_bound_c=4.0 if args.move_bound_c is None else args.move_bound_c,
        reduction=not args.no_reduction, max_memory_mb=args.max_memory_mb,
        keep_growing=args.keep_growing,
        fingerprint_extra=tuple(args.fingerprint_extra),
        force=args.force, lights=args.lights, initial_colours=args.initial_colours,
    ) for n in args.robots for m in args.meeting]
    if args.readings:
        return _readings(args, settings)
    summary = _swept(args, settings)
    if summary is None:
        return EXIT_INTERRUPTED
    if args.junit:
        from gather_verify.junit import write_sweep_junit

        write_sweep_junit(args.db, settings, args.junit)
    if args.json:
        print_json(summary if args.timings else without_timings(summary))
    else:
        format_summary(summary)
        _reading_note(args.algorithm)
        print(f"\nresults: {os.path.abspath(args.db)}")
        if summary["settings"]:
            print(f"fingerprint: {summary['settings']['fingerprint']} (the algorithm's source "
                  "and options, property files, --fingerprint-extra files, gather-verify's own "
                  "source: an edit of any computes again)")
    verdicts = {v for by in summary["verdicts"].values() for v in by}
    if "VIOLATED" in verdicts:
        return 1
    return 3 if "INCOMPLETE" in verdicts else 0


def _reading_note(algorithm: str) -> None:
    """Under the verdict table of the paper's algorithm: the counts are one reading's, not
    yet faults of the paper (SEMANTICS.md §8), and how to tell them apart."""
    from gather_verify.algorithms import parse_name

    if algorithm.partition(":")[0] != "paper":  # a file or module spec is never the paper's
        return
    _, options = parse_name(algorithm)
    which = "its default reading" if not options else f"the reading {algorithm}"
    print(f"\nThe verdicts are those of the paper's algorithm under {which} of the paper's "
          "ambiguous passages (docs/interpretations.md). A VIOLATED count is not yet a fault "
          "of the paper: another reading removes many of them. Add --readings all to count "
          "ROBUST-VIOLATED (every reading refutes a claim) apart from READING-DEPENDENT "
          "(docs/findings.md).")


def _lights(args: argparse.Namespace) -> None:
    """Luminous robots on the paper's world: checked one configuration and colouring at a
    time by the bulk engine (the union engine encodes no lights)."""
    from gather_verify.sweeps.lit_census import check_colourings
    from gather_verify.worlds.moves import parse_lights

    if args.lights is None:
        raise InvalidInput("--initial-colours needs --lights K")
    if args.readings:
        raise InvalidInput("--readings are the paper's algorithm's, for oblivious robots: "
                           "give no --lights")
    light = parse_lights(args.lights)
    if args.initial_colours == "all":
        check_colourings(light.colours, max(args.robots))


def _worlds(args: argparse.Namespace) -> int:
    """``sweep --world W``: :func:`_world_sweep`; a limit that stops the setup (building a
    world, listing its configurations) before any configuration is checked is one line,
    exit 3 (INCOMPLETE), never a hang."""
    from gather_verify.engine.bounds import SetupStopped

    try:
        return _world_sweep(args)
    except SetupStopped as stop:
        print(f"INCOMPLETE: {stop.reason}; no configuration was checked (raise "
              "--max-seconds-per-config or --max-memory-mb, or sweep a smaller world)",
              file=sys.stderr)
        return EXIT_INCOMPLETE


def _world_sweep(args: argparse.Namespace) -> int:
    """``sweep --world W``: every class of initial configurations of a finite world (or of
    each ring of a range), one search each, into the same store."""
    from gather_verify.algorithms import get_algorithm
    from gather_verify.model.view import check_detection
    from gather_verify.sweeps.sweep import SweepSettings, format_summary
    from gather_verify.tasks import get_task
    from gather_verify.worlds import finite_world, world_specs

    if args.meeting is None:
        args.meeting = [0]
    for option in ("box", "readings", "readings_types", "junit", "force", "keep_growing",
                   "move_bound_c"):
        if getattr(args, option):
            raise InvalidInput(f"--{option.replace('_', '-')} is an option of the paper's world "
                               f"(Z²), not of {args.world}")
    if 0 in args.robots:
        raise InvalidInput("--robots: at least one robot")
    if args.algorithm == "paper":
        args.algorithm = "go-to-target"
    with deadline(allowance(args.max_seconds_per_config)):  # an endless import ends (watchdog)
        get_algorithm(args.algorithm)
    check_detection(args.multiplicity)
    specs = world_specs(args.world)
    if args.world.startswith("graph:"):  # the workers read the same file, wherever they run
        specs = ["graph:" + os.path.abspath(args.world.partition(":")[2])]
    from gather_verify.engine.bounds import setup
    from gather_verify.engine.resources import memory_budget_mb

    worlds = []
    for spec in specs:  # a bad world fails before any work; a huge one ends at the limits
        with setup(f"building {spec}", args.max_seconds_per_config,
                   args.max_memory_mb or memory_budget_mb()):
            worlds.append(finite_world(spec))
            worlds[-1].symmetries(args.frames)
    if args.task is not None:
        get_task(args.task)
    if args.lights is not None:
        from gather_verify.worlds.moves import parse_lights

        parse_lights(args.lights)
    elif args.initial_colours is not None:
        raise InvalidInput("--initial-colours needs --lights K")
    settings = [SweepSettings(
        robots=n, meeting=m, box=(0, 0), algorithm=args.algorithm, scheduler=args.scheduler,
        detection=args.multiplicity, frames=args.frames,
        properties=tuple(args.properties or ()), max_states=args.max_states_per_config,
        max_seconds=args.max_seconds_per_config, reduction=not args.no_reduction,
        max_memory_mb=args.max_memory_mb,
        fingerprint_extra=tuple(args.fingerprint_extra),
        world=w.name, task=args.task or ("gathering-on-meeting-nodes" if m else "gathering"),
        visibility=args.visibility, lights=args.lights, initial_colours=args.initial_colours,
    ) for w in worlds for n in args.robots for m in args.meeting]
    summary = _swept(args, settings)
    if summary is None:
        return EXIT_INTERRUPTED
    if args.json:
        print_json(summary if args.timings else without_timings(summary))
    else:
        format_summary(summary)
        print(f"\nresults: {os.path.abspath(args.db)}")
    verdicts = {v for by in summary["verdicts"].values() for v in by}
    if "VIOLATED" in verdicts:
        return 1
    return 3 if "INCOMPLETE" in verdicts else 0


def _readings(args: argparse.Namespace, settings: list) -> int:
    """``sweep --readings``: every reading into the store, then the class x robustness table."""
    from gather_verify.paper.readings import format_robustness, readings_sweep

    if args.junit:
        raise InvalidInput("--junit is not available with --readings")
    try:
        from gather_verify.paper.readings import M_TYPES

        types = M_TYPES if args.readings_types is None else [
            t.strip() for t in args.readings_types.split(",")]
        table, switches = readings_sweep(settings, args.readings, args.db, on=args.readings_on,
                                         types=types, workers=args.workers, dask=args.dask,
                                         progress=not args.json, limit=args.limit)
    except KeyboardInterrupt:
        print(f"interrupted: every finished configuration is kept in {os.path.abspath(args.db)}; "
              "run the same command again to resume", file=sys.stderr)
        return EXIT_INTERRUPTED
    if args.json:
        print_json({"robustness": table, "switches": switches})
    else:
        format_robustness(table, switches=switches)
        print(f"\nresults: {os.path.abspath(args.db)}")
    seen = {label for by in table.values() for label in by}
    if seen & {"ROBUST-VIOLATED", "READING-DEPENDENT"}:
        return 1
    return 3 if seen & {"INCOMPLETE", "PARTIAL"} else 0


def _swept(args: argparse.Namespace, settings: Any) -> dict[str, Any] | None:
    """The sweep's summary (:func:`run_sweep` with the command's options); None when Ctrl-C
    stopped it, after saying that every finished configuration is kept."""
    from gather_verify.sweeps.sweep import run_sweep

    try:
        return run_sweep(settings, args.db, workers=args.workers, dask=args.dask,
                         progress=not args.json, limit=args.limit, fresh=args.fresh,
                         engine=args.engine)
    except KeyboardInterrupt:
        print(f"interrupted: every finished configuration is kept in {os.path.abspath(args.db)}; "
              "run the same command again to resume", file=sys.stderr)
        return None
