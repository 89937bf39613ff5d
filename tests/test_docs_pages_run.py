"""The contributing pages' code runs as written and does what the page says."""

from __future__ import annotations

import contextlib
import io
import re
from pathlib import Path

import pytest

from virtual_actuators.core import CORE

DOCS = Path(__file__).resolve().parents[1] / "docs"


@pytest.mark.skipif(CORE is None or not hasattr(CORE, "PlanMachine"), reason="no compiled core")
def test_the_add_a_gait_page_lowers_its_gait_whole():
    (code,) = re.findall(r"```python\n(.*?)```", (DOCS / "contributing/add-a-gait.md").read_text(),
                         re.S)  # fmt: skip
    printed, scope = io.StringIO(), {}
    with contextlib.redirect_stdout(printed):
        exec(compile(code, "add-a-gait.md", "exec"), scope)
    assert "CompiledMachine(state='stand', 0 Python pieces)" in printed.getvalue()
    assert scope["machine"].compiled.pieces == []
    assert scope["memory"].low == pytest.approx(0.24)  # the hook ran in the core
