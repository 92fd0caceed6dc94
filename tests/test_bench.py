"""``gather-verify bench --quick`` runs and prints every field (timings are never asserted);
the ring's Promela model (``bench/spin/make_ring_model.py``) has our state space."""

from __future__ import annotations

import json
import runpy
import shutil
import subprocess
import sys

import pytest

from gather_verify import bench
from gather_verify.world_check import run_world_check

RING_MODEL = runpy.run_path(str(bench.SPIN_DIR / "make_ring_model.py"))  # no __pycache__
needs_spin = pytest.mark.skipif(not (shutil.which("spin") and shutil.which("gcc")),
                                reason="spin and gcc are not installed (apt-get install spin gcc)")


@pytest.mark.slow  # the bench itself: the default run keeps the quick rows of each part
def test_bench_quick_prints_every_field():
    out = subprocess.run([sys.executable, "-m", "gather_verify", "bench", "--quick", "--no-spin"],
                         capture_output=True, text=True, check=True).stdout
    for field in ("states/s, whole process", "bytes per stored state", "SPIN (",
                  "time to verdict, reductions on", "verdict VERIFIED", "2,184", "7,032",
                  "ring instance ring:9", "SPIN (stored (ring-quick.json))",
                  "states/s, search only", "seconds, start-up", "the same space as SPIN's",
                  "225", "560"):
        assert field in out, out


def _ours(world: str, robots: list[int], meeting: int) -> tuple[int, int]:
    r = run_world_check(world, robots, [meeting], "go-to-target", "async", reduction=False)
    assert r["verdict"] == "VERIFIED"
    return r["states"], r["transitions"]


@pytest.mark.parametrize("world, robots, meeting", [
    ("ring:9", [0, 3, 5], 7),        # SEMANTICS.md §9: 225 states, 560 transitions
    ("ring:8", [4, 1, 6], 0),        # node 4 is opposite the meeting node: two closer steps
    ("ring:3", [1, 2], 0),
    ("ring:10", [5, 0, 4, 7], 2),    # a robot on the meeting node from the start
    ("ring:12", [6, 5, 7], 0),
])
def test_ring_closed_form_is_our_count(world, robots, meeting):
    n = int(world.split(":")[1])
    assert RING_MODEL["closed_form_counts"](n, robots, meeting) == _ours(world, robots, meeting)


def test_stored_ring_results_are_the_bench_instances():
    """The no-spin path: SPIN's stored numbers, labelled stored, for the instances the bench
    checks, and their counts are the closed form's (that is, ours)."""
    for instance, quick, name in ((bench.RING, False, "ring.json"),
                                  (bench.RING_QUICK, True, "ring-quick.json")):
        world, robots, meeting = instance
        stored = bench.spin_ring(instance, quick, run=False)
        assert stored is not None and stored["source"] == f"stored ({name})"
        assert stored["instance"] == {"world": world, "algorithm": "go-to-target",
                                      "scheduler": "ASYNC", "reductions": "none",
                                      "robots": robots, "meeting": meeting}
        n = int(world.split(":")[1])
        expected = RING_MODEL["closed_form_counts"](n, robots, meeting)
        assert (stored["states"], stored["edges"]) == expected
        assert stored["validated"] and stored["states_per_second"] > 0


def test_ring_bench_quick_json_without_spin():
    r = bench.ring_bench(quick=True, run_spin=False)
    assert r["ours"]["states"] == 225 and r["ours"]["transitions"] == 560
    assert r["spin"]["source"] == "stored (ring-quick.json)"
    assert r["same_space"] is True
    assert r["ratio_states_per_second"] > 0 and r["ratio_search_states_per_second"] > 0
    assert r["ratio_check_seconds"] > 0
    assert 0 < r["ours"]["check_seconds"] < r["ours"]["seconds"]
    assert r["ours"]["startup_seconds"] > r["ours"]["warm_seconds"] > 0
    json.dumps(r)


@needs_spin
def test_spin_ring_quick_measured_is_our_space():
    theirs = bench.spin_ring(bench.RING_QUICK, quick=True)
    assert theirs is not None and theirs["source"] == "measured"
    assert (theirs["states"], theirs["edges"]) == _ours(*bench.RING_QUICK) == (225, 560)
    assert theirs["transitions"] == theirs["edges"] + 1  # pan also counts the initial state


@needs_spin
@pytest.mark.parametrize("world, robots, meeting", [
    ("ring:8", [4, 1, 6], 0),
    ("ring:10", [5, 0, 4, 7], 2),
])
def test_spin_ring_model_states_equal_ours(world, robots, meeting):
    out = subprocess.run([sys.executable, str(bench.SPIN_DIR / "run_spin.py"), "--world", world,
                          "--robots", " ".join(map(str, robots)), "--meeting", str(meeting)],
                         capture_output=True, text=True, check=True)
    theirs = json.loads(out.stdout)
    assert theirs["validated"]
    assert (theirs["states"], theirs["edges"]) == _ours(world, robots, meeting)


def test_bench_schedulers_rows_quick():
    """``--scheduler`` runs the search under each round scheduler beside ASYNC on the quick
    instance and its 2-robot prefix: the state counts of SEMANTICS.md §4, and ratios."""
    out = subprocess.run([sys.executable, "-m", "gather_verify", "bench", "--quick", "--scheduler",
                          "ssync", "--scheduler", "fsync", "--schedulers-only", "--json"],
                         capture_output=True, text=True, check=True).stdout
    result = json.loads(out)
    rows = result["schedulers"]
    got = {(r["robots"], r["scheduler"]): r for r in rows}
    assert [(r["robots"], r["scheduler"]) for r in rows] == [
        (2, "async"), (2, "ssync"), (2, "fsync"), (3, "async"), (3, "ssync"), (3, "fsync")]
    assert [got[3, s]["states"] for s in ("async", "ssync", "fsync")] == [2184, 216, 18]
    assert got[3, "async"]["transitions"] == 7032
    assert got[3, "ssync"]["ratio_to_async"]["search_cpu"] > 0
    assert set(got[3, "async"]["ratio_to_async"].values()) == {1.0}
    # the text table of the same rows (the command prints it without --json; a second run of
    # the command would start four more measuring processes)
    # the union rows: one sweep per scheduler of the quick box, its union graphs' counts
    union = result["union"]
    assert [r["scheduler"] for r in union] == ["async", "ssync", "fsync"]
    assert len({r["configurations"] for r in union}) == 1
    assert all(r["graphs"] >= 1 and r["states"] > 0 and r["transitions"] > 0 for r in union)
    assert set(union[0]["ratio_to_async"].values()) == {1.0}
    assert min(union[1]["ratio_to_async"].values()) > 0
    lines: list[str] = []
    bench.format_bench({"schedulers": rows, "union": union}, lines.append)
    text = "\n".join(lines)
    assert "ratios: whole, CPU, search" in text and "ssync" in text and "fsync" in text
    assert "robots 0,0 3,1, meeting 2,2:" in text and "union engine, sweep of" in text


def test_bench_schedulers_only_needs_a_scheduler():
    out = subprocess.run([sys.executable, "-m", "gather_verify", "bench", "--schedulers-only"],
                         capture_output=True, text=True)
    assert out.returncode == 2 and "--schedulers-only needs --scheduler" in out.stderr
    assert "Traceback" not in out.stderr


LOADED = """
import json, sys
from gather_verify import bench, kernels
from gather_verify.kernels import compiled
kind, scheduler = sys.argv[1], sys.argv[2]
def loaded():
    return sorted(k for k in kernels.KERNELS if getattr(compiled, k).signatures)
kernels.warm(bench.RUN_KERNELS["rounds" if scheduler != "async" else kind])
print(json.dumps(loaded()))
robots, meeting = bench.QUICK
bench._child(kind, robots, meeting, 600.0, scheduler)
print(json.dumps(loaded()))
"""


def test_each_bench_child_loads_no_kernel_after_its_baseline():
    """A measurement's memory baseline is taken once :data:`bench.RUN_KERNELS` of its kind
    are loaded: its run loads no other kernel (that load would count per state). One fresh
    process per kind, run side by side."""
    runs = {(kind, scheduler): subprocess.Popen([sys.executable, "-c", LOADED, kind, scheduler],
                                                stdout=subprocess.PIPE, text=True)
            for kind, scheduler in [("explore", "async"), ("explore", "ssync"),
                                    ("verdict", "async"), ("full", "async")]}
    for (kind, scheduler), process in runs.items():
        out, _ = process.communicate()
        assert process.returncode == 0
        warmed, after = map(json.loads, out.splitlines())
        if not after:
            pytest.skip("the compiled kernels are off (numba missing, or GATHER_VERIFY_KERNELS)")
        assert after == warmed, (kind, scheduler, sorted(set(after) - set(warmed)))


def test_warm_loads_the_named_kernels_and_their_inputs_makers():
    code = ("import json\n"
            "from gather_verify import kernels\n"
            "from gather_verify.kernels import compiled\n"
            "kernels.warm(['pair_keys'])\n"
            "print(json.dumps(sorted(k for k in kernels.KERNELS\n"
            "                        if getattr(compiled, k).signatures)))")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         check=True).stdout
    from gather_verify import kernels

    if kernels.enabled():
        assert json.loads(out) == ["async_successors", "decode_chunk", "pair_keys"]
    with pytest.raises(ValueError, match="no kernel named nope"):
        kernels.warm(["nope"])
