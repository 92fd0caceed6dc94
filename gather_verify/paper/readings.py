"""Readings: every defensible reading of the paper's ambiguous passages, and robustness.

SEMANTICS.md §8: a counterexample is a fault of the paper only when it fails
under every defensible reading of the passages it goes through. Each reading is
an option of ``paper`` (:data:`gather_verify.paper.algorithm.READINGS`,
``docs/interpretations.md``); ``--readings all`` on ``check`` and ``sweep`` runs
the configuration under every combination of them that can act on it, and the
verdicts give its *robustness*:

- ``ROBUST-VIOLATED``: every reading run refutes a claim of the paper;
- ``ROBUST-VERIFIED``: no reading run refutes one;
- ``READING-DEPENDENT``: some reading refutes one and another refutes none;
- ``INCOMPLETE``: some reading's run is undecided and the others all agree (never robust
  on fewer readings than claimed); ``NOT-APPLICABLE``: the configuration is in U or
  UNCLASSIFIED (no reading applies the algorithm).

What refutes a claim (:func:`fault`): a safety violation (``defined``,
``target-invariance``, ``no-ungatherable``), a run that never gathers (``final``,
``termination``: a deadlock or a fair livelock), any other property asked for, or an
infinite run (``move-bound`` by a cycle with moves). A finite run over ``c·D·n`` does not:
the paper claims O(Dn) moves, with no constant, and ``c`` is the project's. Such a run
is reported *over the project's constant*, beside the robustness, never as a fault.

The covering set. ``M`` never changes during a run, and which options
:func:`gather_verify.paper.algorithm.analyse` can read depends on ``M`` alone
(:func:`relevant_options`): ``alpha`` only when ``M`` is asymmetric or has a single
reflection with a meeting node on ``L`` (I11, I12: the orderings ``O`` and ``O'``);
none when a meeting node is on the centre ``c`` (I13); otherwise every option but
``alpha``, and of those ``metric`` and ``unclassified`` only when ``M`` has a rotation
(``metric`` changes the distance to ``c`` only: the distance to a line ``L`` is
``d(v, phi(v))``/2 in every metric, and ``unclassified`` is about a rotational ``M``).
The readings of a configuration are the product of the values of the options its ``M``
can read (the others at their first value: the same runs); options are varied as a
product, never one at a time, because they interact: finding F9 disappears only under
``oscan=guard`` *and* ``finalize=target`` together.

``check --readings`` and ``sweep --readings`` run fewer (:func:`check_readings`, the
dynamic covering; a sweep runs it per configuration, :func:`verify_readings_one`): the
plans (and the robots, for ``movement``) read every option through a recording
:class:`~gather_verify.paper.algorithm.Reading`, so after a run the instance knows every
option its plans and moves consulted; a reading that agrees with the run on those options
computes the same plan on every snapshot the run planned and the same moves, hence
explores the same graph in the same order to the same verdict, and the run stands for
it. The next run is the first reading not yet stood for. ``tests/test_readings.py``
checks both claims on random snapshots, compares the dynamic covering with the full
product, and fails when either claim is broken on purpose.

>>> varied = parse_readings("all")
>>> [len(v) for v in varied.values()]
[2, 2, 2, 4, 2, 2, 2, 3, 2, 2]
>>> from gather_verify.model.configuration import Configuration
>>> i22 = Configuration([(0, 0), (2, 3)], [(3, 0), (3, 1)])
>>> len(covering(varied, i22))  # every option but alpha: 2*2*4*2*2 * 2*3*2*2
1536
>>> [r.split(",")[0] for r in covering(varied, Configuration([(0, 0)], [(0, 0), (1, 0), (3, 1)]))]
['paper:alpha=mer', 'paper:alpha=mer_f']
>>> robustness(["VIOLATED", "VERIFIED"]), robustness(["VIOLATED", "INCOMPLETE"])
('READING-DEPENDENT', 'INCOMPLETE')
"""

from __future__ import annotations

import itertools
from collections.abc import Callable, Iterable, Sequence
from typing import Any

from gather_verify.algorithms import parse_name
from gather_verify.errors import InvalidInput
from gather_verify.model.configuration import Configuration
from gather_verify.model.symmetry import meeting_automorphisms
from gather_verify.paper.algorithm import READINGS, PaperAlgorithm

ROBUSTNESS = ("ROBUST-VIOLATED", "READING-DEPENDENT", "ROBUST-VERIFIED", "INCOMPLETE",
              "NOT-APPLICABLE")
ROBUSTNESS_EXIT = {"ROBUST-VERIFIED": 0, "ROBUST-VIOLATED": 1, "READING-DEPENDENT": 1,
                   "INCOMPLETE": 3, "NOT-APPLICABLE": 4}
"""Exit codes of ``check --readings``: 1 as soon as some reading refutes a claim."""
OVER = "OVER-CONSTANT"
"""The column of a robustness table that counts, beside the robustness, the configurations
with a finite run over ``c·D·n`` under some reading: over the project's constant, which
no claim of the paper states (it claims O(Dn) moves)."""

M_TYPES = ("I1-ordered", "I13", "reflection", "rotation")
"""What ``M`` alone decides about a run: see :func:`m_type`."""
CLASS_M_TYPE = {"I11": "I1-ordered", "I12": "I1-ordered", "I13": "I13", "I21": "reflection",
                "I31": "reflection", "I41": "reflection", "I22": "rotation", "I32": "rotation",
                "I42": "rotation", "UNCLASSIFIED": "rotation"}
"""The ``M`` type of every class (the classes are defined by the symmetry of ``M`` first)."""

_READ: dict[str, tuple[str, ...]] = {
    "I1-ordered": ("alpha",),
    "I13": (),
    "reflection": ("oscan", "finalize", "outside", "placement", "survivor", "hidden",
                   "movement"),
    "rotation": ("metric", "oscan", "finalize", "outside", "unclassified", "placement",
                 "survivor", "hidden", "movement"),
}


def m_type(c: Configuration) -> str:
    """``I1-ordered`` (M asymmetric, or one reflection with a meeting node on L),
    ``I13`` (a rotation with a meeting node on c), ``reflection`` / ``rotation`` (no
    meeting node on L / c): the branch of ``analyse`` every snapshot of a run takes."""
    aut_m = meeting_automorphisms(c)[1:]
    if not aut_m:
        return "I1-ordered"
    rotations = [a for a in aut_m if a.kind == "rotation"]
    symmetry = rotations[0] if rotations else aut_m[0]
    on = any(symmetry.fixes(m) for m in c.meeting_nodes)
    if rotations:
        return "I13" if on else "rotation"
    return "I1-ordered" if on else "reflection"


def relevant_options(c: Configuration) -> tuple[str, ...]:
    """The options of ``paper`` that the plans of a run from ``c`` read."""
    return _READ[m_type(c)]


def parse_readings(text: str, base: str = "paper") -> dict[str, tuple[str, ...]]:
    """The values of every option to run, from ``--readings``: ``all`` (every value of
    every option), or a comma list of ``OPTION`` (all its values) and
    ``OPTION=V1|V2`` items; an option not named keeps the base algorithm's value. The
    base's own value comes first, so the first reading is the base algorithm.

    >>> parse_readings("oscan,finalize=target|closest", "paper:alpha=mer_f")["finalize"]
    ('closest', 'target')
    >>> parse_readings("oscan", "paper:alpha=mer_f")["alpha"]
    ('mer_f',)
    """
    name, fixed = parse_name(base)
    if name != "paper":
        raise InvalidInput(f"--readings needs the algorithm paper (its options are the "
                         f"readings), not {name!r}")
    for option, value in fixed.items():
        if option not in READINGS or value not in READINGS[option]:
            raise InvalidInput(f"bad option {option}={value!r} of paper")
    base_value = {o: fixed.get(o, values[0]) for o, values in READINGS.items()}
    varied: dict[str, tuple[str, ...]] = {o: (v,) for o, v in base_value.items()}
    items = list(READINGS) if text.strip() == "all" else [i.strip() for i in text.split(",")]
    if not any(items):
        raise InvalidInput("--readings: give 'all' or a comma list of OPTION or OPTION=V1|V2")
    for item in items:
        option, eq, values = item.partition("=")
        if option not in READINGS:
            raise InvalidInput(f"--readings: unknown option {option!r}: use all or one of "
                             f"{', '.join(READINGS)}")
        chosen = tuple(v.strip() for v in values.split("|")) if eq else READINGS[option]
        bad = [v for v in chosen if v not in READINGS[option]]
        if bad or not chosen:
            raise InvalidInput(f"--readings: bad value {bad[0] if bad else ''!r} for {option}: "
                             f"use {'|'.join(READINGS[option])}")
        ordered = sorted(set(chosen), key=lambda v: (v != base_value[option],
                                                     READINGS[option].index(v)))
        varied[option] = tuple(ordered)
    return varied


def reading_name(values: dict[str, str]) -> str:
    """The algorithm name of one reading, every option spelt out."""
    return "paper:" + ",".join(f"{o}={values[o]}" for o in READINGS)


def covering_for(varied: dict[str, tuple[str, ...]], kind: str) -> list[str]:
    """The readings to run for an ``M`` of type ``kind``: the product of the values of
    the options read there; the other options at their first value (same runs)."""
    read = _READ[kind]
    axes = [varied[o] if o in read else varied[o][:1] for o in READINGS]
    return [reading_name(dict(zip(READINGS, combo, strict=True)))
            for combo in itertools.product(*axes)]


def covering(varied: dict[str, tuple[str, ...]], c: Configuration) -> list[str]:
    """:func:`covering_for` the type of ``c``'s meeting nodes."""
    return covering_for(varied, m_type(c))


def fault(report: dict[str, Any]) -> tuple[str, dict[str, Any] | None]:
    """What one run says of the paper's claims, and its finite run over the project's
    constant if it has one.

    The first is ``VIOLATED`` when a property other than ``move-bound`` fails, or
    ``move-bound`` does by an infinite run (a cycle with moves); ``VERIFIED`` when every
    other property holds, whether or not a finite run goes over ``c·D·n``; ``INCOMPLETE``
    when one is undecided (a limit, or a search stopped by its region after a finite run
    over the bound); ``NOT-APPLICABLE`` as the check says. The second, for a finite run
    over ``c·D·n``: ``{"moves": the moves of that run (None when another property's trace
    is the one shown), "bound": c·D·n}``.

    >>> over = {"verdict": "VIOLATED", "property": "move-bound", "max_moves": None,
    ...         "max_moves_infinite": False, "bound": 32.0,
    ...         "trace": {"detail": {"moves": 33}},
    ...         "properties": {"move-bound": {"holds": False}, "final": {"holds": None}}}
    >>> fault(over)
    ('INCOMPLETE', {'moves': 33, 'bound': 32.0})
    >>> over["properties"]["final"]["holds"] = True
    >>> fault(over)[0], fault({**over, "max_moves_infinite": True})
    ('VERIFIED', ('VIOLATED', None))
    """
    verdict = report["verdict"]
    if verdict in ("NOT-APPLICABLE", "VERIFIED"):
        return verdict, None
    properties = report.get("properties") or {}
    bound = properties.get("move-bound") or {}
    finite = bound.get("holds") is False and not report.get("max_moves_infinite")
    over = None
    if finite:
        moves = report.get("max_moves")
        if moves is None and report.get("property") == "move-bound":
            moves = ((report.get("trace") or {}).get("detail") or {}).get("moves")
        over = {"moves": moves, "bound": report.get("bound")}
    others = [r.get("holds") for name, r in properties.items()
              if not (finite and name == "move-bound")]
    if False in others or (verdict == "VIOLATED" and not finite):
        return "VIOLATED", over
    if verdict == "INCOMPLETE" or None in others:
        return "INCOMPLETE", over
    return "VERIFIED", over


def robustness(verdicts: Iterable[str]) -> str:
    """The robustness of one configuration from what its runs say of the claims
    (:func:`fault`) under the readings run."""
    seen = set(verdicts)
    if not seen or seen == {"NOT-APPLICABLE"}:
        return "NOT-APPLICABLE"
    if {"VIOLATED", "VERIFIED"} <= seen:
        return "READING-DEPENDENT"
    if seen == {"VIOLATED"}:
        return "ROBUST-VIOLATED"
    if seen == {"VERIFIED"}:
        return "ROBUST-VERIFIED"
    return "INCOMPLETE"


def _values(spec: str) -> dict[str, str]:
    """The option values of a reading's name (:func:`reading_name`)."""
    return parse_name(spec)[1]


def check_readings(configuration: Configuration, readings: str, *, algorithm: str = "paper",
                   run: Callable[..., dict[str, Any]] | None = None, dynamic: bool = True,
                   **check: Any) -> dict[str, Any]:
    """``run_check`` under every reading of the covering set; the first reading's report
    (the base algorithm's when its values are listed) with ``readings`` (one entry per
    reading of the covering set, with the ``run`` that stands for it and the run's
    ``fault``), ``runs`` (each with its ``fault`` and, for a finite run over ``c·D·n``,
    ``over``: :func:`fault`), ``robustness`` (from the faults), ``over_constant`` (the runs
    over the project's constant, the readings they stand for and their largest run; None
    when there is none) and ``readings_not_read`` (options the plans of this ``M`` never
    read).

    ``dynamic`` (the default): a run stands for every reading that agrees with it on the
    options its plans and moves consulted (:class:`~gather_verify.paper.algorithm.Reading`):
    those readings compute the same plan on every snapshot the run planned and the same
    moves, so they explore
    the same graph, in the same order, and reach the same verdict. The next run is the
    first reading no run stands for yet. ``dynamic=False`` runs every reading."""
    if run is None:
        from gather_verify.plane_check import run_check as run
    varied = parse_readings(readings, algorithm)
    specs = covering(varied, configuration)
    pending = [_values(spec) for spec in specs]
    stands: dict[str, tuple[str, dict[str, Any]]] = {}  # reading -> (run, its report)
    runs: list[dict[str, Any]] = []
    while pending:
        values = pending[0]
        spec = reading_name(values)
        instance = PaperAlgorithm(**values)
        instance.name = spec
        report = run(configuration, algorithm=instance, **check)
        consulted = sorted(instance.consulted) if dynamic else list(READINGS)
        covered = [r for r in pending if all(r[o] == values[o] for o in consulted)]
        pending = [r for r in pending if r not in covered]
        claims, over = fault(report)  # a run that refutes a claim: its over is by the way
        runs.append({"algorithm": spec, "verdict": report["verdict"],
                     "property": report["property"], "fault": claims,
                     **({"over": over} if over and claims != "VIOLATED" else {}),
                     "consulted": consulted,
                     "readings": len(covered), "report": report})
        for r in covered:
            stands[reading_name(r)] = (spec, runs[-1])
    out = dict(runs[0]["report"])
    out["readings"] = [{"algorithm": spec, "verdict": stands[spec][1]["verdict"],
                        "property": stands[spec][1]["property"],
                        "fault": stands[spec][1]["fault"], "run": stands[spec][0]}
                       for spec in specs]
    out["runs"] = [{k: v for k, v in r.items() if k != "report"} for r in runs]
    out["robustness"] = robustness(r["fault"] for r in runs)
    out["over_constant"] = over_constant(out["runs"])
    read = relevant_options(configuration)
    out["readings_not_read"] = {o: list(varied[o]) for o in READINGS
                                if o not in read and len(varied[o]) > 1}
    return out


def over_constant(runs: Iterable[dict[str, Any]]) -> dict[str, Any] | None:
    """The runs of a :func:`check_readings` report that refute no claim but go over
    ``c·D·n`` by a finite run: how many runs, the readings they stand for, the most moves
    such a run shows and the bound; None when there is none."""
    over = [r for r in runs if r.get("over")]
    if not over:
        return None
    moves = [r["over"]["moves"] for r in over if r["over"]["moves"] is not None]
    return {"runs": len(over), "readings": sum(r["readings"] for r in over),
            "moves": max(moves) if moves else None, "bound": over[0]["over"]["bound"]}


def _over_text(over: dict[str, Any]) -> str:
    moves = "a finite run" if over["moves"] is None else f"a finite run of {over['moves']} moves"
    return (f"{moves} over c·D·n = {over['bound']:g}: over the project's constant, not a "
            "fault of an O(Dn) claim")


def format_readings(report: dict[str, Any], write: Callable[[str], Any] = print) -> None:
    """The runs, the readings each stands for, and the robustness of a
    :func:`check_readings` report."""
    runs = report["runs"]
    write(f"readings ({len(runs)} run{'s' if len(runs) != 1 else ''} for "
          f"{len(report['readings'])} reading{'s' if len(report['readings']) != 1 else ''}):")
    for r in runs:
        write(f"  {r['verdict']:15} {r['property'] or '-':18} {r['algorithm']}")
        if r.get("over"):
            write(f"  {'':15} {'':18} {_over_text(r['over'])}; the other claims: "
                  + {"VERIFIED": "hold", "INCOMPLETE": "undecided"}.get(r["fault"], r["fault"]))
        if r["readings"] > 1:
            read = ", ".join(r["consulted"]) or "none"
            write(f"  {'':15} {'':18} stands for {r['readings']} readings (options read: "
                  f"{read})")
    if report["readings_not_read"]:
        fixed = "; ".join(f"{o}={values[0]} stands for {'|'.join(values)}"
                          for o, values in report["readings_not_read"].items())
        write(f"  not read by the algorithm on this M: {fixed}")
    over = report.get("over_constant")
    if over:
        write(f"over the project's constant: {over['runs']} run(s) for {over['readings']} "
              f"reading(s), {_over_text(over)}")
    write(f"robustness: {report['robustness']}")


# -- sweeps -------------------------------------------------------------------------


def single_switches(report: dict[str, Any]) -> dict[str, list[str]]:
    """The readings of a :func:`check_readings` report that differ from the base (its first
    reading) in exactly one option and reach the other verdict on the claims (``fault``):
    ``removed_by`` (VERIFIED where the base is VIOLATED) or ``broken_by`` (VIOLATED where
    the base is VERIFIED), each as ``option=value``; ``combinations``: true when the
    configuration is READING-DEPENDENT and no single switch changes the base's verdict."""
    readings = [(_values(r["algorithm"]), r["fault"]) for r in report["readings"]]
    (base, verdict), rest = readings[0], readings[1:]
    goal = {"VIOLATED": "VERIFIED", "VERIFIED": "VIOLATED"}.get(verdict)
    switches = []
    for values, other in rest:
        changed = [o for o in READINGS if values[o] != base[o]]
        if len(changed) == 1 and other == goal:
            switches.append(f"{changed[0]}={values[changed[0]]}")
    key = "removed_by" if verdict == "VIOLATED" else "broken_by"
    return {key: switches,
            "combinations": [] if switches or report["robustness"] != "READING-DEPENDENT"
            else ["only combinations"]}


def verify_readings_one(settings: Any, index: int, c: Configuration) -> dict[str, Any]:
    """One row of a readings sweep: the configuration under every reading of its covering
    set (:func:`check_readings`, the dynamic covering), with the sweep's own check settings.
    ``verdict`` holds the robustness, ``property`` and ``cause`` the base reading's, and
    ``trace`` the evidence: every run with the options it read, the readings it stands for
    and what it says of the claims, the single switches that change the base's verdict,
    and ``over_constant`` (:func:`over_constant`). ``failing``: the properties of the runs
    that refute a claim."""
    import time

    from gather_verify.sweeps.sweep import configuration_key

    started = time.perf_counter()
    report = check_readings(
        c, settings.extra["spec"], algorithm=settings.algorithm, scheduler=settings.scheduler,
        detection=settings.detection, frames=settings.frames,
        properties=settings.properties or None, reduction=settings.reduction,
        max_states=settings.max_states, max_seconds=settings.max_seconds,
        move_bound_c=settings.move_bound_c, max_memory_mb=settings.max_memory_mb,
        keep_growing=settings.keep_growing)  # memo off: every run plans its own snapshots
    switches = single_switches(report)
    failing = sorted({r["property"] for r in report["runs"] if r["fault"] == "VIOLATED"})
    return {
        "key": configuration_key(c), "index": index,
        "robots": [list(r) for r in c.robots],
        "meeting_nodes": sorted(list(m) for m in c.meeting_nodes),
        "class": report["class"], "verdict": report["robustness"], "n": len(c.robots),
        "property": report.get("property"), "cause": report.get("cause"),
        "reason": f"{len(report['runs'])} runs for {len(report['readings'])} readings",
        "trace": {"runs": report["runs"], **switches,
                  "over_constant": report["over_constant"]}, "failing": failing,
        "seconds": time.perf_counter() - started,
    }


def robustness_table(groups: Sequence[tuple[dict[str, Any], list[dict[str, Any]]]]
                     ) -> dict[str, dict[str, int]]:
    """Class x robustness over the stored sweeps of one readings group: the base reading's
    ordinary sweep (``covering`` absent) and the robustness rows of
    :func:`verify_readings_one` (``covering: dynamic``). A configuration counts once: by its
    robustness row; ``NOT-APPLICABLE`` where the base says so; ``DEFAULT-ONLY`` where only
    the base ran (``--readings-on violated`` examines only what the base violates);
    ``PARTIAL`` where an interrupted sweep has not examined it yet. Beside them, not in the
    count, :data:`OVER`: the examined configurations with a reading whose finite run goes
    over ``c·D·n`` (:func:`over_constant`). A sweep stored with one stored sweep per
    reading (``covering`` absent on every sweep of the group) is counted the old way: by
    the verdicts of every reading its ``M`` type needs."""
    if not any(s["extra"].get("covering") == "dynamic" for s, _ in groups):
        return _static_table(groups)
    base: dict[str, dict[str, Any]] = {}
    robust: dict[str, dict[str, Any]] = {}
    on = "all"
    for settings, rows in groups:
        target = robust if settings["extra"].get("covering") == "dynamic" else base
        on = settings["extra"].get("on", on)
        for row in rows:
            target[row["key"]] = row
    table: dict[str, dict[str, int]] = {}
    for key, row in base.items():
        by = table.setdefault(row["class"], {})
        if key in robust:
            label = robust[key]["verdict"]
            if (robust[key].get("trace") or {}).get("over_constant"):
                by[OVER] = by.get(OVER, 0) + 1
        elif row["verdict"] == "NOT-APPLICABLE":
            label = "NOT-APPLICABLE"
        elif on == "violated" and row["verdict"] != "VIOLATED":
            label = "DEFAULT-ONLY"
        else:
            label = "PARTIAL"
        by[label] = by.get(label, 0) + 1
    return table


def switch_table(groups: Sequence[tuple[dict[str, Any], list[dict[str, Any]]]]
                 ) -> dict[str, dict[str, dict[str, int]]]:
    """Per class, over the READING-DEPENDENT rows of a dynamic readings group: how many
    configurations each single switch ``removes`` (violated by the base) or ``breaks``
    (verified by the base), and how many need two switches or more (``only combinations``).
    A configuration counts under every switch that changes its verdict."""
    out: dict[str, dict[str, dict[str, int]]] = {}
    for settings, rows in groups:
        if settings["extra"].get("covering") != "dynamic":
            continue
        for row in rows:
            evidence = row.get("trace") or {}
            if row["verdict"] != "READING-DEPENDENT":
                continue
            kind = "removed by" if "removed_by" in evidence else "broken by"
            for switch in evidence.get("removed_by", evidence.get("broken_by", [])) + \
                    evidence.get("combinations", []):
                by = out.setdefault(row["class"], {}).setdefault(kind, {})
                by[switch] = by.get(switch, 0) + 1
    return {name: {kind: dict(sorted(by.items(), key=lambda kv: (-kv[1], kv[0])))
                   for kind, by in sorted(kinds.items(), reverse=True)}
            for name, kinds in out.items()}


def _static_table(groups: Sequence[tuple[dict[str, Any], list[dict[str, Any]]]]
                  ) -> dict[str, dict[str, int]]:
    """:func:`robustness_table` of a group stored one sweep per reading."""
    needed: dict[str, set[str]] = {}  # M type -> readings it needs
    by_key: dict[str, dict[str, Any]] = {}
    for settings, rows in groups:
        for kind in settings["extra"]["types"]:
            needed.setdefault(kind, set()).add(settings["algorithm"])
        for row in rows:
            entry = by_key.setdefault(row["key"], {"class": row["class"], "verdicts": {}})
            entry["verdicts"][settings["algorithm"]] = row["verdict"]
    table: dict[str, dict[str, int]] = {}
    for entry in by_key.values():
        verdicts = entry["verdicts"]
        if set(verdicts.values()) == {"NOT-APPLICABLE"}:
            label = "NOT-APPLICABLE"
        else:
            label = robustness(verdicts.values())
            if not needed.get(CLASS_M_TYPE[entry["class"]], set()) <= set(verdicts) and \
                    label != "READING-DEPENDENT":  # that one is already true on a part
                label = "DEFAULT-ONLY" if len(verdicts) == 1 else "PARTIAL"
        by = table.setdefault(entry["class"], {})
        by[label] = by.get(label, 0) + 1
    return table


def format_robustness(table: dict[str, dict[str, int]], write: Callable[[str], Any] = print,
                      switches: dict[str, dict[str, dict[str, int]]] | None = None) -> None:
    """The class x robustness table as text, then the single switches of the
    READING-DEPENDENT configurations (:func:`switch_table`) when given."""
    from gather_verify.paper.classes import CLASS_NAMES

    columns = [c for c in (*ROBUSTNESS, "DEFAULT-ONLY", "PARTIAL", OVER)
               if c in ROBUSTNESS[:3] or any(c in by for by in table.values())]
    header = f"{'class':<13}{'count':>7}" + "".join(f"{c:>19}" for c in columns)
    write(header)
    write("-" * len(header))
    for name in CLASS_NAMES:
        by = table.get(name)
        if by:
            count = sum(k for c, k in by.items() if c != OVER)
            write(f"{name:<13}{count:>7}" + "".join(f"{by.get(c, 0):>19}" for c in columns))
    write("ROBUST-VIOLATED: every reading refutes a claim (a safety violation, a run that "
          "never gathers, an infinite run); a finite run over c·D·n refutes none")
    if OVER in columns:
        write(f"{OVER} (beside the count): a reading has a finite run over c·D·n, the "
              "project's constant (the paper claims O(Dn) moves)")
    if "DEFAULT-ONLY" in columns:
        write("DEFAULT-ONLY: not violated by the base reading, the other readings not run "
              "(--readings-on violated)")
    if switches:
        write("")
        write("READING-DEPENDENT: the single switches (one option off the base) that change "
              "the base's verdict; a configuration counts under each:")
        for name in CLASS_NAMES:
            for kind, by in switches.get(name, {}).items():
                write(f"  {name} {kind}: " + ", ".join(f"{s} {k}" for s, k in by.items()))


def readings_sweep(settings: Sequence[Any], readings: str, db_path: str, *, on: str = "all",
                   types: Sequence[str] = M_TYPES, **run: Any
                   ) -> tuple[dict[str, dict[str, int]], dict[str, dict[str, dict[str, int]]]]:
    """Sweep the base reading into ``db_path`` (an ordinary sweep), then every
    configuration it needs to examine under every reading of its covering set
    (:func:`verify_readings_one`, one stored robustness sweep per ``settings``): every
    configuration, or with ``on="violated"`` those the base reading violates; ``types``
    keeps only the configurations whose ``M`` is of those types (:data:`M_TYPES`). Both
    stored sweeps name the readings group in their ``extra``. Returns the class x
    robustness table and the switch table (:func:`robustness_table`, :func:`switch_table`)."""
    from dataclasses import replace

    from gather_verify.sweeps.store import Store
    from gather_verify.sweeps.sweep import configuration_key, run_sweep

    if on not in ("all", "violated"):
        raise InvalidInput(f"--readings-on {on!r}: use all or violated")
    algorithm = settings[0].algorithm
    parse_readings(readings, algorithm)  # bad options are reported before any work
    bad = [t for t in types if t not in M_TYPES]
    if bad or not types:
        raise InvalidInput(f"--readings-types: unknown M type {bad[0] if bad else ''!r}: use "
                         f"{', '.join(M_TYPES)}")
    only = sorted(set(types))
    group = f"{algorithm}|{readings}|on={on}" + ("" if len(only) == len(M_TYPES) else
                                                 f"|types={','.join(only)}")
    extra = {"readings": group, "types": only, "on": on}
    base = [replace(s, extra={**s.extra, **extra}) for s in settings]
    run_sweep(base, db_path, where=lambda one, c: m_type(c) in only, **run)
    store = Store(db_path)
    try:
        verdicts = {r["key"]: r["verdict"] for s in base
                    for r in store.results(store.sweep_id(s.key()))}
    finally:
        store.close()

    def where(one: Any, c: Configuration) -> bool:
        verdict = verdicts.get(configuration_key(c))
        return verdict is not None and verdict != "NOT-APPLICABLE" and (
            on == "all" or verdict == "VIOLATED")

    examine = [replace(s, extra={**s.extra, "covering": "dynamic", "spec": readings})
               for s in base]
    run_sweep(examine, db_path, where=where, verify=verify_readings_one, **run)
    tables = stored_robustness(db_path)[group]
    return tables["table"], tables["switches"]


def stored_robustness(db_path: str, algorithm: str | None = None) -> dict[str, dict[str, Any]]:
    """Per readings group stored in ``db_path`` (of the sweeps of ``algorithm``, when given):
    its class x robustness ``table`` and its ``switches`` (:func:`robustness_table`,
    :func:`switch_table`)."""
    from gather_verify.sweeps.store import Store, algorithm_matches

    store = Store(db_path, read_only=True)
    try:
        groups: dict[str, list[tuple[dict[str, Any], list[dict[str, Any]]]]] = {}
        for i, settings in store.sweeps():
            group = (settings.get("extra") or {}).get("readings")
            if group and algorithm_matches(settings.get("algorithm"), algorithm):
                groups.setdefault(group, []).append((settings, store.results(i)))
    finally:
        store.close()
    return {group: {"table": robustness_table(sweeps), "switches": switch_table(sweeps)}
            for group, sweeps in groups.items()}
