"""The page's actions in tests: what the page says of a refused one."""

from __future__ import annotations

from typing import Any

import pytest

from focas_net.sim import MachineError
from focas_net.web import ActionError, Station, perform


def page_refusal(station: Station, action: str, args: dict[str, Any]) -> str:
    """The words the page shows for ``action`` refused (an argument's or the machine's)."""
    with pytest.raises((ActionError, MachineError)) as refused:
        perform(station, action, args)
    exc = refused.value
    return exc.detail if isinstance(exc, MachineError) else str(exc)
