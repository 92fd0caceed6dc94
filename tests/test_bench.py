"""``gather-verify bench --quick`` runs and prints every field (timings are never asserted)."""

from __future__ import annotations

import subprocess
import sys


def test_bench_quick_prints_every_field():
    out = subprocess.run([sys.executable, "-m", "gather_verify", "bench", "--quick", "--no-spin"],
                         capture_output=True, text=True, check=True).stdout
    for field in ("states/s, whole process", "bytes per stored state", "SPIN (",
                  "time to verdict, reductions on", "verdict VERIFIED", "2,184", "7,032"):
        assert field in out, out
