"""The command line answers a bad option value with a usage error (exit 2), never a traceback."""

from __future__ import annotations

import subprocess
import sys

import pytest

import virtual_actuators.__main__ as cli

BAD = [
    (["demo", "turkey-walk", "--duration", "-5"], "--duration"),
    (["demo", "turkey-walk", "--duration", "0"], "--duration"),
    (["demo", "turkey-walk", "--duration", "nan"], "--duration"),
    (["demo", "turkey-walk", "--duration", "inf"], "--duration"),
    (["demo", "flamingo-slopes", "--speed", "-1"], "--speed"),
    (["demo", "--speed", "abc"], "--speed"),
    (["demo", "--speed", "7"], "--speed"),
    (["demo", "--terrain", "garbage"], "--terrain"),
    (["demo", "--terrain", "0:0,-1:0"], "--terrain"),
    (["demo", "stand", "--robot", "nosuchrobot"], "--robot"),
    (["demo", "--json", "/no/such/folder/metrics.json"], "--json"),
    (["demo", "--plot", "/"], "--plot"),
    (["demo", "--record", "/no/such/folder/run.html"], "--record"),
    (["demo", "no-such-demo"], "name"),
    (["example", "no-such-example"], "name"),
]


@pytest.mark.parametrize(("argv", "option"), BAD, ids=[" ".join(a) for a, _ in BAD])
def test_bad_option_is_a_usage_error(argv, option, capsys):
    with pytest.raises(SystemExit) as exit_info:
        cli.main(argv)
    assert exit_info.value.code == 2
    err = capsys.readouterr().err
    assert "usage:" in err and option in err and "Traceback" not in err


def test_library_error_from_an_argument_is_a_usage_error(capsys):
    """A robot that loads but has no *_FOOT frames: the library's typed error, exit 2."""
    with pytest.raises(SystemExit) as exit_info:
        cli.main(["demo", "stand", "--robot", "ur5_robot"])
    assert exit_info.value.code == 2
    err = capsys.readouterr().err
    assert "usage:" in err and "Traceback" not in err


def test_documented_example_in_a_subprocess():
    """The issue's own command, as a user types it."""
    run = subprocess.run(
        [sys.executable, "-m", "virtual_actuators", "demo", "turkey-walk", "--duration", "-5"],
        capture_output=True,
        text=True,
        timeout=120,
    )
    assert run.returncode == 2
    assert "usage:" in run.stderr and "--duration" in run.stderr
    assert "Traceback" not in run.stderr
