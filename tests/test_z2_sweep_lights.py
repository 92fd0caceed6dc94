"""A luminous sweep of the paper's world (``sweep --lights K [--initial-colours all]``): every
row equals ``run_check`` on its configuration and colouring, the colourings are one per class
under the configuration's symmetries (counted against an independent canonical form), every
colouring of a class has its representative's verdict, ``--lights 1`` rows are the oblivious
sweep's, ``broken-beacon`` is caught, and bad input is one line."""

from __future__ import annotations

from functools import partial
from itertools import product
from pathlib import Path
from typing import Any

import pytest

from gather_verify.cli import main
from gather_verify.model import geometry
from gather_verify.model.configuration import Configuration
from gather_verify.plane_check import run_check
from gather_verify.sweeps.census import enumerate_configurations
from gather_verify.sweeps.lit_census import verify_lit_one
from gather_verify.sweeps.store import Store
from gather_verify.sweeps.sweep import LIT_FALLBACK, SweepSettings, run_sweep

SMALL = {"robots": 2, "meeting": 2, "box": (3, 3), "scheduler": "async"}
"""``--robots 2 --meeting 2 --box 3x3 --scheduler async``."""


def sweep_rows(tmp_path: Path, verify: Any = None,
               **options: Any) -> tuple[dict, list[dict]]:
    """The summary and the stored rows of one sweep (one worker, this process)."""
    s = SweepSettings(**{**SMALL, **options})
    tmp_path.mkdir(parents=True, exist_ok=True)
    db = str(tmp_path / "results.sqlite")
    summary = run_sweep(s, db, workers=1, progress=False, verify=verify)
    store = Store(db)
    try:
        return summary, store.results(store.sweep_id(s.key()))
    finally:
        store.close()


def lit_canonical(robots: list[tuple[int, int]], colours: list[int],
                  meeting: list[tuple[int, int]]) -> tuple:
    """The least image of a coloured configuration under D4 and translation, computed here
    from the definition (not from the configuration's automorphisms)."""
    best = None
    for g in geometry.ALL:
        rs = [(geometry.apply(g, v), c) for v, c in zip(robots, colours, strict=True)]
        ms = [geometry.apply(g, v) for v in meeting]
        nodes = [v for v, _ in rs] + ms
        x0, y0 = min(x for x, _ in nodes), min(y for _, y in nodes)
        key = (tuple(sorted(((x - x0, y - y0), c) for (x, y), c in rs)),
               tuple(sorted((x - x0, y - y0) for x, y in ms)))
        best = key if best is None or key < best else best
    return best  # type: ignore[return-value]


def test_every_row_is_run_check_on_its_colouring_one_per_class(tmp_path: Path) -> None:
    summary, rows = sweep_rows(tmp_path, algorithm="beacon", lights="2", initial_colours="all")
    assert summary["engine_fallback"] == LIT_FALLBACK
    by_class: dict[tuple, dict] = {}
    for r in rows:
        robots = [tuple(v) for v, _ in r["robots"]]
        colours = [c for _, c in r["robots"]]
        meeting = [tuple(v) for v in r["meeting_nodes"]]
        c = Configuration(robots, meeting, initial=True)
        assert list(c.robots) == robots  # colours listed as the sorted robots
        report = run_check(c, algorithm="beacon", scheduler="async", lights="2",
                           colours=colours)
        for field in ("class", "verdict", "property", "reason", "states", "transitions",
                      "max_moves", "ratio", "trace"):
            assert r[field] == report[field], (r["key"], field)
        canonical = lit_canonical(robots, colours, meeting)
        assert canonical not in by_class, r["key"]  # two rows of one class
        by_class[canonical] = r
    # every colouring of every configuration is in a stored class, with its verdict
    every = 0
    for c in enumerate_configurations(2, 2, 3, 3):
        for colours in product(range(2), repeat=c.n):
            every += 1
            r = by_class[lit_canonical(list(c.robots), list(colours), sorted(c.meeting_nodes))]
            if r["robots"] == [[list(v), k] for v, k in zip(c.robots, colours, strict=True)]:
                continue  # the representative itself, checked above
            report = run_check(c, algorithm="beacon", scheduler="async", lights="2",
                               colours=list(colours))
            assert (report["verdict"], report["states"]) == (r["verdict"], r["states"])
    assert len(rows) < every  # symmetric configurations share colourings
    verdicts = {r["verdict"] for r in rows}
    assert {"VERIFIED", "VIOLATED"} <= verdicts  # a robot lit off a meeting node waits


@pytest.mark.parametrize(("n", "m", "scheduler"), [
    (2, 1, "ssync"), pytest.param(2, 2, "ssync", marks=pytest.mark.slow),
    pytest.param(3, 1, "async", marks=pytest.mark.slow)])
def test_lights_one_rows_are_the_oblivious_sweeps(n: int, m: int, scheduler: str,
                                                  tmp_path: Path) -> None:
    """Field by field, traces included: the reference engine's rows and the union's."""
    common = {"robots": n, "meeting": m, "algorithm": "go-to-target", "scheduler": scheduler}
    _, lit = sweep_rows(tmp_path / "lit", lights="1", **common)
    _, plain = sweep_rows(tmp_path / "plain", **common)
    assert len(lit) == len(plain) > 0
    assert any(r["verdict"] == "VIOLATED" for r in plain) or m == 1  # traces compared too
    for a, b in zip(lit, plain, strict=True):
        assert {k: v for k, v in a.items() if k != "seconds"} == \
               {k: v for k, v in b.items() if k != "seconds"}


BY_REFERENCE = partial(verify_lit_one, engine="reference")
"""A luminous sweep's rows, each checked by the reference engine."""


@pytest.mark.parametrize("options", [
    {"algorithm": "beacon", "lights": "2", "scheduler": "ssync"},
    {"algorithm": "broken-beacon", "lights": "2:external", "scheduler": "ssync"},
    pytest.param({"algorithm": "beacon", "lights": "2", "initial_colours": "all"},
                 marks=pytest.mark.slow),
    pytest.param({"algorithm": "bounce", "lights": "3", "scheduler": "fsync",
                  "initial_colours": "all", "max_states": 3000},  # bounce never gathers
                 marks=pytest.mark.slow),
    pytest.param({"algorithm": "beacon", "lights": "2", "robots": 3, "meeting": 1,
                  "scheduler": "centralized", "initial_colours": "all"},
                 marks=pytest.mark.slow),
    pytest.param({"algorithm": "broken-beacon", "lights": "2:internal", "robots": 3,
                  "scheduler": "async", "reduction": False, "max_states": 3000},
                 marks=pytest.mark.slow),
], ids=lambda o: "-".join(f"{v}" for v in o.values()))
def test_the_bulk_engines_rows_are_the_references(options: dict, tmp_path: Path) -> None:
    """Every stored row (traces included) of a luminous sweep, by the bulk engine (the
    default) and by the reference, field by field but the time."""
    summary, bulk = sweep_rows(tmp_path / "bulk", **options)
    _, ref = sweep_rows(tmp_path / "ref", verify=BY_REFERENCE, **options)
    assert summary["engine_fallback"] == LIT_FALLBACK and len(bulk) == len(ref) > 0
    for a, b in zip(bulk, ref, strict=True):
        assert {k: v for k, v in a.items() if k != "seconds"} == \
               {k: v for k, v in b.items() if k != "seconds"}, a["key"]


def test_beacon_verified_and_its_broken_twin_violated(tmp_path: Path) -> None:
    _, good = sweep_rows(tmp_path / "good", algorithm="beacon", lights="2")
    _, bad = sweep_rows(tmp_path / "bad", algorithm="broken-beacon", lights="2")
    assert [r["key"] for r in good] == [r["key"] for r in bad]
    assert {r["verdict"] for r in good if r["class"] == "I22"} == {"VERIFIED"}
    assert any(r["verdict"] == "VIOLATED" and r["property"] == "final" for r in bad)


def test_the_lights_are_in_the_stored_settings() -> None:
    plain = SweepSettings(**SMALL, algorithm="beacon")
    assert "lights" not in plain.key() and "initial_colours" not in plain.key()
    lit = SweepSettings(**SMALL, algorithm="beacon", lights="2", initial_colours="all")
    assert lit.key()["lights"] == "2" and lit.key()["initial_colours"] == "all"
    assert len({str(s.key()) for s in (plain, lit, SweepSettings(
        **SMALL, algorithm="beacon", lights="2"))}) == 3


def test_the_cli_sweeps_and_says_which_engine_ran(tmp_path: Path, capsys) -> None:  # noqa: ANN001
    args = ["sweep", "--robots", "2", "--meeting", "2", "--box", "3x3", "--algorithm",
            "beacon", "--lights", "2", "--scheduler", "async", "--workers", "1", "--db",
            str(tmp_path / "r.sqlite")]
    assert main(args) == 0  # every I22 configuration VERIFIED, the rest NOT-APPLICABLE
    assert "engine: the union engine encodes no lights" in capsys.readouterr().out


@pytest.mark.parametrize(("args", "words"), [
    (("--initial-colours", "all"), "needs --lights"),
    (("--lights", "0"), "number of colours"),
    (("--lights", "64", "--initial-colours", "all"), "colourings per configuration"),
    (("--lights", "2", "--readings", "all"), "give no --lights"),
    (("--lights", "2", "--task", "gathering"), "finite world"),
])
def test_bad_luminous_sweeps_are_one_line(args: tuple[str, ...], words: str, tmp_path: Path,
                                          capsys) -> None:  # noqa: ANN001
    assert main(["sweep", "--robots", "3", "--meeting", "1", "--box", "3x3", "--workers", "1",
                 "--db", str(tmp_path / "r.sqlite"), *args]) == 2
    err = capsys.readouterr().err
    assert words in err and len(err.strip().splitlines()) == 1, err
