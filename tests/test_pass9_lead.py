"""A usage error keeps what was typed as it was typed: runs of spaces inside a value stay."""

from __future__ import annotations

import pytest
from cli_support import fails

from focas_net.cli import EXIT_USAGE


@pytest.mark.parametrize("typed", [" ", "  ", "   "])
async def test_a_usage_error_quotes_a_host_of_spaces_as_typed(typed: str) -> None:
    line = await fails(EXIT_USAGE, "status", "--host", typed, prefix="focas-net")
    assert f"empty host {typed!r}" in line


async def test_a_usage_error_is_still_one_line() -> None:
    line = await fails(EXIT_USAGE, "status", "--port", "x" * 200, prefix="focas-net")
    assert "x" * 200 in line
