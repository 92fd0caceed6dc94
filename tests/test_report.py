"""The HTML report and the plot of a results database: one page per batch, a settings table,
the class x verdict x property table with links to filtered lists, thumbnails opening
viewers, the plot coloured by verdict with the bound line."""

from __future__ import annotations

import json
import re
from pathlib import Path

import pytest

from gather_verify.cli import main
from gather_verify.sweeps.report import batches, write_html, write_plot
from gather_verify.sweeps.sweep import SweepSettings, run_sweep


def sweep(db: Path, algorithm: str = "broken-away") -> None:
    """A batch of two quick sweeps (n = 2, m = 1 and 2, box 2 x 2) with violations
    (move-bound cycles and a deadlock), NOT-APPLICABLE configurations and, for
    go-to-target, VERIFIED ones."""
    run_sweep([SweepSettings(robots=2, meeting=m, box=(2, 2), algorithm=algorithm,
                             scheduler="async", max_seconds=20) for m in (1, 2)],
              str(db), workers=1, progress=False)


@pytest.fixture(scope="module")
def db(tmp_path_factory) -> Path:
    path = tmp_path_factory.mktemp("report") / "r.sqlite"
    sweep(path)
    return path


def test_batches_group_the_sweeps_of_one_command(db, tmp_path):
    groups = batches(str(db))
    assert len(groups) == 1 and len(groups[0][1]) == 2
    assert "robots" not in groups[0][0] and groups[0][0]["algorithm"] == "broken-away"


def test_one_page_with_settings_table_links_and_viewers(db, tmp_path):
    out = tmp_path / "report.html"
    written = write_html(str(db), str(out))
    assert written == [out]
    page = out.read_text()
    assert "{&quot;" not in page and '{"algorithm"' not in page  # no raw JSON settings
    assert re.search(r"<th>algorithm</th><td>broken-away</td>", page)
    assert re.search(r"<th>box</th><td>2 × 2</td>", page)
    # every count links to a list that exists, holding that many configurations
    links = re.findall(r"<a href='#(list-[^']+)'>(\d+)</a>", page)
    assert links
    for anchor, count in links:
        section = re.search(rf"<section class='list' id='{re.escape(anchor)}'>(.*?)</section>",
                            page, re.S)
        assert section, anchor
        assert section.group(1).count("<tr><td>") == int(count)
    # a thumbnail for each (class, property) with a counterexample, opening its viewer
    viewers = re.findall(r"<figure><a href='([^']+)'", page)
    assert viewers and all((tmp_path / v).is_file() for v in viewers)
    assert all("trace-data" in (tmp_path / v).read_text() for v in viewers)
    from gather_verify.sweeps.report import load_sweeps

    pairs = {(r["class"], r["property"]) for _, rs in load_sweeps(str(db)) for r in rs
             if r["verdict"] == "VIOLATED" and r.get("trace")}
    assert page.count("<figure>") == len(pairs) >= 2
    assert (tmp_path / "report-files" / "plot-1.png").is_file()


def test_long_lists_are_cut_and_say_so(db, tmp_path, monkeypatch):
    import gather_verify.sweeps.report as report

    monkeypatch.setattr(report, "LIST_LIMIT", 1)
    out = tmp_path / "r.html"
    write_html(str(db), str(out))
    page = out.read_text()
    cut = [int(n) for _, n in re.findall(r"<a href='#(list-[^']+)'>(\d+)</a>", page) if int(n) > 1]
    assert cut and page.count("The first 1 of ") == len(cut)
    for section in re.findall(r"<section class='list'.*?</section>", page, re.S):
        assert section.count("<tr><td>") == 1


def test_smallest_counterexample_is_shown(db, tmp_path):
    from gather_verify.sweeps.report import _smallest, load_sweeps

    rows = [r for _, rs in load_sweeps(str(db)) for r in rs if r["verdict"] == "VIOLATED"]
    best = _smallest(rows)
    assert all(len(best["trace"]["steps"]) <= len(r["trace"]["steps"]) for r in rows)


def test_several_batches_get_an_index_and_one_page_each(tmp_path):
    db = tmp_path / "two.sqlite"
    sweep(db)
    sweep(db, "go-to-target")
    out = tmp_path / "report.html"
    written = write_html(str(db), str(out))
    assert [p.name for p in written] == ["report.html", "report-1.html", "report-2.html"]
    index = out.read_text()
    assert "report-1.html" in index and "report-2.html" in index
    second = (tmp_path / "report-2.html").read_text()
    assert "go-to-target" in second and "VERIFIED" in second


def test_plot_has_one_legend_entry_per_series_and_the_bound(tmp_path):
    db = tmp_path / "two.sqlite"
    sweep(db)
    sweep(db, "go-to-target")
    legend = write_plot(str(db), str(tmp_path / "p.png"))
    assert len(legend) == len(set(legend))
    assert "bound 4·D·n" in legend
    assert any("VERIFIED" in x for x in legend) and any("VIOLATED" in x for x in legend)
    assert (tmp_path / "p.png").stat().st_size > 0


def test_cli_report_html(db, tmp_path, capsys):
    out = tmp_path / "r.html"
    assert main(["report", "--db", str(db), "--html", str(out)]) == 0
    assert "Verdicts" in out.read_text()


def test_browser_report_counts_open_lists_and_thumbnails_open_viewers(db, web, tmp_path):
    out = tmp_path / "report.html"
    write_html(str(db), str(out))
    page = web.page
    page.goto(out.as_uri())
    first = page.query_selector("table.verdicts a")
    anchor = first.get_attribute("href")[1:]
    assert not page.is_visible(f"#{anchor}")
    first.click()
    assert page.is_visible(f"#{anchor}")  # the filtered list shows
    rows = page.eval_on_selector_all(f"#{anchor} tr", "rs => rs.length") - 1
    assert rows == int(first.inner_text())
    page.click("figure a")  # a thumbnail opens its viewer
    assert page.url.endswith(".html") and "report-files" in page.url
    assert page.is_visible("#now")
    assert web.errors == [] and web.remote == []


def test_the_index_tells_the_batches_of_an_edited_algorithm_apart(tmp_path, capsys,
                                                                  monkeypatch):
    """Each batch names its fingerprint, when its rows were written and whether it is the
    code on disk now: after an edit, the old batch is older code and the new one current.
    ``--algorithm`` keeps one algorithm's sweeps."""
    import sqlite3

    alg = tmp_path / "walk.py"
    alg.write_text("from gather_verify.algorithms.go_to_target import GoToTarget\n\n\n"
                   "class Walk(GoToTarget):\n    name = 'walk'\n")
    db = tmp_path / "r.sqlite"
    sweep(db, f"{alg}:Walk")
    alg.write_text(alg.read_text() + "# edited\n")
    sweep(db, f"{alg}:Walk")
    sweep(db, "go-to-target")
    out = tmp_path / "report.html"
    write_html(str(db), str(out))
    items = re.findall(r"<li>.*?</li>", out.read_text())
    assert len(items) == 3
    tags = [re.search(r"<span class='code (\w+)'[^>]*>(.*?)</span>", li).groups() for li in items]
    assert [kind for kind, _ in tags] == ["older", "current", "current"]
    fingerprints = [re.search(r"fingerprint (\w{8}) · written \d{4}-\d\d-\d\d \d\d:\d\d UTC",
                              text).group(1) for _, text in tags]
    assert len(set(fingerprints)) == 3
    assert "current" in (tmp_path / "report-2.html").read_text()  # and on the batch's page
    assert main(["report", "--db", str(db), "--algorithm", "Walk"]) == 0
    text = capsys.readouterr().out
    assert text.count("== sweep") == 4 and "go-to-target" not in text
    assert text.count("older code: not the code on disk now; rows written ") == 2
    assert text.count("current: the code on disk now; rows written ") == 2
    monkeypatch.chdir(tmp_path)  # a file named as on the command line, from where it is
    assert main(["report", "--db", str(db), "--algorithm", "walk.py:Walk", "--json"]) == 0
    found = json.loads(capsys.readouterr().out)["sweeps"]
    assert [s["current"] for s in found] == [False, False, True, True]
    assert all("written" not in s for s in found)  # wall-clock: only with --timings
    write_html(str(db), str(out), algorithm="go-to-target")
    assert "go-to-target" in out.read_text() and "walk.py" not in out.read_text()
    with sqlite3.connect(db) as con:  # a database written before the dates were kept
        con.execute("DROP TABLE written")
    main(["report", "--db", str(db), "--algorithm", "go-to-target"])
    assert "current: the code on disk now; written before dates were kept" in \
        capsys.readouterr().out
