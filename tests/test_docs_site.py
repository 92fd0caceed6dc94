"""The docs site: it builds with warnings as errors, every page is in it, its links hold,
and the pages read as documentation, not as a development diary.

The whole build (`test_the_site_builds_with_warnings_as_errors`) takes about half a minute
of CPU, so it is marked slow; `.ci/run` builds the site itself, with the same options. The
other tests are fast and need no Sphinx.
"""

from __future__ import annotations

import importlib.util
import re
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent
DOCS = ROOT / "docs"
SPHINX = [sys.executable, "-m", "sphinx", "-W", "-n", "--keep-going", "-q"]

needs_sphinx = pytest.mark.skipif(
    not all(importlib.util.find_spec(m) for m in ("sphinx", "myst_parser")),
    reason="Sphinx and MyST are not installed: pip install -e '.[docs]'")


def pages() -> list[Path]:
    """Every Markdown page of the site (generated pages and build output aside)."""
    return sorted(p for p in DOCS.rglob("*.md")
                  if not {"_build", "_generated", "examples", "img"} & set(p.relative_to(DOCS).parts))


@pytest.mark.slow
@needs_sphinx
def test_the_site_builds_with_warnings_as_errors(tmp_path):
    html = tmp_path / "html"
    result = subprocess.run([*SPHINX, "-b", "html", "-d", str(tmp_path / "doctrees"),
                             str(DOCS), str(html)], cwd=ROOT, capture_output=True, text=True)
    assert result.returncode == 0, result.stderr
    assert "WARNING" not in result.stderr, result.stderr
    for page in pages():
        built = html / page.relative_to(DOCS).with_suffix(".html")
        assert built.is_file(), f"{page} was not built"
    from gather_verify.cli import COMMANDS

    cli = (html / "reference" / "cli.html").read_text(encoding="utf-8")
    for command in COMMANDS:  # the command line's reference is generated from its parser
        assert f'id="command-{command}"' in cli, command
    assert "EXIT_NO_LONGER_REPRODUCES" in cli
    api = html / "reference" / "_generated"
    assert (api / "gather_verify.plane_check.html").is_file()
    assert (api / "schedulers.base.html").is_file()


def test_every_page_is_in_a_toctree_of_the_site():
    listed: set[Path] = set()
    for page in pages():
        for block in re.findall(r"```\{toctree\}\n(.*?)```", page.read_text(encoding="utf-8"), re.S):
            for line in block.splitlines():
                entry = line.strip()
                if entry and not entry.startswith(":"):
                    listed.add((page.parent / f"{entry}.md").resolve())
    missing = [str(p.relative_to(DOCS)) for p in pages()
               if p.resolve() not in listed and p != DOCS / "index.md"]
    assert not missing, f"pages in no toctree of docs/index.md: {missing}"


LINK = re.compile(r"!?\[[^\]]*\]\(([^)\s]+)\)")


def test_the_relative_links_of_the_readme_and_the_pages_name_files_that_exist():
    """What GitHub shows: every relative Markdown link or image names a file of the
    repository (the site build also checks the anchors)."""
    broken = []
    for page in [ROOT / "README.md", *pages()]:
        text = re.sub(r"```.*?```", "", page.read_text(encoding="utf-8"), flags=re.S)
        for target in LINK.findall(text):
            path = target.split("#")[0]
            if not path or re.match(r"[a-z]+:", path):
                continue
            if not (page.parent / path).exists():
                broken.append(f"{page.relative_to(ROOT)}: {target}")
    assert not broken, broken


DIARY = [
    (re.compile(r"(?<![/\w])issues? ?-?#?\d+(?!\w|\.\w)", re.I), "an issue number"),  # not a file name
    (re.compile(r"\b(first|second|third|fourth|fifth|sixth|last|next|this|that) round\b", re.I),
     "a development round"),
    (re.compile(r"\brounds? of (work|development)\b", re.I), "a development round"),
    (re.compile(r"(?<![\w.])/(work|tmp)/"), "a path of one machine"),
    (re.compile(r"\b(this|a slower|a faster) (VM|day)\b|\bengineers?\b|\bsessions? shared\b", re.I),
     "a run diary"),
]


def test_the_docs_are_not_a_development_diary():
    """No issue numbers, development rounds, run diaries or paths of one machine in the
    README or the pages (the configuration classes I11 ... I42 are the paper's, and the
    rounds of FSYNC and SSYNC are the model's)."""
    found = []
    for page in [ROOT / "README.md", *pages()]:
        for number, line in enumerate(page.read_text(encoding="utf-8").splitlines(), 1):
            for pattern, what in DIARY:
                if pattern.search(line):
                    found.append(f"{page.relative_to(ROOT)}:{number}: {what}: {line.strip()}")
    assert not found, "\n".join(found)


def test_the_link_checker_finds_a_missing_page_and_a_missing_anchor(tmp_path):
    sys.path.insert(0, str(DOCS / "_ext"))
    try:
        from gv_links import broken_links
    finally:
        sys.path.remove(str(DOCS / "_ext"))
    (tmp_path / "a.html").write_text('<h1 id="top">A</h1><a href="b.html#here">b</a>'
                                     '<a href="b.html#gone">b</a><a href="c.html">c</a>'
                                     '<a href="#top">top</a><a href="https://x.org/">web</a>')
    (tmp_path / "b.html").write_text('<p id="here">B</p>')
    assert broken_links(tmp_path) == ["a.html: b.html#gone (no such id)",
                                      "a.html: c.html (no such file)"]


@needs_sphinx
def test_every_exit_code_of_the_command_line_has_a_meaning_on_the_reference_page():
    sys.path.insert(0, str(DOCS / "_ext"))
    try:
        from gv_cli import MEANINGS, command_codes, exit_codes
    finally:
        sys.path.remove(str(DOCS / "_ext"))
    codes = exit_codes()
    assert set(codes) == set(MEANINGS)
    assert command_codes("gather_verify.cli.replay", codes) == {1, 5}
    assert command_codes("gather_verify.cli.check", codes) >= {0, 1, 3, 4}


def tutorial_steps(page: Path) -> list[tuple[str, str, str]]:
    """The steps of a tutorial, in order: ``("save", file, text)`` for each "Save this as
    `FILE`" (or "Change `FILE` to:") and the block after it, ``("run", command, expected)``
    for each indented command, with the first line of the output block after it."""
    lines = page.read_text(encoding="utf-8").splitlines()
    steps: list[tuple[str, str, str]] = []
    i = 0
    while i < len(lines):
        named = re.search(r"(?:Save this as|Change) `([^`]+)`", lines[i])
        if named:
            start = next(k for k in range(i + 1, len(lines)) if lines[k].startswith("```"))
            end = next(k for k in range(start + 1, len(lines)) if lines[k].startswith("```"))
            steps.append(("save", named.group(1), "\n".join(lines[start + 1:end]) + "\n"))
            i = end + 1
            continue
        if re.match(r"    (gather-verify|mkdir) ", lines[i]):
            command = lines[i].strip()
            while command.endswith("\\"):
                i += 1
                command = command[:-1] + lines[i].strip()
            k = i + 1
            while k < len(lines) and not lines[k].strip():
                k += 1
            expected = lines[k + 1] if k < len(lines) and lines[k] == "```text" else ""
            steps.append(("run", command, expected))
        i += 1
    return steps


@pytest.mark.parametrize("name", ["your-algorithm", "ring-algorithm"])
def test_a_tutorial_followed_word_for_word_in_a_new_folder_works(name, tmp_path, monkeypatch,
                                                                   capsys):
    """Every file the tutorial saves, every command it runs, in a folder outside the
    project; each command's first line of output is the one the page shows ("..." stands
    for a path or a time)."""
    import shlex

    from gather_verify.cli import main

    steps = tutorial_steps(DOCS / "tutorials" / f"{name}.md")
    assert [kind for kind, *_ in steps].count("run") >= 4
    monkeypatch.chdir(tmp_path)
    for kind, what, body in steps:
        if kind == "save":
            Path(what).write_text(body, encoding="utf-8")
            continue
        if what.startswith("mkdir "):
            folder = what.split()[1]
            Path(folder).mkdir()
            monkeypatch.chdir(folder)
            continue
        capsys.readouterr()
        code = main(shlex.split(what)[1:])
        out = capsys.readouterr().out
        assert code in (0, 1), (what, code, out)
        if body:
            pattern = ".*".join(re.escape(part) for part in body.split("..."))
            assert re.fullmatch(pattern, out.splitlines()[0]), (what, body, out)
