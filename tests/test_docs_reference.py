"""Every public name of ``virtual_actuators`` has an entry in the API reference (docs/reference)."""

from __future__ import annotations

from pathlib import Path

import virtual_actuators as va

REFERENCE = Path(__file__).resolve().parents[1] / "docs" / "reference"


def test_every_public_name_is_in_the_reference():
    text = "".join(page.read_text() for page in REFERENCE.glob("*.md"))
    missing = [name for name in va.__all__ if f"::: virtual_actuators.{name}" not in text]
    assert missing == [], f"add these to docs/reference: {missing}"
