"""Reports of stored sweeps: text tables, an HTML page, and a plot of moves against D·n."""

from __future__ import annotations

import html
import json
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from gather_verify.errors import InvalidInput
from gather_verify.sweeps.store import Store, algorithm_matches
from gather_verify.sweeps.sweep import summarise
from gather_verify.words import counted


def load_sweeps(db_path: str, algorithm: str | None = None
                ) -> list[tuple[dict[str, Any], list[dict[str, Any]]]]:
    """Every sweep in a results database with its rows (those of ``algorithm`` only, when
    given: :func:`~gather_verify.sweeps.store.algorithm_matches`)."""
    return [(settings, rows) for _, settings, rows, _ in _records(db_path, algorithm)]


def _records(db_path: str, algorithm: str | None = None
             ) -> list[tuple[int, dict[str, Any], list[dict[str, Any]], dict[str, Any] | None]]:
    """Every sweep (of ``algorithm``) as (id, settings, rows, when it was written: None for a
    sweep stored before that was kept)."""
    store = Store(db_path, read_only=True)
    try:
        written = store.written()
        return [(i, settings, store.results(i), written.get(i)) for i, settings in store.sweeps()
                if algorithm_matches(settings.get("algorithm"), algorithm)]
    finally:
        store.close()


def code_status(db_path: str, settings: dict[str, Any], written: dict[str, Any] | None,
                cache: dict[str, bool | None] | None = None) -> bool | None:
    """Whether the code and data on disk now give a stored sweep's fingerprint (its rows are
    the current code's), False when they do not, None when that cannot be told
    (:func:`gather_verify.fingerprint.disk_fingerprint`; for a sweep stored before its
    ``--fingerprint-extra`` files were kept, only a match can be told)."""
    from gather_verify.fingerprint import disk_fingerprint

    stored = settings.get("fingerprint")
    extra = None if written is None else written.get("fingerprint_extra")
    key = json.dumps([settings.get("algorithm"), settings.get("world"),
                      settings.get("properties"), extra, stored], sort_keys=True, default=str)
    if cache is not None and key in cache:
        return cache[key]
    folder = Path(db_path).resolve().parent
    now = disk_fingerprint(settings, extra or [], folder)
    status = None if now is None or not isinstance(stored, str) else now == stored
    if status is False and extra is None:
        status = None  # it may have read files we do not know of
    if cache is not None:
        cache[key] = status
    return status


def when(text: Any) -> str | None:
    """A stored UTC time as people read it, to the minute (None: not recorded).

    >>> when("2026-01-31T09:05:07Z"), when(None)
    ('2026-01-31 09:05 UTC', None)
    """
    if not isinstance(text, str) or len(text) < 16:
        return None
    return f"{text[:10]} {text[11:16]} UTC"


def code_text(status: bool | None) -> str:
    """What :func:`code_status` says, in words."""
    return {True: "current: the code on disk now", False: "older code: not the code on disk "
            "now"}.get(status, "cannot tell whether it is the code on disk now")  # type: ignore[arg-type]


def summaries(db_path: str, algorithm: str | None = None) -> list[dict[str, Any]]:
    """Every sweep's :func:`summarise`, with ``current`` (:func:`code_status`) and
    ``written`` (``first`` and ``last``: when its rows were written, UTC; wall-clock, so
    ``--json`` leaves it out unless ``--timings``)."""
    out = []
    cache: dict[str, bool | None] = {}
    for _, settings, rows, written in _records(db_path, algorithm):
        summary = summarise(rows)
        summary["settings"] = settings
        summary["current"] = code_status(db_path, settings, written, cache)
        summary["written"] = {"first": (written or {}).get("first"),
                              "last": (written or {}).get("last")}
        out.append(summary)
    return out


LIST_LIMIT = 1000
"""Configurations listed per table cell (the page of a 40,000-configuration sweep stays a
few megabytes); the list says how many it leaves out."""
BATCH_AXES = ("robots", "meeting")
"""Settings that vary inside one batch: ``sweep --robots 2-3 --meeting 2-4`` stores one sweep
per (n, m) with everything else equal, and the report shows them as one batch."""


@dataclass
class Batch:
    """The sweeps of one ``sweep`` command: their ``common`` settings, each sweep's settings
    and rows, when its rows were written (``first``, ``last``: UTC text, None when not
    recorded) and whether they are the current code's (:func:`code_status`)."""

    common: dict[str, Any]
    sweeps: list[tuple[dict[str, Any], list[dict[str, Any]]]] = field(default_factory=list)
    first: str | None = None
    last: str | None = None
    current: bool | None = None

    def describe(self) -> str:
        """``fingerprint 1a2b3c4d · written 2026-01-31 09:05 UTC · current: ...``"""
        fingerprint = self.common.get("fingerprint")
        parts = [f"fingerprint {str(fingerprint)[:8]}" if fingerprint else "no fingerprint",
                 f"written {when(self.last)}" if when(self.last) else
                 "written before dates were kept", code_text(self.current)]
        return " · ".join(parts)


def batch_list(db_path: str, algorithm: str | None = None) -> list[Batch]:
    """The sweeps of a database grouped into batches (:class:`Batch`), in the order of their
    first sweep."""
    groups: dict[str, Batch] = {}
    cache: dict[str, bool | None] = {}
    for _, settings, rows, written in _records(db_path, algorithm):
        common = {k: v for k, v in settings.items() if k not in BATCH_AXES}
        key = json.dumps(common, sort_keys=True)
        if key not in groups:
            groups[key] = Batch(common, current=code_status(db_path, common, written, cache))
        batch = groups[key]
        batch.sweeps.append((settings, rows))
        times = [t for t in ((written or {}).get("first"), (written or {}).get("last"))
                 if isinstance(t, str)]
        if times:
            batch.first = min([t for t in (batch.first, *times) if t is not None])
            batch.last = max([t for t in (batch.last, *times) if t is not None])
    return list(groups.values())


def batches(db_path: str, algorithm: str | None = None
            ) -> list[tuple[dict[str, Any], list[tuple[dict[str, Any], list[dict[str, Any]]]]]]:
    """The sweeps of a database grouped into batches: (common settings, [(settings, rows)])."""
    return [(b.common, b.sweeps) for b in batch_list(db_path, algorithm)]


def _esc(value: Any) -> str:
    return html.escape(str(value), quote=True)


def _number(value: Any) -> str:
    """A ratio as ``1.25``; anything a database holds that is no number, escaped as text."""
    try:
        return f"{float(value):.2f}"
    except (TypeError, ValueError):
        return _esc(value)


def _nodes(nodes: Any, lit: bool = False) -> str:
    """Nodes as the command line writes them: ``x,y`` on Z² and on grids and tori, a ring's
    number, a graph file's id; ``lit``: each is [node, colour] (a robot with its initial
    light), the node is written."""
    return " ".join(",".join(map(str, v)) if isinstance(v, list) else str(v)
                    for v in ((n[0] if lit and isinstance(n, list) else n) for n in nodes))


def _lit(common: dict[str, Any]) -> bool:
    """Whether a batch's rows store each robot with its initial colour (a sweep over every
    initial colouring)."""
    return common.get("initial_colours") == "all"


def _on_plane(common: dict[str, Any]) -> bool:
    """Whether the settings of a sweep name a world the Z² engines run (no world: the
    default, the paper's)."""
    from gather_verify.worlds import DEFAULT_WORLD, PLANE, entry_of

    world = common.get("world", DEFAULT_WORLD)
    return isinstance(world, str) and entry_of(world) == PLANE


def _recheck(r: dict[str, Any], verdict: str, common: dict[str, Any]) -> str:
    """The command that checks one stored configuration again (and writes its viewer when it
    fails)."""
    lit, plane = _lit(common), _on_plane(common)
    parts = ["gather-verify check"]
    if not plane:  # a finite world: a row's class is its world's name
        parts.append(f"--world {r['class']}")
    parts.append(f"--robots \"{_nodes(r['robots'], lit)}\"")
    if plane or r["meeting_nodes"]:
        parts.append(f"--meeting \"{_nodes(r['meeting_nodes'])}\"")
    parts.append(f"--algorithm {common.get('algorithm')} --scheduler {common.get('scheduler')}")
    if not plane:
        for option, key, default in (("--task", "task", None),
                                     ("--multiplicity", "detection", "local-weak"),
                                     ("--frames", "frames", "all"),
                                     ("--visibility", "visibility", None)):
            if common.get(key, default) != default:
                parts.append(f"{option} {common[key]}")
    if common.get("lights") is not None:
        parts.append(f"--lights {common['lights']}")
    if lit:
        colours = " ".join(str(n[1]) for n in r["robots"] if isinstance(n, list))
        parts.append(f"--colours \"{colours}\"")
    if verdict == "VIOLATED":
        parts.append("--html trace.html")
    return " ".join(parts)


def _slug(*parts: Any) -> str:
    return "-".join("".join(c if c.isalnum() else "_" for c in str(p)) for p in parts)


def setting_text(key: str, value: Any) -> str | None:
    """A stored setting as people read it, never as Python or JSON (``None``, ``null``,
    ``[3, 3]``); None: leave it out (a setting with no value).

    >>> setting_text("box", [3, 3]), setting_text("properties", []), setting_text("task", None)
    ('3x3', 'all', None)
    >>> setting_text("visibility", None), setting_text("extra", {"readings": "alpha", "on": [1]})
    ('unlimited', 'readings=alpha, on=1')
    """
    if value is None:
        return "unlimited" if key == "visibility" else None
    if key == "box" and isinstance(value, list):
        return "x".join(map(str, value))
    if key == "properties" and isinstance(value, list):
        return ", ".join(map(str, value)) or "all"
    if isinstance(value, bool):
        return "yes" if value else "no"
    if isinstance(value, dict):
        parts = ((k, setting_text(str(k), v)) for k, v in value.items())
        return ", ".join(f"{k}={v}" for k, v in parts if v is not None) or None
    if isinstance(value, list):
        return " ".join(t for t in (setting_text(key, v) for v in value) if t is not None)
    return str(value)


def settings_line(settings: dict[str, Any]) -> str:
    """A sweep's settings as ``key=value, ...`` (:func:`setting_text`, sorted by key)."""
    texts = ((k, setting_text(k, v)) for k, v in sorted(settings.items(), key=lambda kv: str(kv[0])))
    return ", ".join(f"{k}={v}" for k, v in texts if v is not None)


def _settings_table(common: dict[str, Any], sweeps: list[tuple[dict[str, Any], list]]) -> str:
    """The settings of a batch as a table, and its configurations per (n, m)."""
    from gather_verify.properties import PROPERTIES

    labels = {"algorithm": "algorithm", "scheduler": "scheduler", "detection": "multiplicity "
              "detection", "frames": "frames", "box": "box", "properties": "properties",
              "move_bound_c": "move bound c (c·D·n)", "reduction": "reductions (anonymity, Aut(M))",
              "max_states": "state limit per configuration", "max_seconds": "time limit per "
              "configuration (s)", "max_memory_mb": "memory limit per worker (MB)",
              "extra": "other settings"}
    shown = dict(common)
    if "box" in shown and isinstance(shown["box"], list):
        shown["box"] = " × ".join(map(str, shown["box"]))
    if shown.get("properties") == []:
        shown["properties"] = (f"all ({', '.join(PROPERTIES)})" if _on_plane(common)
                               else "all of the task's")
    if "reduction" in shown and isinstance(shown["reduction"], bool):
        shown["reduction"] = "on" if shown["reduction"] else "off"
    rows = []
    for key in [*labels, *sorted((k for k in shown if k not in labels), key=str)]:
        if key in shown:
            text = setting_text(str(key), shown[key])
            if text is not None:
                rows.append(f"<tr><th>{_esc(labels.get(key, key))}</th><td>{_esc(text)}</td></tr>")
    ns = sorted({s.get("robots") for s, _ in sweeps}, key=str)
    ms = sorted({s.get("meeting") for s, _ in sweeps}, key=str)
    count = {(s.get("robots"), s.get("meeting")): len(r) for s, r in sweeps}
    grid = ("<table class='counts'><tr><th>robots n \\ meeting nodes m</th>"
            + "".join(f"<th>{_esc(m)}</th>" for m in ms) + "<th>total</th></tr>"
            + "".join(f"<tr><th>{_esc(n)}</th>"
                      + "".join(f"<td>{count.get((n, m), '')}</td>" for m in ms)
                      + f"<td>{sum(c for (a, _), c in count.items() if a == n)}</td></tr>"
                      for n in ns) + "</table>")
    return ("<div class='settings'><table class='kv'>" + "".join(rows) + "</table>"
            "<div><p class='note'>configurations (up to "
            + ("translation and the 8 isometries" if _on_plane(common) else
               "the world's symmetries") + ")</p>"
            + grid + "</div></div>")


def _smallest(rows: list[dict[str, Any]]) -> dict[str, Any]:
    """The smallest counterexample: fewest events, then fewest robots, meeting nodes, the
    smallest D, then the first in enumeration order."""
    return min(rows, key=lambda r: (len((r.get("trace") or {}).get("steps", ())) if r.get("trace")
                                    else 10**9, len(r["robots"]), len(r["meeting_nodes"]),
                                    r.get("D") or 0, r["index"]))


def _code_tag(batch: Batch) -> str:
    """The batch's fingerprint, when it was written and whether it is the current code's, as
    one line of the page (the current one marked)."""
    kind = {True: "current", False: "older"}.get(batch.current, "unknown")  # type: ignore[arg-type]
    title = f"fingerprint {batch.common.get('fingerprint')}"
    if when(batch.first) and when(batch.first) != when(batch.last):
        title += f"; first rows written {when(batch.first)}"
    return (f"<span class='code {kind}' title='{_esc(title)}'>{_esc(batch.describe())}"
            "</span>")


def _batch_page(number: int, common: dict[str, Any], sweeps: list, folder: Path,
                plot: str | None, batch: Batch | None = None) -> str:
    from gather_verify.properties import ORDER
    from gather_verify.scenario import VERDICTS
    from gather_verify.theory import get_fact

    rows = [dict(r, robots_n=s.get("robots"), meeting_m=s.get("meeting"))
            for s, rs in sweeps for r in rs]
    title = (f"{common.get('algorithm')} / {common.get('scheduler')}"
             + (f", box {' × '.join(map(str, common['box']))}" if common.get("box") else ""))
    parts = [f"<h2 id='batch{number}'>Batch {number}: {_esc(title)}</h2>",
             *([f"<p>{_code_tag(batch)}</p>"] if batch is not None else []),
             f"<p>{len(rows)} configurations in {len(sweeps)} sweep(s) of one command "
             "(one sweep per number of robots and of meeting nodes).</p>",
             "<h3>Settings</h3>", _settings_table(common, sweeps)]
    # class x verdict x property: every count links to the list of its configurations
    cells: dict[tuple[str, str, str], list[dict[str, Any]]] = {}
    for r in rows:
        prop = (r.get("property") or "") if r["verdict"] == "VIOLATED" else ""
        cells.setdefault((r["class"], r["verdict"], prop), []).append(r)
    props = [p for p in ORDER if any(k[2] == p for k in cells)]
    props += sorted({k[2] for k in cells if k[2] and k[2] not in props})
    columns = [("VERIFIED", "")] + [("VIOLATED", p) for p in props] + \
              ([("VIOLATED", "")] if any(k[1:] == ("VIOLATED", "") for k in cells) else []) + \
              [(v, "") for v in VERDICTS if v not in ("VERIFIED", "VIOLATED")]
    classes = [c for c in get_fact("class").values if any(k[0] == c for k in cells)]
    classes += sorted({k[0] for k in cells} - set(classes))
    plane = _on_plane(common)  # the paper's notions (classes, D·n) on its world only
    head = (f"<tr><th rowspan=2>{'class' if plane else 'world'}</th><th rowspan=2>"
            "configurations</th><th rowspan=2>VERIFIED</th>"
            + (f"<th colspan={len(props)} class='bad'>VIOLATED, by failing property</th>" if props else "")
            + "".join(f"<th rowspan=2>{v}</th>" for v, p in columns[1 + len(props):])
            + ("<th rowspan=2>largest moves / (D·n)</th>" if plane else "") + "</tr><tr>"
            + "".join(f"<th class='bad'>{_esc(p)}</th>" for p in props) + "</tr>")
    body = []
    lists = []
    for c in classes:
        total = sum(len(v) for k, v in cells.items() if k[0] == c)
        ratios = [r["ratio"] for k, v in cells.items() if k[0] == c for r in v
                  if r.get("ratio") is not None]
        tds = []
        for verdict, prop in columns:
            found = cells.get((c, verdict, prop), [])
            if not found:
                tds.append("<td class='zero'>0</td>")
                continue
            anchor = _slug("list", number, c, verdict, prop)
            kind = "bad" if verdict == "VIOLATED" else "ok" if verdict == "VERIFIED" else ""
            tds.append(f"<td class='{kind}'><a href='#{anchor}'>{len(found)}</a></td>")
            lists.append(_filtered_list(anchor, c, verdict, prop, found, common))
        ratio = "" if not plane else f"<td>{_number(max(ratios))}</td>" if ratios else \
            "<td>–</td>"
        body.append(f"<tr><th>{_esc(c)}</th><td>{total}</td>" + "".join(tds) + ratio + "</tr>")
    named = (f"the first that fails in the order {', '.join(ORDER)}, but a livelock is named "
             "termination (move-bound fails with it)" if plane else
             "the first of the task's parts that fails")
    parts += [f"<h3>Verdicts: {'class' if plane else 'world'} × verdict × failing property</h3>",
              "<p class='note'>Each count opens the list of its configurations. One property is "
              f"named per configuration: {named}.</p>",
              "<table class='verdicts'>" + head + "".join(body) + "</table>"]
    parts += _causes_table(rows)
    parts += _smallest_figures(number, classes, props, cells, folder, common)
    if plot and plane:
        parts += ["<h3>Moves against D·n</h3>",
                  f"<img class='plot' src='{_esc(plot)}' alt='largest total moves against D·n, "
                  "coloured by verdict, with the line c·D·n'>"]
    parts += ["<h3>Configurations</h3><p class='note'>The list of a count in the table above "
              "shows here when you click it.</p>", *lists]
    return "\n".join(parts)


def _smallest_figures(number: int, classes: list[str], props: list[str],
                      cells: dict[tuple[str, str, str], list[dict[str, Any]]], folder: Path,
                      common: dict[str, Any]) -> list[str]:
    """The smallest counterexample of each (class, property), as a thumbnail opening its
    viewer (written into ``folder``)."""
    from gather_verify.render import thumbnail_svg
    from gather_verify.viewer import write_viewer

    figures = []
    for c in classes:
        for p in props:
            found = [r for r in cells.get((c, "VIOLATED", p), []) if r.get("trace")]
            if not found:
                continue
            r = _smallest(found)
            name = f"{_slug('batch', number, c, p)}.html"
            folder.mkdir(parents=True, exist_ok=True)
            write_viewer(r["trace"], str(folder / name),
                         title=f"{c}: {p} fails ({common.get('algorithm')} / "
                               f"{common.get('scheduler')})", load_code=False)
            steps = len(r["trace"]["steps"])
            figures.append(
                f"<figure><a href='{_esc(folder.name)}/{name}' title='open the viewer'>"
                f"{thumbnail_svg(r['trace'], uid=_slug('t', number, c, p))}</a>"
                f"<figcaption><b>{_esc(c)}</b> · <span class='bad'>{_esc(p)}</span> · "
                f"{steps} event{'s' if steps != 1 else ''}<br>robots "
                f"{_esc(_nodes(r['robots'], _lit(common)))}"
                f"<br>meeting {_esc(_nodes(r['meeting_nodes']))}<br>"
                f"<a href='{_esc(folder.name)}/{name}'>open the viewer</a> · "
                f"<a href='#{_slug('list', number, c, 'VIOLATED', p)}'>all "
                f"{len(cells[(c, 'VIOLATED', p)])}</a></figcaption></figure>")
    if not figures:
        return []
    return ["<h3>Smallest counterexample of each class and property</h3>",
            "<p class='note'>Initial configuration → last state (robots coloured by "
            "identity, meeting nodes as squares, dashed arrows = pending moves). Click one to "
            "step through it.</p>", "<div class='thumbs'>" + "".join(figures) + "</div>"]


def _filtered_list(anchor: str, c: str, verdict: str, prop: str, found: list[dict[str, Any]],
                   common: dict[str, Any]) -> str:
    """The configurations of one table cell, each with the command that re-checks it."""
    items = []
    plane = _on_plane(common)
    for r in found[:LIST_LIMIT]:
        command = _recheck(r, verdict, common)
        ratio = "" if r.get("ratio") is None else _number(r["ratio"])
        moves = (f"<td>{'' if r.get('max_moves') is None else _esc(r['max_moves'])}</td>"
                 f"<td>{ratio}</td>") if plane else ""
        items.append(f"<tr><td>{_esc(r['robots_n'])}</td><td>{_esc(r['meeting_m'])}</td>"
                     f"<td>{_esc(_nodes(r['robots'], _lit(common)))}</td>"
                     f"<td>{_esc(_nodes(r['meeting_nodes']))}</td>{moves}"
                     f"<td class='reason'>{_esc(r.get('reason') or '')}</td>"
                     f"<td><code>{_esc(command)}</code></td></tr>")
    what = f"{verdict}" + (f", {prop} fails" if prop else "")
    return (f"<section class='list' id='{anchor}'><h4>{_esc(c)}: {_esc(what)} — "
            f"{counted(len(found), 'configuration')} <a href='#top'>↑ back to the table</a></h4>"
            "<table><tr><th>n</th><th>m</th><th>robots</th><th>meeting nodes</th>"
            + ("<th>max moves</th><th>moves / (D·n)</th>" if plane else "")
            + "<th>reason</th><th>re-check</th></tr>"
            + "".join(items) + "</table>"
            + (f"<p class='note'>The first {LIST_LIMIT} of {len(found)} are listed; "
               "<code>gather-verify report --db DB --json</code> has the totals, the database "
               "every row.</p>" if len(found) > LIST_LIMIT else "") + "</section>")


STYLE = """
body{font:14px/1.45 system-ui,sans-serif;margin:16px auto;max-width:1200px;padding:0 16px;color:#222}
h1{font-size:22px} h2{border-bottom:2px solid #ddd;padding-bottom:4px;margin-top:28px}
table{border-collapse:collapse;margin:6px 0} td,th{padding:3px 10px;border:1px solid #e3e3e3}
th{background:#f4f4f4;font-weight:600;text-align:left} td{text-align:right}
.kv td{text-align:left} .settings{display:flex;gap:32px;flex-wrap:wrap;align-items:flex-start}
.note{color:#666;font-size:13px;margin:4px 0} .zero{color:#bbb}
.bad{color:#b3261e} td.bad{background:#fdecea} td.ok{background:#eef6ee}
th.bad{background:#fbe1de}
a{color:#1f5fbf} td a{font-weight:600;text-decoration:none}
.thumbs{display:flex;flex-wrap:wrap;gap:12px}
figure{margin:0;border:1px solid #ddd;border-radius:6px;padding:8px;background:#fff}
figure svg{display:block;margin-bottom:4px} figcaption{font-size:12px;color:#444}
.list{display:none;margin:10px 0;padding:8px;border:2px solid #1f5fbf;border-radius:6px}
.list:target{display:block} .list td{text-align:left;font-size:12px} .reason{max-width:360px}
.list code{font-size:11px;white-space:nowrap}
.plot{max-width:100%;border:1px solid #ddd;border-radius:6px}
nav a{margin-right:12px}
.code{font-size:13px;color:#555;padding:1px 6px;border-radius:4px;background:#f4f4f4}
.code.current{color:#1b5e20;background:#e3f1e3;font-weight:600}
.code.older{color:#7a4b00;background:#fff3dc} .batches li{margin:6px 0}
"""


def write_html(db_path: str, out: str, svg_dir: str | None = None,
               algorithm: str | None = None) -> list[Path]:
    """The report: one page per batch of sweeps (one ``sweep`` command), with a settings table,
    the class × verdict × property table whose counts open filtered lists, the smallest
    counterexample of each (class, property) as a thumbnail opening its viewer, and the plot
    of moves against D·n (when matplotlib is installed). With several batches ``out`` is an
    index and the batches are ``<out stem>-<k>.html`` beside it; the viewers and the plot go
    into the folder ``svg_dir`` (default ``<out stem>-files``). Every page names each batch's
    fingerprint, when its rows were written and whether it is the code on disk now (the
    index marks the current batches: those of an edited algorithm differ in all three).
    ``algorithm``: only the sweeps of that algorithm. Returns the pages written."""
    page = Path(out)
    folder = Path(svg_dir) if svg_dir else page.with_name(page.stem + "-files")
    groups = batch_list(db_path, algorithm)
    page.parent.mkdir(parents=True, exist_ok=True)
    written = []
    names = [page] if len(groups) <= 1 else [page.with_name(f"{page.stem}-{k}.html")
                                            for k in range(1, len(groups) + 1)]
    for k, (batch, target) in enumerate(zip(groups, names, strict=False), 1):
        common, sweeps = batch.common, batch.sweeps
        plot = None
        plane = _on_plane(common)  # a finite world counts no moves
        try:
            if plane:
                folder.mkdir(parents=True, exist_ok=True)
                _plot([(common, [r for _, rs in sweeps for r in rs])],
                      str(folder / f"plot-{k}.png"))
                plot = f"{folder.name}/plot-{k}.png"
        except InvalidInput:  # no matplotlib: the page says so instead of showing the plot
            pass
        body = _batch_page(k, common, sweeps, folder, plot, batch)
        if plot is None and plane:
            body += "<p class='note'>(install matplotlib for the plot: pip install 'gather-verify[plot]')</p>"
        back = f"<nav><a href='{_esc(page.name)}'>← all batches</a></nav>" if len(groups) > 1 else ""
        target.write_text(_document("gather-verify report", back + body), encoding="utf-8")
        written.append(target)
    if len(groups) != 1:
        index = ["<p>One page per batch of sweeps (one <code>gather-verify sweep</code> command "
                 "each), with its fingerprint (the code and data behind its rows), when they "
                 "were written and whether they are the code on disk now (<span class='code "
                 "current'>current</span>): the batches of an edited algorithm differ in "
                 "all three.</p><ul class='batches'>"]
        for k, (batch, target) in enumerate(zip(groups, names, strict=False), 1):
            n = sum(len(rs) for _, rs in batch.sweeps)
            bad = sum(r["verdict"] == "VIOLATED" for _, rs in batch.sweeps for r in rs)
            index.append(f"<li><a href='{_esc(target.name)}'>Batch {k}: "
                         f"{_esc(batch.common.get('algorithm'))} / "
                         f"{_esc(batch.common.get('scheduler'))}</a>: "
                         f"{n} configurations, {bad} VIOLATED<br>{_code_tag(batch)}</li>")
        if not groups:
            index.append("<li>(no sweep in this database"
                         + (f" of algorithm {_esc(algorithm)}" if algorithm else "") + ")</li>")
        page.write_text(_document("gather-verify report", "".join(index) + "</ul>"),
                        encoding="utf-8")
        written.insert(0, page)
    return written


def _document(title: str, body: str) -> str:
    return (f"<!doctype html><html lang='en'><head><meta charset='utf-8'><title>{_esc(title)}"
            f"</title><style>{STYLE}</style></head><body><h1 id='top'>{_esc(title)}</h1>"
            f"{body}</body></html>\n")


VERDICT_COLOURS = {"VERIFIED": "#2e7d32", "VIOLATED": "#c62828", "INCOMPLETE": "#9e9e9e",
                   "NOT-APPLICABLE": "#6d4c9e"}
MARKERS = "os^Dv<>p*h"


def write_plot(db_path: str, out: str, algorithm: str | None = None) -> list[str]:
    """Scatter of the largest total moves against D·n, one series per verdict (and per batch
    when there are several), marker area growing with the number of configurations on a
    point, and the line c·D·n of each batch's move bound (matplotlib); ``algorithm``: only
    its sweeps. Returns the legend."""
    groups = [(common, [r for _, rs in sweeps for r in rs])
              for common, sweeps in batches(db_path, algorithm) if _on_plane(common)]
    if not groups:  # a finite world has no D (the paper's MER) to plot moves against
        raise InvalidInput(f"--plot {out}: no sweep of the paper's world in {db_path} (the "
                           "plot is of moves against D·n, the paper's notions)")
    return _plot(groups, out)


def _plot(groups: list[tuple[dict[str, Any], list[dict[str, Any]]]], out: str) -> list[str]:
    try:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        raise InvalidInput("--plot needs matplotlib: pip install 'gather-verify[plot]'") from None
    from collections import Counter

    from gather_verify.scenario import VERDICTS

    fig, ax = plt.subplots(figsize=(7, 4.8))
    formats = fig.canvas.get_supported_filetypes()
    if Path(out).suffix.lower().lstrip(".") not in formats:
        plt.close(fig)
        raise InvalidInput(f"--plot {out}: write a picture, one of "
                           f"{', '.join('.' + f for f in sorted(formats))}")
    top = 1.0
    bounds: set[float] = set()
    for b, (common, rows) in enumerate(groups):
        bounds.add(float(common.get("move_bound_c", 4.0)))
        name = f"{common.get('algorithm')} / {common.get('scheduler')} · " if len(groups) > 1 else ""
        for verdict in VERDICTS:
            points = Counter((r["D"] * r["n"], r["max_moves"]) for r in rows
                             if r["verdict"] == verdict and r.get("max_moves") is not None
                             and r.get("D") is not None and r.get("n") is not None)
            if not points:
                continue
            xs, ys = zip(*points, strict=True)
            top = max(top, *xs)
            sizes = [12 + 6 * points[p] ** 0.5 for p in points]
            ax.scatter(xs, ys, s=sizes, alpha=0.55, color=VERDICT_COLOURS.get(verdict, "#333"),
                       marker=MARKERS[b % len(MARKERS)], edgecolors="none",
                       label=f"{name}{verdict} ({sum(points.values())})")
    ends = [0, top * 1.05]
    for c in sorted(bounds):
        ax.plot(ends, [c * x for x in ends], "k--", linewidth=1, label=f"bound {c:g}·D·n")
    ax.set_xlabel("D·n (D: longer side of the initial MER, n: robots)")
    ax.set_ylabel("largest total moves over all executions")
    ax.set_title("Moves against D·n (marker area: configurations on the point)", fontsize=10)
    ax.set_xlim(left=0)
    ax.set_ylim(bottom=0)
    ax.grid(alpha=0.3)
    legend = ax.legend(fontsize=8, loc="upper left")
    fig.tight_layout()
    fig.savefig(out, dpi=100)
    plt.close(fig)
    return [t.get_text() for t in legend.get_texts()]


def _causes_table(rows: list[dict[str, Any]]) -> list[str]:
    """The VIOLATED rows counted by failing property × cause (the rule the run failed in);
    a row with none counts as :data:`~gather_verify.sweeps.store.CAUSE_UNKNOWN`, never as
    some cause, and rows none of which has a cause (a finite world's) give no table."""
    from gather_verify.properties import ORDER
    from gather_verify.sweeps.store import CAUSE_UNKNOWN

    counts: dict[str, dict[str, int]] = {}
    for r in rows:
        if r["verdict"] == "VIOLATED" and r.get("property"):
            by = counts.setdefault(r["property"], {})
            why = r.get("cause") or CAUSE_UNKNOWN
            by[why] = by.get(why, 0) + 1
    if all(set(by) == {CAUSE_UNKNOWN} for by in counts.values()):
        return []
    order = [p for p in ORDER if p in counts] + sorted(set(counts) - set(ORDER))
    body = "".join(
        f"<tr><th>{_esc(p)} × {sum(counts[p].values())}</th><td>"
        + ", ".join(f"{_esc(why)} {k}" for why, k in sorted(counts[p].items(),
                                                            key=lambda kv: (-kv[1], kv[0])))
        + "</td></tr>" for p in order)
    return ["<h3>Violations by cause: failing property × the rule its run failed in</h3>",
            "<table class='causes'>" + body + "</table>"]

