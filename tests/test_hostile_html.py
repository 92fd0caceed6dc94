"""Escaping everywhere HTML is written: a hostile trace and a hostile results database put
markup into every text, key and number they hold, and Chromium must show it as text (no
injected element, no script run). Skips without a browser, as the other browser tests."""

from __future__ import annotations

import json
import sqlite3
from pathlib import Path
from typing import Any

import pytest

from gather_verify.errors import InvalidInput
from gather_verify.sweeps.report import write_html
from gather_verify.sweeps.sweep import SweepSettings, run_sweep
from gather_verify.viewer import write_viewer

ROOT = Path(__file__).resolve().parent.parent
STALE = ROOT / "scenarios/regressions/i22-defined-paper-alpha-mer-f-async-df2289d6.json"
PAYLOAD = "<img src=x onerror=\"window.__pwned=1\">'\"</script><b id=injected>"


def poison(value: Any, keys: bool = True) -> Any:
    """Every string of ``value`` prefixed with the payload (dict keys too, where the reader
    of the structure keeps unknown keys); numbers and lists of numbers left as they are."""
    if isinstance(value, str):
        return PAYLOAD + value
    if isinstance(value, list):
        return [poison(v, keys) for v in value]
    if isinstance(value, dict):
        return {k: poison(v, keys) for k, v in value.items()}
    return value


def untouched(web) -> None:
    """No element and no script of the payload ran or exists."""
    page = web.page
    assert page.evaluate("() => window.__pwned === undefined")
    assert page.query_selector("#injected") is None
    assert page.query_selector("img[src=x]") is None


def test_a_hostile_trace_shows_as_text_in_the_viewer(web, tmp_path):
    trace = json.loads(STALE.read_text())["trace"]
    for key in ("property", "reason", "algorithm", "cause"):  # detection, frames: validated
        trace[key] = PAYLOAD + str(trace.get(key) or "")
    trace["detail"] = {PAYLOAD: PAYLOAD, "x" + PAYLOAD: [PAYLOAD, 1]}
    trace["detail"]["drift"] = {"vector": [1, 0], "period": PAYLOAD, "start": PAYLOAD,
                                "periods_checked": PAYLOAD}
    path = tmp_path / "v.html"
    write_viewer(trace, str(path))
    web.page.goto(path.as_uri())
    for _ in range(len(trace["steps"]) + 1):
        untouched(web)
        web.page.keyboard.press("ArrowRight")
    assert PAYLOAD.split(" ")[0] in web.page.inner_text("#verdict")  # shown, as text


def test_a_hostile_database_shows_as_text_in_the_report(web, tmp_path):
    db = tmp_path / "r.sqlite"
    run_sweep([SweepSettings(robots=2, meeting=1, box=(2, 2), algorithm="broken-away",
                             scheduler="async", max_seconds=20)], str(db), workers=1,
              progress=False)
    con = sqlite3.connect(db)
    with con:
        for sweep, settings in con.execute("SELECT id, settings FROM sweeps").fetchall():
            s = json.loads(settings)
            s.update(scheduler=PAYLOAD, algorithm=PAYLOAD)
            con.execute("UPDATE sweeps SET settings = ? WHERE id = ?", (json.dumps(s), sweep))
        con.execute("UPDATE results SET class = ?, reason = ?, property = ?, cause = ?",
                    (PAYLOAD, PAYLOAD, PAYLOAD, PAYLOAD))
    con.close()
    out = tmp_path / "report.html"
    for column in ("max_moves", "ratio"):  # a number column holding text: refused, one line
        damaged = tmp_path / f"{column}.sqlite"
        damaged.write_bytes(db.read_bytes())
        with sqlite3.connect(damaged) as con:
            con.execute(f"UPDATE results SET {column} = ?", (PAYLOAD,))
        with pytest.raises(InvalidInput, match=f"{column} holds"):
            write_html(str(damaged), str(out))
    write_html(str(db), str(out))
    web.page.goto(out.as_uri())
    untouched(web)
    for link in web.page.query_selector_all("table.verdicts a")[:3]:
        link.click()
        untouched(web)
