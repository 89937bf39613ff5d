"""The command line answers a bad option value with a usage error (exit 2), never a traceback."""

from __future__ import annotations

import os
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
    (["demo", "stand", "--robot", ""], "--robot"),
    (["demo", "stand", "--robot", "   "], "--robot"),
    (["sweep", "turkey-walk", "--seeds", "100000000000"], "--seeds"),
    (["sweep", "turkey-walk", "--seeds", "1001"], "--seeds"),
    (["sweep", "turkey-walk", "--seeds", "9" * 5000], "--seeds"),
    (["sweep", "turkey-walk", "--workers", "100000"], "--workers"),
    (["sweep", "turkey-walk", "--plot", "map.nosuchformat"], "--plot"),
]


@pytest.mark.parametrize(("argv", "option"), BAD, ids=[" ".join(a)[:60] for a, _ in BAD])
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


# -- outputs: tried before the run, a usage error when they cannot be written ----------------------
UNWRITABLE = [
    (["demo", "turkey-walk", "--json", "/dev/full"], "--json", "/dev/full"),
    (["demo", "hexapod-walk", "--json", "/dev/full"], "--json", "/dev/full"),
    (["demo", "turkey-walk", "--json", "/proc/version"], "--json", "/proc/version"),
    (["demo", "turkey-walk", "--plot", "/proc/x.png"], "--plot", "/proc/x.png"),
    (["demo", "turkey-walk", "--record", "/proc/x.html"], "--record", "/proc/x.html"),
    (["example", "millipede", "--record", "/proc/x.html"], "--record", "/proc/x.html"),
    (["sweep", "turkey-walk", "--out", "/proc/s.csv"], "--out", "/proc/s.csv"),
    (["sweep", "turkey-walk", "--plot", "/proc/s.png"], "--plot", "/proc/s.png"),
]


@pytest.mark.skipif(
    not (os.path.exists("/dev/full") and os.path.exists("/proc/version")), reason="Linux paths"
)
@pytest.mark.parametrize(
    ("argv", "option", "path"), UNWRITABLE, ids=[" ".join(a[:2] + a[-2:]) for a, _, _ in UNWRITABLE]
)
def test_an_output_that_cannot_be_written_is_a_usage_error(argv, option, path, capsys):
    with pytest.raises(SystemExit) as exit_info:
        cli.main(argv)
    assert exit_info.value.code == 2
    err = capsys.readouterr().err
    assert "Traceback" not in err
    last = err.strip().splitlines()[-1]  # one line: the option, the path and the reason
    assert f"error: argument {option}: " in last and repr(path) in last and "cannot" in last


def test_trying_the_outputs_leaves_no_file_and_changes_none(tmp_path, capsys):
    """New outputs are not left behind; an existing one keeps its content (not truncated)."""
    new, kept = tmp_path / "new.json", tmp_path / "kept.png"
    kept.write_bytes(b"an earlier plot")
    parser, _ = cli.build_parser()
    args = parser.parse_args(["demo", "turkey-walk", "--json", str(new), "--plot", str(kept)])
    assert args.json == str(new) and args.plot == str(kept)
    assert not new.exists() and kept.read_bytes() == b"an earlier plot"
    with pytest.raises(SystemExit) as exit_info:  # a later option fails: nothing is written
        cli.main(["demo", "turkey-walk", "--json", str(new), "--plot", "/proc/x.png"])
    assert exit_info.value.code == 2
    assert sorted(p.name for p in tmp_path.iterdir()) == ["kept.png"]
    assert kept.read_bytes() == b"an earlier plot"


def test_a_sweep_grid_too_large_is_a_usage_error(capsys):
    """1000 seeds pass alone, but 141 speeds x 2 terrains x 1000 seeds is refused before a walk."""
    argv = ["sweep", "turkey-walk", "--speed", "0.1:1.5:0.01", "--terrain", "flat,rolling"]
    with pytest.raises(SystemExit) as exit_info:
        cli.main([*argv, "--seeds", "1000", "--out", os.devnull])
    assert exit_info.value.code == 2
    err = capsys.readouterr().err
    assert "--seeds" in err and "282000 walks" in err and "100000" in err
    assert "Traceback" not in err


@pytest.mark.slow
@pytest.mark.skipif(not hasattr(os, "fork"), reason="POSIX resource limits")
def test_a_write_that_fails_after_the_run_is_a_usage_error(tmp_path):
    """The file size limit lets the output be tried (an empty write) but not written at the end:
    exit 2 and one line naming --json and the path, not a traceback with exit 1 ("fell")."""
    import resource
    import signal

    def limit_file_size() -> None:
        signal.signal(signal.SIGXFSZ, signal.SIG_IGN)  # a write past the limit fails with EFBIG
        resource.setrlimit(resource.RLIMIT_FSIZE, (8, 8))

    path = tmp_path / "metrics.json"
    command = [sys.executable, "-m", "virtual_actuators", "demo", "turkey-walk"]
    command += ["--duration", "0.01", "--quiet", "--json", str(path)]
    # once without the limit, so that whatever the walk caches on disk (compiled bytecode) is
    # written before the limited run
    subprocess.run(command, capture_output=True, timeout=300, check=True)
    path.unlink()
    run = subprocess.run(
        command,
        capture_output=True,
        text=True,
        timeout=120,
        preexec_fn=limit_file_size,
        check=False,
    )
    assert run.returncode == 2, run.stderr
    assert "Traceback" not in run.stderr
    last = run.stderr.strip().splitlines()[-1]
    assert f"error: argument --json: cannot write {str(path)!r}: File too large" in last
    assert "m in 0.01 s" in run.stdout  # the run itself went through and printed its summary


# -- issue 35's first hour: robots that cannot walk, gaits that do not fit, speeds --------------
def _truncated_urdf(folder) -> str:
    """solo12's URDF cut off in its first lines (not well-formed XML)."""
    import virtual_actuators as va

    path = folder / "truncated.urdf"
    path.write_text(va.load_robot("solo12").urdf_path.read_text()[:600])
    return str(path)


FIRST_HOUR = [
    (["demo", "legged", "--robot", "ur5"], "--robot", ["'ur5' has no feet"]),
    (["demo", "balance", "--robot", "ur5"], "--robot", ["'ur5' has no feet"]),
    (["demo", "legged", "--robot", "ur5", "--feet", "tool0,wrist_3_link"], "--robot",
     ["'ur5' has a fixed base"]),
    (["demo", "legged", "--robot", "TRUNCATED"], "--robot", ["not well-formed XML"]),
    (["demo", "balance", "--robot", "TRUNCATED"], "--robot", ["not well-formed XML"]),
    (["demo", "stand", "--robot", "TRUNCATED", "--feet", "a,b"], "--robot",
     ["not well-formed XML"]),
    (["demo", "legged", "--robot", "solo12", "--gait", "tripod"], "--gait",
     ["three feet or more on each side", "the gaits that fit them are trot, pace, walk"]),
    (["demo", "legged", "--robot", "hexapod", "--gait", "trot"], "--gait",
     ["two feet on each side", "the gaits that fit them are pace, walk, tripod"]),
    (["demo", "legged", "--speed", "1.0"], "--speed", ["or --force-speed to run it anyway."]),
    (["demo", "legged", "--robot", "go2", "--speed", "2", "--force-speed"], "--speed",
     ["(0, 1.5]", "--force-speed does not lift it", "no walk here walks faster"]),
]  # fmt: skip


@pytest.mark.parametrize(
    ("argv", "option", "expected"), FIRST_HOUR, ids=[" ".join(a[1:]) for a, _, _ in FIRST_HOUR]
)
def test_first_hour_usage_errors_name_their_option_on_one_line(
    argv, option, expected, tmp_path, capsys
):
    argv = [_truncated_urdf(tmp_path) if word == "TRUNCATED" else word for word in argv]
    with pytest.raises(SystemExit) as exit_info:
        cli.main([*argv, "--quiet"] if argv[1] != "stand" else argv)
    assert exit_info.value.code == 2
    err = capsys.readouterr().err
    assert "Traceback" not in err and err.startswith("usage:")
    message = [line for line in err.splitlines() if not line.startswith(("usage:", " "))]
    assert len(message) == 1, err  # the usage, then one line
    assert message[0].startswith(f"python -m virtual_actuators demo: error: argument {option}: ")
    for text in expected:
        assert text in message[0], (text, message[0])
    assert "force_speed" not in message[0]  # the command line offers its own flag


def test_a_push_that_starts_with_a_minus_is_its_value():
    """``--push -10@1`` (argparse took ``-10@1`` for an option): 10 N the other way."""
    from virtual_actuators.cli.options import attach_values
    from virtual_actuators.gaits.push import Push

    parser, subparsers = cli.build_parser()
    words = ["demo", "legged", "--push", "-10@1", "--direction", "-90", "--yaw-rate", "-.5"]
    args = parser.parse_args(attach_values(words, [parser, *subparsers.values()]))
    assert args.push == Push(10.0, 1.0, 180.0) and args.direction == -90 and args.yaw_rate == -0.5
    assert attach_values(["demo", "--quiet", "-10@1"], [parser]) == ["demo", "--quiet", "-10@1"]
    assert Push.parse("-3@1:90") == Push(3.0, 1.0, 270.0)
