"""``gather_verify.check`` is the API's entry point: a plain function (docs/api.md), whichever
of the package's lazy name or an import of its module comes first."""

from __future__ import annotations

import subprocess
import sys

import pytest

ORDERS = {
    "the module first": "import gather_verify.plane_check as m\nimport gather_verify as gv\n",
    "the lazy name first": "import gather_verify as gv\nf = gv.check\n"
                           "import gather_verify.plane_check as m\n",
    "from the package": "from gather_verify import check as f\nimport gather_verify as gv\n"
                        "import gather_verify.plane_check as m\n",
}


@pytest.mark.parametrize("order", sorted(ORDERS))
def test_gather_verify_check_is_a_plain_function(order: str) -> None:
    code = ORDERS[order] + (
        "import types\n"
        "assert isinstance(gv.check, types.FunctionType) and gv.check is m.check, gv.check\n"
        "r = gv.check(robots=[(0, 0), (2, 1)], meeting=[(1, 1)], algorithm='go-to-target',"
        " scheduler='fsync')\n"
        "assert isinstance(r, m.CheckReport) and r.verdict == 'VERIFIED', r\n"
        "assert not callable(m), 'a module is no function'\n")
    run = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         timeout=120)
    assert run.returncode == 0, run.stderr


def test_a_bad_call_is_one_line_whatever_binds_the_name() -> None:
    import gather_verify as gv
    from gather_verify.errors import InvalidInput

    with pytest.raises(InvalidInput, match="robots and meeting"):
        gv.check(robots=[(0, 0)])
