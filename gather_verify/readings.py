"""Readings: every defensible reading of the paper's ambiguous passages, and robustness.

SEMANTICS.md §8: a counterexample is a fault of the paper only when it fails
under every defensible reading of the passages it goes through. Each reading is
an option of ``paper`` (:data:`gather_verify.algorithms.paper.READINGS`,
``docs/interpretations.md``); ``--readings all`` on ``check`` and ``sweep`` runs
the configuration under every combination of them that can act on it, and the
verdicts give its *robustness*:

- ``ROBUST-VIOLATED``: VIOLATED under every reading run;
- ``ROBUST-VERIFIED``: VERIFIED under every reading run;
- ``READING-DEPENDENT``: VIOLATED under some reading and VERIFIED under another;
- ``INCOMPLETE``: some reading INCOMPLETE and the others all agree (never robust on
  fewer readings than claimed); ``NOT-APPLICABLE``: the configuration is in U or
  UNCLASSIFIED (no reading applies the algorithm).

The covering set. ``M`` never changes during a run, and which options
:func:`gather_verify.algorithms.paper.analyse` can read depends on ``M`` alone
(:func:`relevant_options`): ``alpha`` only when ``M`` is asymmetric or has a single
reflection with a meeting node on ``L`` (I11, I12: the orderings ``O`` and ``O'``);
none when a meeting node is on the centre ``c`` (I13); otherwise every option but
``alpha``, and of those ``metric`` and ``unclassified`` only when ``M`` has a rotation
(``metric`` changes the distance to ``c`` only: the distance to a line ``L`` is
``d(v, phi(v))``/2 in every metric, and ``unclassified`` is about a rotational ``M``).
The readings of a configuration are the product of the values of the options its ``M``
can read (the others at their first value: the same runs); options are varied as a
product, never one at a time, because they interact: finding F9 disappears only under
``oscan=guard`` *and* ``finalize=target`` together. Sweeps run that static set.

``check --readings`` runs fewer (:func:`check_readings`, the dynamic covering): the
plans read every option through a recording :class:`~gather_verify.algorithms.paper.Reading`,
so after a run the instance knows every option its plans consulted; a reading that agrees
with the run on those options computes the same plan on every snapshot the run planned,
hence explores the same graph in the same order to the same verdict, and the run stands
for it. The next run is the first reading not yet stood for. ``tests/test_readings.py``
checks both claims on random snapshots, compares the dynamic covering with the full
product, and fails when either claim is broken on purpose.

>>> varied = parse_readings("all")
>>> [len(v) for v in varied.values()]
[2, 2, 2, 4, 2, 2, 2, 3, 2]
>>> from gather_verify.model.configuration import Configuration
>>> i22 = Configuration([(0, 0), (2, 3)], [(3, 0), (3, 1)])
>>> len(covering(varied, i22))  # every option but alpha: 2*2*4*2*2 * 2*3*2
768
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
from gather_verify.algorithms.paper import READINGS, PaperAlgorithm
from gather_verify.errors import InvalidInput
from gather_verify.model.configuration import Configuration
from gather_verify.model.symmetry import meeting_automorphisms

ROBUSTNESS = ("ROBUST-VIOLATED", "READING-DEPENDENT", "ROBUST-VERIFIED", "INCOMPLETE",
              "NOT-APPLICABLE")
ROBUSTNESS_EXIT = {"ROBUST-VERIFIED": 0, "ROBUST-VIOLATED": 1, "READING-DEPENDENT": 1,
                   "INCOMPLETE": 3, "NOT-APPLICABLE": 4}
"""Exit codes of ``check --readings``: 1 as soon as some reading violates."""

M_TYPES = ("I1-ordered", "I13", "reflection", "rotation")
"""What ``M`` alone decides about a run: see :func:`m_type`."""
CLASS_M_TYPE = {"I11": "I1-ordered", "I12": "I1-ordered", "I13": "I13", "I21": "reflection",
                "I31": "reflection", "I41": "reflection", "I22": "rotation", "I32": "rotation",
                "I42": "rotation", "UNCLASSIFIED": "rotation"}
"""The ``M`` type of every class (the classes are defined by the symmetry of ``M`` first)."""

_READ: dict[str, tuple[str, ...]] = {
    "I1-ordered": ("alpha",),
    "I13": (),
    "reflection": ("oscan", "finalize", "outside", "placement", "survivor", "hidden"),
    "rotation": ("metric", "oscan", "finalize", "outside", "unclassified", "placement",
                 "survivor", "hidden"),
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


def robustness(verdicts: Iterable[str]) -> str:
    """The robustness of one configuration from its verdicts under the readings run."""
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
    reading of the covering set, with the ``run`` that stands for it), ``runs``,
    ``robustness`` and ``readings_not_read`` (options the plans of this ``M`` never read).

    ``dynamic`` (the default): a run stands for every reading that agrees with it on the
    options its plans consulted (:class:`~gather_verify.algorithms.paper.Reading`): those
    readings compute the same plan on every snapshot the run planned, so they explore
    the same graph, in the same order, and reach the same verdict. The next run is the
    first reading no run stands for yet. ``dynamic=False`` runs every reading."""
    if run is None:
        from gather_verify.check import run_check as run
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
        runs.append({"algorithm": spec, "verdict": report["verdict"],
                     "property": report["property"], "consulted": consulted,
                     "readings": len(covered), "report": report})
        for r in covered:
            stands[reading_name(r)] = (spec, report)
    out = dict(runs[0]["report"])
    out["readings"] = [{"algorithm": spec, "verdict": stands[spec][1]["verdict"],
                        "property": stands[spec][1]["property"], "run": stands[spec][0]}
                       for spec in specs]
    out["runs"] = [{k: v for k, v in r.items() if k != "report"} for r in runs]
    out["robustness"] = robustness(r["verdict"] for r in runs)
    read = relevant_options(configuration)
    out["readings_not_read"] = {o: list(varied[o]) for o in READINGS
                                if o not in read and len(varied[o]) > 1}
    return out


def format_readings(report: dict[str, Any], write: Callable[[str], Any] = print) -> None:
    """The runs, the readings each stands for, and the robustness of a
    :func:`check_readings` report."""
    runs = report["runs"]
    write(f"readings ({len(runs)} run{'s' if len(runs) != 1 else ''} for "
          f"{len(report['readings'])} reading{'s' if len(report['readings']) != 1 else ''}):")
    for r in runs:
        write(f"  {r['verdict']:15} {r['property'] or '-':18} {r['algorithm']}")
        if r["readings"] > 1:
            read = ", ".join(r["consulted"]) or "none"
            write(f"  {'':15} {'':18} stands for {r['readings']} readings (options read: "
                  f"{read})")
    if report["readings_not_read"]:
        fixed = "; ".join(f"{o}={values[0]} stands for {'|'.join(values)}"
                          for o, values in report["readings_not_read"].items())
        write(f"  not read by the algorithm on this M: {fixed}")
    write(f"robustness: {report['robustness']}")


# -- sweeps -------------------------------------------------------------------------


def sweep_plan(varied: dict[str, tuple[str, ...]]) -> list[tuple[str, tuple[str, ...]]]:
    """Every reading to sweep with the ``M`` types it must run on (the covering set of each
    type), the base reading first."""
    kinds: dict[str, list[str]] = {}
    for kind in M_TYPES:
        for spec in covering_for(varied, kind):
            kinds.setdefault(spec, []).append(kind)
    return [(spec, tuple(k)) for spec, k in kinds.items()]


def robustness_table(groups: Sequence[tuple[dict[str, Any], list[dict[str, Any]]]]
                     ) -> dict[str, dict[str, int]]:
    """Class x robustness over the stored sweeps of one readings group (one sweep per
    reading and n, m): a configuration counts once, by the verdicts of every reading its
    ``M`` type needs; ``DEFAULT-ONLY`` when only the base reading ran on it (a sweep
    with ``--readings-on violated`` skips the configurations it verifies), ``PARTIAL``
    when an interrupted sweep left some reading out (``READING-DEPENDENT`` as soon as the
    readings run hold a VIOLATED and a VERIFIED one: more readings cannot undo that)."""
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


def format_robustness(table: dict[str, dict[str, int]], write: Callable[[str], Any] = print
                      ) -> None:
    """The class x robustness table as text."""
    from gather_verify.model.classes import CLASS_NAMES

    columns = [c for c in (*ROBUSTNESS, "DEFAULT-ONLY", "PARTIAL")
               if c in ROBUSTNESS[:3] or any(c in by for by in table.values())]
    header = f"{'class':<13}{'count':>7}" + "".join(f"{c:>19}" for c in columns)
    write(header)
    write("-" * len(header))
    for name in CLASS_NAMES:
        by = table.get(name)
        if by:
            write(f"{name:<13}{sum(by.values()):>7}" + "".join(f"{by.get(c, 0):>19}"
                                                             for c in columns))


def readings_sweep(settings: Sequence[Any], readings: str, db_path: str, *, on: str = "all",
                   types: Sequence[str] = M_TYPES, **run: Any) -> dict[str, dict[str, int]]:
    """Sweep every reading of the covering set (:func:`sweep_plan`) into ``db_path``, one
    stored sweep per reading and ``settings`` (their ``extra`` names the readings group
    and the ``M`` types the reading runs on); ``on="violated"`` runs the readings other
    than the base only on the configurations the base reading violates; ``types`` keeps
    only the configurations whose ``M`` is of those types (:data:`M_TYPES`). Returns
    the class x robustness table (:func:`robustness_table`)."""
    from dataclasses import replace

    from gather_verify.sweeps.store import Store
    from gather_verify.sweeps.sweep import configuration_key, run_sweep

    if on not in ("all", "violated"):
        raise InvalidInput(f"--readings-on {on!r}: use all or violated")
    algorithm = settings[0].algorithm
    varied = parse_readings(readings, algorithm)
    bad = [t for t in types if t not in M_TYPES]
    if bad or not types:
        raise InvalidInput(f"--readings-types: unknown M type {bad[0] if bad else ''!r}: use "
                         f"{', '.join(M_TYPES)}")
    only = sorted(set(types))
    group = f"{algorithm}|{readings}|on={on}" + ("" if len(only) == len(M_TYPES) else
                                                 f"|types={','.join(only)}")
    plan = [(spec, tuple(k for k in kinds if k in only)) for spec, kinds in sweep_plan(varied)]
    plan = [(spec, kinds) for spec, kinds in plan if kinds]

    def of(spec: str, kinds: tuple[str, ...]) -> list[Any]:
        return [replace(s, algorithm=spec, extra={**s.extra, "readings": group,
                                                  "types": list(kinds)}) for s in settings]

    (base, base_kinds), rest = plan[0], plan[1:]
    run_sweep(of(base, base_kinds), db_path, where=lambda one, c: m_type(c) in only, **run)
    violated: set[str] | None = None
    if on == "violated":
        store = Store(db_path)
        try:
            violated = {r["key"] for s in of(base, base_kinds)
                        for r in store.results(store.sweep_id(s.key()))
                        if r["verdict"] == "VIOLATED"}
        finally:
            store.close()

    def where(one: Any, c: Configuration) -> bool:
        return m_type(c) in one.extra["types"] and (
            violated is None or configuration_key(c) in violated)

    if rest:
        run_sweep([s for spec, kinds in rest for s in of(spec, kinds)], db_path, where=where,
                  **run)
    return stored_robustness(db_path)[group]


def stored_robustness(db_path: str) -> dict[str, dict[str, dict[str, int]]]:
    """The class x robustness table of every readings group stored in ``db_path``."""
    from gather_verify.sweeps.store import Store

    store = Store(db_path)
    try:
        groups: dict[str, list[tuple[dict[str, Any], list[dict[str, Any]]]]] = {}
        for i, settings in store.sweeps():
            group = (settings.get("extra") or {}).get("readings")
            if group:
                groups.setdefault(group, []).append((settings, store.results(i)))
    finally:
        store.close()
    return {group: robustness_table(sweeps) for group, sweeps in groups.items()}
