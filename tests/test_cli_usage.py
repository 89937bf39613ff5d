"""``python -m virtual_actuators`` answers every bad option value with a usage error.

Each bad command line runs in a subprocess, as a user types it: exit code 2, argparse's usage
line and a message naming the option on stderr, never a traceback. No demo runs to completion
here: every case fails before a simulation starts.
"""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import pytest

import virtual_actuators.__main__ as cli
from virtual_actuators.exceptions import InvalidInputError

pytestmark = [pytest.mark.slow]  # subprocesses or simulation: run with -m slow

MISSING = str(Path("/no/such/folder") / "out.json")

#: (arguments, text that stderr must contain: the option, and the bad value or the reason)
BAD = [
    (["demo", "turkey-walk", "--duration", "-5"], ["--duration", "'-5'", "> 0"]),
    (["demo", "turkey-walk", "--duration", "0"], ["--duration", "'0'"]),
    (["demo", "turkey-walk", "--duration", "nan"], ["--duration", "'nan'", "finite"]),
    (["demo", "turkey-walk", "--duration", "inf"], ["--duration", "'inf'"]),
    (["demo", "turkey-walk", "--duration", "five"], ["--duration", "'five'", "number"]),
    (["demo", "turkey-walk", "--duration", "1e12"], ["--duration", "'1e12'", "600"]),
    (["demo", "turkey-walk", "--duration", "0.0001"], ["--duration", "0.01"]),
    (["demo", "turkey-walk", "--speed", "-1"], ["--speed", "'-1'", "(0, 1.5]"]),
    (["demo", "flamingo-slopes", "--speed", "0"], ["--speed", "'0'"]),
    (["demo", "flamingo-slopes", "--speed", "nan"], ["--speed", "'nan'"]),
    (["demo", "turkey-walk", "--speed", "9"], ["--speed", "'9'"]),
    (["demo", "turkey-walk", "--terrain", "garbage"], ["--terrain", "'garbage'"]),
    (["demo", "turkey-walk", "--terrain", ""], ["--terrain", "Empty terrain"]),
    (["demo", "turkey-walk", "--terrain", "0:0,-1:0"], ["--terrain", "increasing"]),
    (["demo", "turkey-walk", "--terrain", "flat:nan"], ["--terrain", "'nan'"]),
    (["demo", "turkey-walk", "--terrain", "flat:1e300"], ["--terrain", "1000 m"]),
    (["demo", "stand", "--robot", "nosuchrobot"], ["--robot", "'nosuchrobot'", "Closest"]),
    (["demo", "stand", "--robot", "ur5_robot"], ["--robot", "has no feet", "--feet"]),
    (["demo", "stand", "--feet", "FL_FOOT,NOSE"], ["--feet", "'NOSE'"]),
    (["demo", "stand", "--feet", "FL_FOOT"], ["--feet", "two or more"]),
    (["demo", "turkey-walk", "--window", "5:2", "--plot", "x.png"], ["--window", "before"]),
    (["demo", "turkey-walk", "--window", "1:2"], ["--window", "--plot"]),
    (["demo", "stand", "--distribution", "qp"], ["--distribution", "only the walks"]),
    (["sweep", "turkey-walk", "--speed", "0.1:0.2:0"], ["--speed", "STEP"]),
    (["sweep", "turkey-walk", "--terrain", "moon"], ["--terrain"]),
    (["sweep", "turkey-walk", "--seeds", "0"], ["--seeds", ">= 1"]),
    (["sweep", "turkey-walk", "--speed", "0:1e300:1e-300"], ["--speed", "1000"]),
    (["sweep", "turkey-walk", "--speed", "0.5:0.3:0.1"], ["--speed", "below start"]),
    (["demo", "stand", "--robot", "~nosuchuserxyz/r.urdf"], ["--robot", "no robot named"]),
    (["demo", "turkey-walk", "--json", "a" * 5000], ["--json", "not a usable file path"]),
    (["demo", "stand", "--robot", __file__], ["--robot", "not well-formed XML"]),
    (["demo", "stand", "--speed", "0.5"], ["--speed", "only the walks"]),
    (["demo", "turkey-walk", "--robot", "solo12"], ["--robot", "only the stand demo"]),
    (["demo", "turkey-walk", "--json", MISSING], ["--json", "existing folder"]),
    (["demo", "turkey-walk", "--plot", "/"], ["--plot", "folder"]),
    (["demo", "turkey-walk", "--record", MISSING], ["--record", "existing folder"]),
    (["demo", "no-such-demo"], ["name", "'no-such-demo'"]),
    (["example", "no-such-example"], ["name", "'no-such-example'"]),
    (["example", "millipede", "--record", ""], ["--record", "empty"]),
    (["--duration", "-5"], ["--duration", "'-5'"]),  # options alone mean `demo`
    (["demo", "legged", "--push", "120"], ["--push", "N@T[:DEG]"]),
    (["demo", "legged", "--gait", "gallop"], ["--gait", "'gallop'"]),
    (["demo", "turkey-walk", "--gait", "trot"], ["--gait", "legged"]),
    (["demo", "turkey-walk", "--realtime"], ["--realtime", "--viz"]),
    (["demo", "legged", "--realtime", "--record", "r.html"], ["--realtime", "--viz"]),
    (
        ["demo", "turkey-walk", "--window", "5:8", "--duration", "2", "--plot", "w.png"],
        ["--window", "starts at 5 s", "lasts 2 s"],
    ),
    (
        ["demo", "flamingo-slopes", "--window", "500:", "--plot", "w.png"],
        ["--window", "500 s", "default", "--duration"],
    ),
    (["demo", "turkey-walk", "--window", ":-1", "--plot", "w.png"], ["--window", "before"]),
]


def _short(argument: str) -> str:
    """A test id's word: a long path becomes its file name."""
    return Path(argument).name if len(argument) > 30 else argument


def run_cli(arguments: list[str]) -> subprocess.CompletedProcess[str]:
    """``python -m virtual_actuators ARGUMENTS`` in a subprocess, from a neutral folder."""
    env = {**os.environ, "PYTHONWARNINGS": "ignore"}
    return subprocess.run(
        [sys.executable, "-m", "virtual_actuators", *arguments],
        capture_output=True,
        text=True,
        timeout=120,
        env=env,
        stdin=subprocess.DEVNULL,
        check=False,
    )


@pytest.mark.parametrize(
    ("arguments", "expected"), BAD, ids=[" ".join(map(_short, a)) for a, _ in BAD]
)
def test_bad_value_is_a_usage_error(arguments: list[str], expected: list[str]) -> None:
    run = run_cli(arguments)
    assert run.returncode == 2, run.stderr
    assert "usage:" in run.stderr
    assert "Traceback" not in run.stderr, run.stderr
    assert "error: argument" in run.stderr
    for text in expected:
        assert text in run.stderr, (text, run.stderr)


def test_help_exits_zero() -> None:
    run = run_cli(["demo", "--help"])
    assert run.returncode == 0
    assert "usage:" in run.stdout and "--duration" in run.stdout and "--robot" in run.stdout


def test_parsing_imports_nothing_heavy() -> None:
    """Rejecting --duration / --speed must not import MuJoCo, matplotlib or the viewer."""
    code = (
        "import sys\n"
        "from virtual_actuators.__main__ import main\n"
        "for argv in (['demo', '--duration', '-5'], ['demo', '--speed', 'x']):\n"
        "    try:\n"
        "        main(argv)\n"
        "    except SystemExit as exit:\n"
        "        assert exit.code == 2, exit.code\n"
        "heavy = [m for m in ('mujoco', 'matplotlib', 'meshcat') if m in sys.modules]\n"
        "print(heavy)\n"
    )
    run = subprocess.run(
        [sys.executable, "-c", code], capture_output=True, text=True, timeout=120, check=False
    )
    assert run.returncode == 0, run.stderr
    assert run.stdout.strip() == "[]"


def test_parser_imports_no_optional_package() -> None:
    """The CLI's parser module, ``--help`` and ``robots`` load no MuJoCo, matplotlib or tqdm."""
    code = (
        "import sys, contextlib, io\n"
        "import virtual_actuators.cli.options as options\n"
        "options.build_parser()\n"
        "from virtual_actuators.__main__ import main\n"
        "with contextlib.redirect_stdout(io.StringIO()):\n"
        "    main(['robots'])\n"
        "optional = ('mujoco', 'matplotlib', 'tqdm', 'meshcat')\n"
        "print([m for m in optional if m in sys.modules])\n"
    )
    run = subprocess.run(
        [sys.executable, "-c", code], capture_output=True, text=True, timeout=120, check=False
    )
    assert run.returncode == 0, run.stderr
    assert run.stdout.strip() == "[]"


def test_library_error_at_run_time_is_a_usage_error(
    monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]
) -> None:
    """A VirtualActuatorError raised after parsing becomes ``parser.error`` (exit 2)."""

    def fail(args: object) -> int:
        raise InvalidInputError("speed 0.5 m/s is too fast for this terrain.")

    monkeypatch.setattr(cli, "run", fail)
    with pytest.raises(SystemExit) as exit_info:
        cli.main(["demo", "turkey-walk", "--speed", "0.5"])  # inside its range
    assert exit_info.value.code == 2
    err = capsys.readouterr().err
    assert "usage:" in err and "too fast for this terrain" in err


def test_other_exceptions_propagate(monkeypatch: pytest.MonkeyPatch) -> None:
    """A bug (any other exception type) is not disguised as a usage error."""

    def fail(args: object) -> int:
        raise ZeroDivisionError("a genuine bug")

    monkeypatch.setattr(cli, "run", fail)
    with pytest.raises(ZeroDivisionError, match="a genuine bug"):
        cli.main(["demo", "turkey-walk", "--duration", "1"])
