"""A new user's pass over machine files, part programs and the examples (pass 11): each test
names a case that was wrong or unsettled, and the behaviour FANUC's practice asks for."""

from __future__ import annotations

from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent
NC = ROOT / "focas_net" / "sim" / "nc"


@pytest.mark.parametrize("module", sorted(p.name for p in NC.glob("*.py")), ids=str)
def test_nc_modules_are_short_and_in_the_architecture(module: str) -> None:
    """Each module of the NC package stays under 800 lines (the interpreter had 804: its
    settings and its actions are modules of their own) and is named in the architecture."""
    lines = (NC / module).read_text(encoding="utf-8").count("\n")
    assert lines <= 800, f"{module} has {lines} lines"
    if module != "__init__.py":
        assert module in (ROOT / "docs" / "architecture.md").read_text(encoding="utf-8")
