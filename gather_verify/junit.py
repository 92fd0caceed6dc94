"""JUnit XML output, so a CI server shows each checked configuration as a test case.

A VIOLATED verdict is a failure (the failing property in the message; the reason
and the trace as ASCII grids in the body), INCOMPLETE an error (the check did not finish), NOT-APPLICABLE
a skip, VERIFIED a pass.

>>> print(junit_xml("demo", [{"name": "c1", "verdict": "VERIFIED", "seconds": 0.5}]))
<?xml version="1.0" encoding="utf-8"?>
<testsuite name="demo" tests="1" failures="0" errors="0" skipped="0" time="0.500"><testcase classname="demo" name="c1" time="0.500" /></testsuite>
"""

from __future__ import annotations

from collections.abc import Iterable, Sequence
from pathlib import Path
from typing import Any
from xml.sax.saxutils import escape, quoteattr


def junit_xml(suite: str, cases: Iterable[dict[str, Any]]) -> str:
    """Cases are dicts with ``name``, ``verdict`` and optional ``property``,
    ``reason``, ``trace``, ``seconds``."""
    cases = list(cases)
    body, counts = [], {"failures": 0, "errors": 0, "skipped": 0}
    for case in cases:
        seconds = float(case.get("seconds") or 0.0)
        head = (f"<testcase classname={quoteattr(suite)} name={quoteattr(str(case['name']))} "
                f'time="{seconds:.3f}"')
        verdict = case["verdict"]
        detail = escape(failure_text(case))
        prop, reason = case.get("property"), case.get("reason")
        if verdict == "VERIFIED":
            body.append(head + " />")
        elif verdict == "VIOLATED":
            counts["failures"] += 1
            message = quoteattr(f"VIOLATED: {prop}")
            body.append(f"{head}><failure message={message}>{detail}</failure></testcase>")
        elif verdict == "NOT-APPLICABLE":
            counts["skipped"] += 1
            message = quoteattr(str(reason or verdict))
            body.append(f"{head}><skipped message={message} /></testcase>")
        else:
            counts["errors"] += 1
            message = quoteattr(f"{verdict}: {reason}")
            body.append(f"{head}><error message={message}>{detail}</error></testcase>")
    total = sum(float(c.get("seconds") or 0.0) for c in cases)
    return ('<?xml version="1.0" encoding="utf-8"?>\n'
            f'<testsuite name={quoteattr(suite)} tests="{len(cases)}" failures="{counts["failures"]}" '
            f'errors="{counts["errors"]}" skipped="{counts["skipped"]}" time="{total:.3f}">'
            + "".join(body) + "</testsuite>")


def failure_text(case: dict[str, Any]) -> str:
    """A failure's body as a person reads it: the property, the reason and the trace as ASCII
    grids (:func:`gather_verify.render.render_trace`).

    >>> print(failure_text({"property": "final", "reason": "deadlock", "trace": None}))
    property: final
    reason: deadlock
    (no trace)
    """
    from gather_verify.render import render_trace

    trace = case.get("trace")
    return (f"property: {case.get('property')}\nreason: {case.get('reason')}\n"
            + (render_trace(trace) if trace else "(no trace)"))


def write_junit(path: str, suite: str, cases: Iterable[dict[str, Any]]) -> None:
    Path(path).write_text(junit_xml(suite, cases) + "\n", encoding="utf-8")


def write_sweep_junit(db_path: str, settings: Sequence[Any], path: str) -> None:
    """One test case per configuration of the sweeps with these settings."""
    from gather_verify.sweeps.store import Store

    store = Store(db_path)
    try:
        rows = [r for one in settings for r in store.results(store.sweep_id(one.key()))]
    finally:
        store.close()
    suite = f"sweep.{settings[0].algorithm}.{settings[0].scheduler}"
    write_junit(path, suite, ({**r, "name": f"{r['class']} robots={r['robots']} meeting={r['meeting_nodes']}"}
                              for r in rows))
