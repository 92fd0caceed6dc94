"""``check --json`` byte for byte: the report of every property, failing and holding, under
every scheduler, against stored digests (the scenarios check verdicts; this checks the
whole output: properties, reasons, limits, traces).

After a deliberate change of the output, regenerate (and say why in the commit):

    python tests/test_report_golden.py --write
"""

from __future__ import annotations

import hashlib
import io
import json
import sys
from contextlib import redirect_stdout
from pathlib import Path

import pytest

from gather_verify.cli import main

GOLDEN = Path(__file__).resolve().parent / "golden" / "check_json.json"
TWO = ["--robots", "0,0 3,1", "--meeting", "2,2"]
RUNS = {
    "broken-away": TWO,
    "broken-stay": TWO,
    "broken-undefined": TWO,
    "broken-drift": ["--robots", "1,2 3,2", "--meeting", "0,0 4,0 0,3"],
    "broken-wander": ["--robots", "0,2 2,2", "--meeting", "0,0 3,0 1,1 2,1", "--margin", "3"],
    "go-to-target": ["--robots", "0,0 3,1 1,4", "--meeting", "2,2"],
    "paper": ["--robots", "0,0 0,1 3,3", "--meeting", "1,2 2,1"],
}
OPTIONS = {
    "all": [],
    "tight": ["--move-bound-c", "0.5", "--property", "termination", "--property", "move-bound",
              "--property", "final"],
    "plain": ["--no-reduction"],
    "limited": ["--max-states", "40"],
    "live": ["--property", "termination", "--property", "no-ungatherable"],
}


def _cases() -> list[tuple[str, list[str]]]:
    return [(f"{algo}/{scheduler}/{opt}",
             ["check", *where, "--algorithm", algo, "--scheduler", scheduler, "--json",
              *OPTIONS[opt]])
            for algo, where in RUNS.items() for scheduler in ("fsync", "ssync", "async")
            for opt in OPTIONS]


def _run(argv: list[str]) -> dict[str, object]:
    argv = [*argv, "--max-seconds", "100"]
    out = io.StringIO()
    with redirect_stdout(out):
        code = main(argv)
    text = out.getvalue()
    report = json.loads(text)
    return {"exit": code, "verdict": report["verdict"], "property": report["property"],
            "sha256": hashlib.sha256(text.encode()).hexdigest()}


@pytest.mark.parametrize("name,argv", _cases(), ids=[n for n, _ in _cases()])
def test_check_json_is_unchanged(name: str, argv: list[str]) -> None:
    want = json.loads(GOLDEN.read_text())[name]
    assert _run(argv) == want, f"gather-verify {' '.join(argv)}: the --json output changed"


if __name__ == "__main__":
    if sys.argv[1:] != ["--write"]:
        sys.exit(__doc__)
    GOLDEN.write_text(json.dumps({name: _run(argv) for name, argv in _cases()}, indent=1) + "\n")
