"""Reports of stored sweeps: text tables, an HTML page, and a plot of moves against D·n."""

from __future__ import annotations

import html
import json
from pathlib import Path
from typing import Any

from gather_verify.errors import InvalidInput
from gather_verify.sweeps.store import Store
from gather_verify.sweeps.sweep import summarise


def load_sweeps(db_path: str) -> list[tuple[dict[str, Any], list[dict[str, Any]]]]:
    """Every sweep in a results database with its rows."""
    if not Path(db_path).is_file():
        raise InvalidInput(f"{db_path}: no such results database")
    store = Store(db_path)
    try:
        return [(settings, store.results(i)) for i, settings in store.sweeps()]
    finally:
        store.close()


def summaries(db_path: str) -> list[dict[str, Any]]:
    out = []
    for settings, rows in load_sweeps(db_path):
        summary = summarise(rows)
        summary["settings"] = settings
        out.append(summary)
    return out


def write_html(db_path: str, out: str, svg_dir: str | None = None) -> None:
    """One page: per sweep, the class x verdict table and every counterexample,
    each linked to its SVG storyboard (written beside the page)."""
    from gather_verify.scenario import VERDICTS

    page = Path(out)
    svg_folder = Path(svg_dir) if svg_dir else page.with_suffix("").with_name(page.stem + "-traces")
    parts = ["<!doctype html><meta charset=utf-8><title>gather-verify report</title>",
             "<style>body{font-family:sans-serif}td,th{padding:2px 8px;text-align:right}"
             "th{background:#eee}</style><h1>gather-verify report</h1>"]
    for number, (settings, rows) in enumerate(load_sweeps(db_path)):
        s = summarise(rows)
        parts.append(f"<h2>Sweep {number + 1}</h2><pre>{html.escape(json.dumps(settings, sort_keys=True))}</pre>")
        parts.append("<table><tr><th>class</th><th>count</th>"
                     + "".join(f"<th>{v}</th>" for v in VERDICTS) + "<th>max ratio</th></tr>")
        for name, count in s["classes"].items():
            if count:
                by = s["verdicts"].get(name, {})
                ratio = s["max_ratio"].get(name)
                parts.append(f"<tr><td>{name}</td><td>{count}</td>"
                             + "".join(f"<td>{by.get(v, 0)}</td>" for v in VERDICTS)
                             + f"<td>{'' if ratio is None else f'{ratio:.2f}'}</td></tr>")
        parts.append("</table>")
        bad = [r for r in rows if r["verdict"] == "VIOLATED"]
        if bad:
            parts.append("<h3>Counterexamples</h3><ul>")
            for r in bad:
                link = ""
                if r.get("trace"):
                    svg_folder.mkdir(parents=True, exist_ok=True)
                    name = f"sweep{number + 1}-{r['index']}.svg"
                    _write_svg(r["trace"], svg_folder / name)
                    link = f' <a href="{html.escape(svg_folder.name)}/{name}">trace</a>'
                parts.append(f"<li>{html.escape(r['class'])} {html.escape(str(r['property']))}: "
                             f"robots {r['robots']} meeting {r['meeting_nodes']}{link}</li>")
            parts.append("</ul>")
    page.parent.mkdir(parents=True, exist_ok=True)
    page.write_text("\n".join(parts), encoding="utf-8")


def _write_svg(trace: dict[str, Any], path: Path) -> None:
    from gather_verify.render import trace_svg

    path.write_text(trace_svg(trace), encoding="utf-8")


def write_plot(db_path: str, out: str) -> None:
    """Scatter of max moves against D·n for every verified configuration (matplotlib)."""
    try:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        raise InvalidInput("--plot needs matplotlib: pip install 'gather-verify[plot]'") from None
    fig, ax = plt.subplots(figsize=(6, 4.5))
    for settings, rows in load_sweeps(db_path):
        xs = [r["D"] * r["n"] for r in rows if r.get("max_moves") is not None and r.get("D") is not None]
        ys = [r["max_moves"] for r in rows if r.get("max_moves") is not None and r.get("D") is not None]
        ax.scatter(xs, ys, s=10, alpha=0.5,
                   label=f"{settings.get('algorithm')} {settings.get('scheduler')}")
    top = max([1, *ax.get_xlim()])
    ax.plot([0, top], [0, 4 * top], "k--", linewidth=0.8, label="4·D·n")
    ax.set_xlabel("D·n")
    ax.set_ylabel("max moves over all executions")
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(out)
    plt.close(fig)
