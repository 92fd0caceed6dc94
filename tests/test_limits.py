"""Limits bound every step: a state with very many events, many robots, a slow ``decide``,
a wide region. The clock is faked where time matters, so no assertion depends on the
machine's speed; subprocess timeouts only guard against a hang."""

from __future__ import annotations

import json
import random
import subprocess
import sys

import pytest

from gather_verify.engine import bfs as clock_module
from gather_verify.engine import explore as reference_module
from gather_verify.engine.encoding import Encoding, Limits
from gather_verify.model import geometry
from gather_verify.model.configuration import Configuration
from gather_verify.model.symmetry import Automorphism

CLI = [sys.executable, "-m", "gather_verify"]


def check(*args: str) -> tuple[int, dict]:
    run = subprocess.run([*CLI, "check", *args, "--json"], capture_output=True, text=True,
                         timeout=300)
    assert "Traceback" not in run.stderr, run.stderr
    return run.returncode, json.loads(run.stdout)


def test_128_robots_or_more_are_searched() -> None:
    """A round of 130 robots moves up to 130 of them: its weight fits no signed byte."""
    robots = " ".join(f"{i},0" for i in range(130))
    code, report = check("--robots", robots, "--meeting", "200,0", "--algorithm",
                         "go-to-target", "--scheduler", "fsync", "--max-states", "5")
    assert code == 3 and report["verdict"] == "INCOMPLETE" and report["reason"] == "states"


@pytest.mark.parametrize("scheduler", ["fsync", "ssync"])
def test_a_state_with_exponentially_many_events_stops_at_the_states_limit(scheduler: str) -> None:
    """16 robots with two closer steps each: 2^16 events in one FSYNC round (the reference
    engine runs it: so many robots' states fit no 63-bit key of the bulk engine)."""
    robots = " ".join(f"{i},{17 - i}" for i in range(1, 17))
    code, report = check("--robots", robots, "--meeting", "0,0", "--algorithm",
                         "go-to-target", "--scheduler", scheduler, "--max-states", "10")
    assert code == 3 and report["reason"] == "states"
    assert report["states"] <= 10 + 1024 + 16  # the grain: 1,024 events of one state


def test_a_finite_world_state_with_many_events_stops_at_the_states_limit() -> None:
    """The one reference search reads the states limit every 1,024 events of one state on
    every world: 12 luminous robots on ring:24, each with two steps, make 4,096 events in the
    first FSYNC round (a key past 63 bits: the reference engine runs it)."""
    from gather_verify.world_check import run_world_check

    report = run_world_check("ring:24", list(range(0, 24, 2)), [], "bounce", "fsync",
                             task="gathering", lights="2", colours=[1] * 12, reduction=False,
                             max_states=10)
    assert report["engine"] == "reference" and report["reason"] == "states"
    assert report["transitions"] == 1024 and report["states"] <= 10 + 1024


class FakeClock:
    """``time`` for one engine module: ``perf_counter`` moves only when told to."""

    def __init__(self) -> None:
        self.now = 0.0

    def perf_counter(self) -> float:
        return self.now


def test_the_reference_engine_reads_the_clock_at_every_state(monkeypatch) -> None:  # noqa: ANN001
    clock = FakeClock()
    monkeypatch.setattr(clock_module, "time", clock)

    from gather_verify.algorithms.go_to_target import GoToTarget

    class Tick(GoToTarget):
        name = "tick"

        def decide(self, view):  # noqa: ANN001, ANN201
            clock.now += 0.01  # as if many robots made every state costly
            return super().decide(view)

        def move_sets(self, *args):  # noqa: ANN002, ANN201
            return None  # ask decide view by view

    c = Configuration([(0, 0), (3, 1), (1, 4)], [(2, 2)], initial=True)
    e = reference_module.explore_reference(c, Tick(), "async", limits=Limits(max_seconds=1.0))
    assert e.stopped == "time" and e.states < 2184
    assert clock.now < 1.0 + 0.5  # one state's worth past the limit, not 1,024 states'


def test_a_wide_region_ends_with_its_limit() -> None:
    # (three robots 500 apart finish within the 2 s on a fast machine; four are still
    # running at 20 s, measured, so the limit ends this run on any machine)
    code, report = check("--robots", "0,0 500,0 250,3 120,2", "--meeting", "250,0",
                         "--algorithm", "go-to-target", "--max-seconds", "2")
    # the setup reads the clock; on a loaded machine the watchdog may stop it first (also time)
    assert code == 3 and report["reason"].split(" ")[0] == "time"


def test_symmetry_tables_built_in_bulk_equal_the_definition() -> None:
    rnd = random.Random(5)
    for _ in range(20):
        x0, y0 = rnd.randint(-5, 5), rnd.randint(-5, 5)
        box = (x0, y0, x0 + rnd.randint(0, 6), y0 + rnd.randint(0, 6))
        enc = Encoding(box)
        for g in geometry.ALL:
            a = Automorphism(g, (rnd.randint(-3, 3), rnd.randint(-3, 3)))
            table = enc._table(a)
            for code in range(enc.base):
                v, p = enc.robot(code)
                w = a(v)
                if enc.inside(w):
                    assert table[code] == enc.code(w, None if p is None else a(p))


def test_a_check_stops_once_every_requested_property_is_settled() -> None:
    """--property P: the search stops at P's first counterexample (the shortest trace, the
    same verdict); --keep-going searches the whole space, and the report never says that a
    property it stopped looking for holds."""
    from gather_verify.plane_check import SETTLED, run_check

    c = Configuration([(0, 0), (4, 0), (0, 4), (4, 4)], [(2, 2), (0, 1)], initial=True)
    kw = {"algorithm": "go-to-target", "scheduler": "async", "properties": ["no-ungatherable"],
          "force": True}
    early = run_check(c, keep_going=False, **kw)
    whole = run_check(c, keep_going=True, **kw)
    assert early["verdict"] == whole["verdict"] == "VIOLATED"
    assert early["trace"]["steps"] == whole["trace"]["steps"]
    assert early["states"] < whole["states"]
    assert all(r["holds"] is not True for r in early["properties"].values())
    assert SETTLED.startswith("not looked for")
