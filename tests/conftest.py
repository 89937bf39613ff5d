"""pytest set-up: the suite's hypothesis profile (the oracles live in ``oracles.py``).

Under CI (``CI=true``) the session fails when the compiled core (``virtual_actuators._core``) is
not built: the suite would otherwise test the numpy paths only, and the tests of the core
(``test_core_parity*.py`` and others) would be skipped, unless ``VA_CORE=0`` asks for exactly
that (CI's second run, of the fast tests, keeps the fallback true).
"""

import os

import pytest
from hypothesis import HealthCheck, settings

from virtual_actuators import core

settings.register_profile(
    "ci",
    derandomize=True,
    deadline=None,
    max_examples=25,
    print_blob=True,
    suppress_health_check=[HealthCheck.too_slow],
)
settings.load_profile("ci")


def pytest_sessionstart(session: pytest.Session) -> None:
    """Stop a CI session without the compiled core (``VA_CORE=0`` asks for the reference)."""
    if (
        os.environ.get("CI", "").lower() == "true"
        and core.CORE is None
        and os.environ.get("VA_CORE", "1") != "0"
    ):
        pytest.exit(
            "CI=true but virtual_actuators._core is not built: install the package with pip "
            "(pip install -e .) or run tools/build_core.sh",
            returncode=1,
        )
