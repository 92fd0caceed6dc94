"""The results store: one SQLite database (standard library) per sweep directory.

A sweep is identified by its settings (algorithm, scheduler, detection, frames,
properties, limits, box and counts) and the fingerprint of its algorithm's source
(:mod:`gather_verify.fingerprint`: an edited algorithm is another sweep, never the
old rows); a result row by the sweep and the
configuration's canonical key. Rows are written in transactions as results
arrive, so a sweep killed at any moment keeps everything committed, and a
re-run skips what is there. Timings live in their own table: the results
table of a sweep is byte-for-byte the same whatever ran it.

>>> store = Store(":memory:")
>>> sweep = store.sweep_id({"algorithm": "go-to-target", "scheduler": "fsync"})
>>> store.add(sweep, [{"key": "k1", "index": 0, "class": "I13", "verdict": "VERIFIED"}])
>>> store.done_keys(sweep)
{'k1'}
"""

from __future__ import annotations

import json
import sqlite3
from collections.abc import Iterable
from pathlib import Path
from typing import Any

from gather_verify.errors import InvalidInput

COLUMNS = (
    "key", "index", "robots", "meeting_nodes", "class", "verdict", "property", "reason",
    "states", "transitions", "max_moves", "D", "n", "ratio", "trace", "failing", "cause",
)
JSON_COLUMNS = ("robots", "meeting_nodes", "trace", "failing")
"""``failing``: every property that fails (``property`` names the first); ``cause``: the rule
the first one's run failed in (``check``'s ``cause``). Both are added to older databases when
they are opened; a row with none (NULL: stored before causes, or a finite world's, whose
algorithms name no rules) counts in a summary as :data:`CAUSE_UNKNOWN`, never as some cause,
and a summary where no row has a cause shows no causes at all."""
CAUSE_UNKNOWN = "cause not recorded"
ADDED = ("failing", "cause")
"""The columns added since the first schema, in order (older databases get them on opening)."""
_SCHEMA = """
CREATE TABLE IF NOT EXISTS sweeps (
    id INTEGER PRIMARY KEY,
    settings TEXT NOT NULL UNIQUE
);
CREATE TABLE IF NOT EXISTS results (
    sweep INTEGER NOT NULL REFERENCES sweeps(id),
    key TEXT NOT NULL,
    "index" INTEGER NOT NULL,
    robots TEXT, meeting_nodes TEXT, class TEXT, verdict TEXT, property TEXT, reason TEXT,
    states INTEGER, transitions INTEGER, max_moves INTEGER, D INTEGER, n INTEGER, ratio REAL,
    trace TEXT, failing TEXT, cause TEXT,
    PRIMARY KEY (sweep, key)
);
CREATE TABLE IF NOT EXISTS timings (
    sweep INTEGER NOT NULL, key TEXT NOT NULL, seconds REAL, PRIMARY KEY (sweep, key)
);
CREATE TABLE IF NOT EXISTS written (
    sweep INTEGER PRIMARY KEY, first TEXT, last TEXT, fingerprint_extra TEXT
);
"""
WRITTEN = ("first", "last", "fingerprint_extra")
"""Per sweep, outside its results (which stay the same whatever ran them): when its first and
its last rows were written (UTC, ISO 8601), and the files named with ``--fingerprint-extra``
(``report`` tells with them whether the code on disk is the one behind the rows). A
database written before has no such table: its dates are unknown."""


def algorithm_matches(spec: Any, name: str | None) -> bool:
    """Whether a stored sweep's algorithm ``spec`` is one ``name`` names (``report
    --algorithm``): the same spec, the same file (a relative path is taken from the working
    directory) or registered name with any options, or the algorithm's ``NAME`` in its file.

    >>> [algorithm_matches(s, "paper") for s in ("paper", "paper:alpha=mer_f", "paperx")]
    [True, True, False]
    >>> algorithm_matches("/home/me/alg.py:Walk:k=1", "Walk"), algorithm_matches("/a/alg.py:W", "alg.py:W")
    (True, False)
    """
    from gather_verify.algorithms.loading import absolute_spec, split_external

    if name is None:
        return True
    if not isinstance(spec, str):
        return False
    if spec in (name, absolute_spec(name)):
        return True
    try:
        external = split_external(spec)
        if external is None:
            return spec.partition(":")[0] == name
        where, what, _ = external
        return name in (what, f"{where}:{what}") or absolute_spec(name) == f"{where}:{what}"
    except ValueError:
        return False


def row(*, key: str, index: int, robots: list[Any], meeting_nodes: list[Any], class_: str,
        verdict: str, seconds: float, failing: list[str] | None = None, **fields: Any
        ) -> dict[str, Any]:
    """The row the store keeps of one configuration: the one place a sweep's row is built,
    on any world and by any engine (a per-configuration check, the union engine). The other
    :data:`COLUMNS` are keywords (``property``, ``reason``, ``states``, ``transitions``,
    ``max_moves``, ``D``, ``n``, ``ratio``, ``trace``, ``cause``) and None when not given; a
    name that is not a column is a bug of ours, refused here rather than silently dropped.

    >>> row(key="k", index=0, robots=[[0, 0]], meeting_nodes=[], class_="I11",
    ...     verdict="VERIFIED", seconds=0.0)["failing"]
    []
    """
    unknown = set(fields) - set(COLUMNS)
    if unknown:
        raise TypeError(f"not a column of the results store: {sorted(unknown)}")
    out: dict[str, Any] = {c: fields.get(c) for c in COLUMNS}
    out.update(key=key, index=index, robots=robots, meeting_nodes=meeting_nodes,
               verdict=verdict, failing=list(failing or []), seconds=seconds)
    out["class"] = class_
    return out


def check_row(report: dict[str, Any], key: str, index: int, robots: list[Any],
              configuration: Any, seconds: float) -> dict[str, Any]:
    """The row of one check of the paper's world (``run_check``'s report), oblivious or
    luminous (``robots`` as the row writes them: ``[x, y]``, or ``[[x, y], colour]``)."""
    return report_row(report, key=key, index=index, robots=robots, class_=report["class"],
                      meeting_nodes=sorted(list(m) for m in configuration.meeting_nodes),
                      seconds=seconds)


def report_row(report: dict[str, Any], **fields: Any) -> dict[str, Any]:
    """The row of one check's report (the paper's world or a finite world's): its verdict,
    counts and trace, with the other ``fields`` of :func:`row` (``key``, ``index``, ``robots``,
    ``meeting_nodes``, ``class_``, ``seconds``)."""
    taken = {c: report.get(c) for c in ("property", "reason", "states", "transitions",
                                         "max_moves", "D", "n", "ratio", "trace", "cause")}
    return row(verdict=report["verdict"], **{**taken, **fields},
               failing=[p for p, r in report["properties"].items() if r.get("holds") is False])


def utc_now() -> str:
    """The time now, UTC, to the second (``2026-01-31T09:05:00Z``)."""
    import datetime

    now = datetime.datetime.now(datetime.UTC).replace(microsecond=0)
    return now.isoformat().replace("+00:00", "Z")


def _json(column: str, kind: str, null: bool = True) -> str:
    c = f'r."{column}"'  # (json_type raises on malformed text: asked only of valid JSON)
    test = f"CASE WHEN json_valid({c}) THEN json_type({c}) = '{kind}' ELSE 0 END"
    return f"{c} IS NULL OR {test}" if null else test


STORED_VERDICTS = ("VERIFIED", "VIOLATED", "INCOMPLETE", "NOT-APPLICABLE", "ROBUST-VERIFIED",
                   "ROBUST-VIOLATED", "READING-DEPENDENT")
"""What a row's verdict may hold: a check's verdict, or a readings sweep's robustness
(:data:`gather_verify.paper.readings.ROBUSTNESS`)."""
_RULES = (
    ("key", "typeof(r.key) = 'text'"),
    ("index", "typeof(r.\"index\") = 'integer'"),
    ("class", "typeof(r.class) = 'text'"),
    ("verdict", f"r.verdict IN {STORED_VERDICTS}"),
    ("property", "typeof(r.property) = 'text' OR (r.property IS NULL AND "
                 "r.verdict IS NOT 'VIOLATED')"),  # a violation names its property
    *((c, f"r.{c} IS NULL OR typeof(r.{c}) = 'text'") for c in ("reason", "cause")),
    *((c, f'r."{c}" IS NULL OR typeof(r."{c}") = \'integer\'')
      for c in ("states", "transitions", "max_moves", "D")),
    ("n", "typeof(r.n) = 'integer' OR (r.n IS NULL AND r.verdict IN "
          "('ROBUST-VERIFIED', 'ROBUST-VIOLATED', 'READING-DEPENDENT'))"),
    # every row counts its robots (a readings row of an earlier version did not)
    ("ratio", "r.ratio IS NULL OR typeof(r.ratio) IN ('real', 'integer')"),
    ("robots", _json("robots", "array", null=False)),
    ("meeting_nodes", _json("meeting_nodes", "array", null=False)),
    ("failing", _json("failing", "array")),
    ("trace", _json("trace", "object")),
)
"""What each column of a stored row holds (an SQL test per column, NULL allowed where a
writer leaves it NULL)."""
_SIDE_RULES = (
    ("timings", "key", "typeof(r.key) = 'text'", "text"),
    ("timings", "seconds", "r.seconds IS NULL OR typeof(r.seconds) IN ('real', 'integer')",
     "a number"),
    *(("written", c, f"r.{c} IS NULL OR typeof(r.{c}) = 'text'", "a date") for c in
      ("first", "last")),
    ("written", "fingerprint_extra", _json("fingerprint_extra", "array"), "a JSON list"),
)
"""The tables beside the results: when each sweep's rows took, when they were written."""
_SWEEP_ONLY = ("class", "verdict", "robots", "meeting_nodes")
"""Columns every sweep row fills, which ``synthesize --minimum``'s rows leave NULL."""
_SWEEP_SETTINGS = " AND ".join((
    *(f"json_type(settings, '$.{k}') = 'text'" for k in ("algorithm", "scheduler")),
    *(f"json_type(settings, '$.{k}') = 'integer'" for k in ("robots", "meeting")),
    "(json_type(settings, '$.world') = 'text' OR (json_type(settings, '$.box') = 'array' AND "
    "json_array_length(settings, '$.box') = 2 AND json_type(settings, '$.box[0]') = 'integer' "
    "AND json_type(settings, '$.box[1]') = 'integer'))"))
"""An SQL test of a sweep's settings: the fields every reader of a sweep takes."""
_RULE_WORDS = {"key": "text", "index": "an integer", "class": "a class or world name",
               "verdict": "a verdict or a robustness", "property": "the failing property's name", "reason": "text", "cause": "text",
               "states": "an integer", "transitions": "an integer", "max_moves": "an integer",
               "D": "an integer", "n": "an integer", "ratio": "a number",
               "robots": "a JSON list", "meeting_nodes": "a JSON list",
               "failing": "a JSON list", "trace": "a JSON object"}


def check_db_path(path: str) -> None:
    """A results database given on the command line must be a file that outlives the command:
    one line for an empty path, ``:memory:`` or a ``file:`` URI (SQLite would keep every row
    in memory, or read the text as options, and the command would end with nothing written).

    >>> check_db_path("file:x.db?mode=memory")  # doctest: +ELLIPSIS
    Traceback (most recent call last):
    gather_verify.errors.InvalidInput: --db 'file:x.db?mode=memory': ...
    """
    text = str(path).strip()
    if not text:
        raise InvalidInput("--db: the path is empty (give a file, e.g. --db out/results.sqlite)")
    if text == ":memory:" or text.lower().startswith("file:"):
        raise InvalidInput(f"--db {path!r}: a results database is a file (SQLite would read this "
                           "as an in-memory database or a URI, and nothing would be kept): "
                           "give a file path, e.g. --db out/results.sqlite")


class Store:
    """A results database at ``path`` (``:memory:`` for tests). ``read_only``: a reader
    (``report``) never writes: the file must exist and be a results database, and is
    opened read-only (an older one's missing columns are read as NULL)."""

    def __init__(self, path: str | Path, read_only: bool = False):
        if not str(path).strip():  # SQLite would open a temporary database: every row lost
            raise InvalidInput("results database: the path is empty (give a file, e.g. "
                               "--db out/results.sqlite)")
        if read_only and not Path(path).is_file():
            raise InvalidInput(f"{path}: no such results database")
        if str(path) != ":memory:" and not read_only:
            folder = Path(path).resolve().parent
            if not folder.is_dir() and not folder.is_relative_to(Path.cwd()):
                raise InvalidInput(f"results database {path}: its folder does not exist (a "
                                   "sweep creates missing folders under the working directory "
                                   "only)")
            folder.mkdir(parents=True, exist_ok=True)
        try:
            if read_only:
                self.db = sqlite3.connect(f"{Path(path).resolve().as_uri()}?mode=ro", uri=True,
                                          timeout=60)
                self.db.execute("SELECT count(*) FROM sqlite_master").fetchone()
            else:
                self.db = sqlite3.connect(str(path), timeout=60)
                self.db.executescript(_SCHEMA)
        except sqlite3.DatabaseError as error:
            raise InvalidInput(f"{path}: not a gather-verify results database ({error})") from None
        for table, wanted in (("sweeps", ("id", "settings")), ("results", ("sweep", *COLUMNS)),
                              ("timings", ("sweep", "key", "seconds"))):
            have = {row[1] for row in self.db.execute(f"PRAGMA table_info({table})")}
            absent = [c for c in ADDED if table == "results" and have and c not in have]
            if absent and read_only:  # read as NULL through a view, the file untouched
                nulls = ", ".join(f"NULL AS {c}" for c in absent)
                self.db.execute(f"CREATE TEMP VIEW results AS SELECT *, {nulls} FROM main.results")
                have.update(absent)
            for column in absent if not read_only else ():
                with self.db:
                    self.db.execute(f"ALTER TABLE results ADD COLUMN {column} TEXT")
                have.add(column)
            missing = [c for c in wanted if c not in have]
            if missing:
                self.db.close()
                raise InvalidInput(f"{path}: not a gather-verify results database (table {table} "
                                 f"has no column {missing[0]!r})")
        if read_only:
            self.refuse_damage(str(path))
            return
        self.db.execute("PRAGMA journal_mode=WAL")
        self.db.execute("PRAGMA synchronous=NORMAL")
        # a whole box is 645,598 rows keyed by text, added a task at a time: pages in memory
        # and the log checkpointed every 64 MB, not every 4 MB (26 s of writing -> ~15 s)
        self.db.execute("PRAGMA cache_size=-65536")
        self.db.execute("PRAGMA wal_autocheckpoint=16384")

    def close(self) -> None:
        self.db.close()

    def refuse_damage(self, path: str, sweep: int | None = None) -> None:
        """One line naming the first value a reader cannot take (a damaged or hand-edited
        database: settings that are no JSON object, a column of the wrong type, truncated
        JSON, a sweep's row with no class or verdict), before anything reads the rows. The
        checks run in SQLite (``typeof``, ``json_valid``): no row is read into Python."""
        try:
            self.db.execute("SELECT json_valid('1')")
            json = True
        except sqlite3.OperationalError:  # an SQLite without its JSON functions: the types
            json = False
        problem = self._first_damage(json, sweep)
        if problem is not None:
            self.db.close()
            raise InvalidInput(f"{path}: a damaged results database: {problem} (written by "
                               "hand, or damaged: sweep again into a fresh database)")

    def _first_damage(self, json: bool = True, sweep: int | None = None) -> str | None:
        """The first damaged value (of one ``sweep``'s rows, or of all), in words, or None."""
        db = self.db
        only = "" if sweep is None else f" AND r.sweep = {int(sweep)}"
        bad = db.execute("SELECT id, substr(settings, 1, 40) FROM sweeps WHERE ("
                         + ("NOT CASE WHEN json_valid(settings) THEN json_type(settings) = "
                            "'object' ELSE 0 END"
                            if json else "typeof(settings) != 'text'") + ")"
                         + ("" if sweep is None else f" AND id = {int(sweep)}")
                         + " LIMIT 1").fetchone()
        if bad is not None:
            return f"sweep {bad[0]}: its settings {bad[1]!r} are not a JSON object"
        if json:  # a sweep's settings name its algorithm, scheduler, counts and world or box
            bad = db.execute(f"SELECT id FROM sweeps WHERE json_extract(settings, '$.command') "
                             f"IS NULL AND NOT IFNULL(({_SWEEP_SETTINGS}), 0)"
                             + ("" if sweep is None else f" AND id = {int(sweep)}")
                             + " LIMIT 1").fetchone()
            if bad is not None:
                return (f"sweep {bad[0]}: its settings lack a text algorithm and scheduler, "
                        "integer robots and meeting, or a world or box")
        for column, rule in _RULES:
            if not json and "json_" in rule:
                continue
            if column in _SWEEP_ONLY:  # a sweep's rows have them; not those of
                rule = (f"({rule}) OR r.sweep IN (SELECT id FROM sweeps WHERE "  # --minimum
                        + ("json_extract(settings, '$.command') IS NOT NULL)" if json else
                           "settings LIKE '%\"command\":%')"))
            got = db.execute(f'SELECT r.sweep, r.key, substr(r."{column}", 1, 40) FROM results r '
                             f"WHERE NOT IFNULL(({rule}), 0){only} LIMIT 1").fetchone()
            if got is not None:
                value = "NULL" if got[2] is None else repr(got[2])
                return (f"sweep {got[0]}, row {str(got[1])[:60]!r}: {column} holds {value}, "
                        f"not {_RULE_WORDS[column]}")
        tables = {t for (t,) in db.execute("SELECT name FROM sqlite_master WHERE type IN "
                                           "('table', 'view')")}
        for table, column, rule, words in _SIDE_RULES:
            if table not in tables or (not json and "json_" in rule):
                continue
            got = db.execute(f'SELECT r.sweep, substr(r."{column}", 1, 40) FROM {table} r '
                             f"WHERE NOT IFNULL(({rule}), 0){only} LIMIT 1").fetchone()
            if got is not None:
                return (f"sweep {got[0]}: its {table} {column} holds "
                        f"{'NULL' if got[1] is None else repr(got[1])}, not {words}")
        return None

    @staticmethod
    def settings_text(settings: dict[str, Any]) -> str:
        return json.dumps(settings, sort_keys=True, separators=(",", ":"))

    def sweep_id(self, settings: dict[str, Any]) -> int:
        """The id of the sweep with these settings, created if new."""
        text = self.settings_text(settings)
        with self.db:
            self.db.execute("INSERT OR IGNORE INTO sweeps(settings) VALUES (?)", (text,))
        return int(self.db.execute("SELECT id FROM sweeps WHERE settings = ?", (text,)).fetchone()[0])

    def sweeps(self) -> list[tuple[int, dict[str, Any]]]:
        return [(i, json.loads(s)) for i, s in self.db.execute("SELECT id, settings FROM sweeps ORDER BY id")]

    def done_keys(self, sweep: int) -> set[str]:
        return {k for (k,) in self.db.execute("SELECT key FROM results WHERE sweep = ?", (sweep,))}

    @staticmethod
    def encode(rows: list[dict[str, Any]]) -> list[dict[str, Any]]:
        """``rows`` with their JSON columns (traces, nodes) as the text the store keeps: what
        a worker does before it sends them, so the process that writes only writes."""
        for row in rows:
            for c in JSON_COLUMNS:
                value = row.get(c)
                if value is not None and not isinstance(value, str):
                    row[c] = json.dumps(value, sort_keys=True, separators=(",", ":"))
        return rows

    def add(self, sweep: int, rows: Iterable[dict[str, Any]]) -> None:
        """Store finished results in one transaction."""
        rows = self.encode(list(rows))
        values = [(sweep, *(row.get(c) for c in COLUMNS)) for row in rows]
        marks = ",".join("?" * (len(COLUMNS) + 1))
        names = ",".join(f'"{c}"' for c in COLUMNS)
        with self.db:
            self.db.executemany(
                f"INSERT OR REPLACE INTO results(sweep,{names}) VALUES ({marks})", values
            )
            self.db.executemany(
                "INSERT OR REPLACE INTO timings(sweep, key, seconds) VALUES (?, ?, ?)",
                [(sweep, r["key"], r.get("seconds")) for r in rows],
            )
            if rows:
                now = utc_now()
                self.db.execute("INSERT INTO written(sweep, first, last) VALUES (?, ?, ?) "
                                "ON CONFLICT(sweep) DO UPDATE SET last = excluded.last",
                                (sweep, now, now))

    def note_extra(self, sweep: int, files: Iterable[str]) -> None:
        """Keep the ``--fingerprint-extra`` files of a sweep (what ``report`` needs to tell
        whether the code and data on disk are those behind its rows)."""
        text = json.dumps(list(files))
        with self.db:
            self.db.execute("INSERT INTO written(sweep, fingerprint_extra) VALUES (?, ?) "
                            "ON CONFLICT(sweep) DO UPDATE SET fingerprint_extra = "
                            "excluded.fingerprint_extra", (sweep, text))

    def written(self) -> dict[int, dict[str, Any]]:
        """Per sweep id: ``first`` and ``last`` (when its first and last rows were written,
        None if unknown) and ``fingerprint_extra`` (a list); empty for a database written
        before these were kept."""
        have = self.db.execute("SELECT count(*) FROM sqlite_master WHERE type = 'table' AND "
                               "name = 'written'").fetchone()[0]
        if not have:
            return {}
        out = {}
        for sweep, first, last, extra in self.db.execute(
                "SELECT sweep, first, last, fingerprint_extra FROM written"):
            try:
                files = json.loads(extra) if extra else []
            except ValueError:
                files = None  # damaged: the files cannot be named
            out[sweep] = {"first": first, "last": last, "fingerprint_extra": files}
        return out

    def seconds(self) -> list[dict[str, Any]]:
        """Every stored row's sweep, index, meeting nodes and seconds (no traces read)."""
        cursor = self.db.execute(
            'SELECT r.sweep, r."index", r.meeting_nodes, t.seconds FROM results r JOIN timings t '
            "ON t.sweep = r.sweep AND t.key = r.key")
        return [{"sweep": sweep, "index": index,
                 "meeting_nodes": None if m is None else json.loads(m), "seconds": sec}
                for sweep, index, m, sec in cursor]  # (synthesize --minimum's rows: NULL)

    def totals(self, sweep: int) -> list[tuple[Any, ...]]:
        """A sweep's rows counted for a summary, no row read: ``(class, verdict, property,
        failing, count, largest ratio, cause)`` per group of rows alike in these (and in
        having a ratio), in order of each group's first row, so totals summed in this order
        meet every class, verdict and property where the rows themselves would."""
        cursor = self.db.execute(
            "SELECT class, verdict, property, failing, COUNT(*), MAX(ratio), cause FROM results "
            "WHERE sweep = ? GROUP BY class, verdict, property, failing, cause, ratio IS NULL "
            'ORDER BY MIN("index")', (sweep,))
        return [(c, v, p, None if f is None else json.loads(f), k, r, why)
                for c, v, p, f, k, r, why in cursor]

    def slowest(self, sweep: int, count: int) -> list[dict[str, Any]]:
        """The ``count`` rows of a sweep that took longest (ties: enumeration order), with
        their nodes, class and seconds."""
        cursor = self.db.execute(
            "SELECT r.robots, r.meeting_nodes, r.class, t.seconds FROM results r LEFT JOIN "
            "timings t ON t.sweep = r.sweep AND t.key = r.key WHERE r.sweep = ? "
            'ORDER BY COALESCE(t.seconds, 0) DESC, r."index" LIMIT ?', (sweep, count))
        return [{"robots": json.loads(robots), "meeting_nodes": json.loads(m), "class": c,
                 "seconds": sec} for robots, m, c, sec in cursor]

    def failing(self, sweep: int, count: int) -> list[dict[str, Any]]:
        """The first ``count`` VIOLATED rows of a sweep, in enumeration order: their nodes,
        class and failing property."""
        cursor = self.db.execute(
            'SELECT robots, meeting_nodes, class, property FROM results WHERE sweep = ? AND '
            'verdict = \'VIOLATED\' ORDER BY "index" LIMIT ?', (sweep, count))
        return [{"robots": json.loads(robots), "meeting_nodes": json.loads(m), "class": c,
                 "property": p} for robots, m, c, p in cursor]

    def forget(self, sweep: int) -> None:
        """Drop every stored row of a sweep (``sweep --fresh``)."""
        with self.db:
            self.db.execute("DELETE FROM results WHERE sweep = ?", (sweep,))
            self.db.execute("DELETE FROM timings WHERE sweep = ?", (sweep,))
            self.db.execute("DELETE FROM written WHERE sweep = ?", (sweep,))

    def results(self, sweep: int) -> list[dict[str, Any]]:
        """All results of a sweep in enumeration order, with their timings."""
        names = ",".join(f'r."{c}"' for c in COLUMNS)
        cursor = self.db.execute(
            f"SELECT {names}, t.seconds FROM results r LEFT JOIN timings t "
            f"ON t.sweep = r.sweep AND t.key = r.key WHERE r.sweep = ? ORDER BY r.\"index\"",
            (sweep,),
        )
        out = []
        for row in cursor:
            record = dict(zip((*COLUMNS, "seconds"), row, strict=True))
            for c in JSON_COLUMNS:
                if record[c] is not None:
                    record[c] = json.loads(record[c])
            out.append(record)
        return out
