"""``python -m tools.move_ratios``: the largest moves / (D·n) per class of stored sweeps, over
the VERIFIED configurations and over every measured one, equal to the rows it reads."""

from __future__ import annotations

import json

from gather_verify.cli import main
from gather_verify.sweeps.store import Store
from tools.move_ratios import main as ratios_main
from tools.move_ratios import ratios


def test_the_ratios_are_those_of_the_stored_rows(tmp_path, capsys):
    db = str(tmp_path / "r.sqlite")
    assert main(["sweep", "--robots", "2", "--meeting", "2", "--box", "3x2", "--algorithm",
                 "paper", "--db", db, "--workers", "1", "--json"]) == 1
    summary = json.loads(capsys.readouterr().out)
    column = ratios(db)
    assert column["covers"] == [[[3, 2], 2, 2]]
    store = Store(db, read_only=True)
    rows = [r for i, _ in store.sweeps() for r in store.results(i)]
    store.close()
    for name, one in column["classes"].items():
        mine = [r for r in rows if r["class"] == name]
        assert one["configurations"] == len(mine)
        assert one["all"] == summary["max_ratio"].get(name)
        verified = [r["ratio"] for r in mine if r["verdict"] == "VERIFIED"]
        assert one["verified"] == (max(verified) if verified else None)
        assert one["unmeasured"] == sum(r["ratio"] is None for r in mine)
    assert any(one["unmeasured"] for one in column["classes"].values())  # the I22 failures
    assert ratios_main([db]) == 0
    assert "3x2 n 2 m 2" in capsys.readouterr().out
    assert ratios_main([str(tmp_path / "none.sqlite")]) == 2
    assert ratios(db, meeting=range(3, 5)) == {"database": db, "covers": [], "classes": {}}
