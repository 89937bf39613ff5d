"""The command line's small promises: a live viewer serves until stopped, a closed output pipe
ends nothing, a sweep says where its table goes, errors name the robot as typed, the help has
no markup. Each runs the command as a user does: in a subprocess, or through ``main(argv)``.
"""

from __future__ import annotations

import csv
import json
import os
import re
import select
import signal
import subprocess
import sys
import time
import urllib.request
from pathlib import Path

import pytest

import virtual_actuators as va
from virtual_actuators.__main__ import main
from virtual_actuators.cli.options import build_parser

pytestmark = pytest.mark.slow  # subprocesses and short walks

ROOT = Path(__file__).resolve().parents[1]


def start(arguments, **options):
    env = {**os.environ, "PYTHONPATH": str(ROOT), "PYTHONWARNINGS": "ignore"}
    return subprocess.Popen(
        [sys.executable, "-m", "virtual_actuators", *arguments], env=env, text=True,
        stdin=subprocess.DEVNULL, stderr=subprocess.PIPE, **options,
    )  # fmt: skip


def children(pid: int) -> list[int]:
    """The processes whose parent is ``pid`` (Linux's /proc)."""
    found = []
    for stat in Path("/proc").glob("[0-9]*/stat"):
        try:
            fields = stat.read_text().rsplit(")", 1)[1].split()
        except OSError:  # it ended meanwhile
            continue
        if int(fields[1]) == pid:
            found.append(int(stat.parent.name))
    return found


def alive(pid: int) -> bool:
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    return True


def answers(url: str) -> bool:
    try:
        with urllib.request.urlopen(url, timeout=5) as response:
            return response.status == 200
    except OSError:
        return False


WALK = ["demo", "legged", "--speed", "0.3", "--duration", "0.3", "--quiet"]


@pytest.mark.parametrize("arguments", [["example", "single-leg"], WALK], ids=["example", "walk"])
@pytest.mark.parametrize("stop", [signal.SIGINT, signal.SIGTERM], ids=["SIGINT", "SIGTERM"])
def test_viz_without_a_terminal_serves_until_interrupted(arguments, stop):
    pytest.importorskip("meshcat")
    process = start([*arguments, "--viz"], stdout=subprocess.PIPE)
    lines = []
    try:
        deadline = time.monotonic() + 120
        while time.monotonic() < deadline:
            line = process.stdout.readline()
            assert line, (lines, process.stderr.read())  # it must not end by itself
            lines.append(line)
            if line.startswith("viewer: serving"):
                break
        printed = "".join(lines)
        urls = re.findall(r"http://\S+", printed)
        assert len(urls) == 1, printed  # the URL once, when the viewer started
        assert "until interrupted" in lines[-1], lines[-1]
        time.sleep(2.0)  # still serving after the run, with nobody at a terminal
        assert process.poll() is None
        assert answers(urls[0])
        helpers = children(process.pid)  # the MeshCat server and its relay
        process.send_signal(stop)
        rest, errors = process.communicate(timeout=30)
    finally:
        if process.poll() is None:
            process.kill()
            process.communicate()
    assert process.returncode == 0, errors
    assert rest.strip().endswith("viewer: stopped") and "Traceback" not in errors, (rest, errors)
    if Path("/proc/self/stat").exists():
        assert len(helpers) >= 1 and not any(alive(pid) for pid in helpers)  # closed with it


def test_a_closed_output_pipe_ends_quietly_and_the_json_is_written(tmp_path):
    """``demo ... --json PATH | head -1``: the reader leaves before the first line is written."""
    report = tmp_path / "run.json"
    arguments = ["demo", "turkey-walk", "--duration", "0.3", "--quiet", "--json", str(report)]
    process = start(arguments, stdout=subprocess.PIPE)
    process.stdout.close()  # no reader any more: every write to the pipe fails (EPIPE)
    errors = process.stderr.read()
    assert process.wait(timeout=300) == 0, errors  # the walk's own exit code: it did not fall
    assert errors == "", errors  # no traceback, no "Broken pipe" blamed on --json
    assert json.loads(report.read_text())["fell"] is False


@pytest.mark.parametrize("arguments", [["robots"], ["--help"], ["example", "millipede"]])
def test_printing_into_a_closed_pipe_is_quiet(arguments):
    process = start(arguments, stdout=subprocess.PIPE)
    process.stdout.close()
    errors = process.stderr.read()
    assert process.wait(timeout=120) == 0 and errors == "", errors


SWEEP = ["sweep", "turkey-walk", "--speed", "0.4", "--seeds", "1", "--duration", "0.3"]
SWEEP += ["--workers", "1", "--quiet"]


def test_sweep_plot_writes_its_table_beside_the_plot(tmp_path, monkeypatch, capsys):
    here, there = tmp_path / "here", tmp_path / "there"
    here.mkdir(), there.mkdir()
    monkeypatch.chdir(here)
    assert main([*SWEEP, "--plot", str(there / "map.png")]) == 0
    assert list(here.iterdir()) == []  # nothing in the current folder
    assert sorted(p.name for p in there.iterdir()) == ["map.csv", "map.png"]
    rows = list(csv.DictReader((there / "map.csv").open()))
    assert [row["fell"] for row in rows] == ["False"]
    out = capsys.readouterr().out
    assert f"results: {there / 'map.csv'} (beside the plot" in out, out


def test_sweep_without_out_or_plot_writes_nothing(tmp_path, monkeypatch, capsys):
    monkeypatch.chdir(tmp_path)
    assert main(SWEEP) == 0
    assert list(tmp_path.iterdir()) == []
    assert "results: not written (--out" in capsys.readouterr().out


def test_sweep_table_beside_the_plot_is_tried_before_the_run(tmp_path, capsys):
    (tmp_path / "map.csv").mkdir()  # a folder where the table would go
    with pytest.raises(SystemExit) as exit_info:
        main([*SWEEP, "--plot", str(tmp_path / "map.png")])
    assert exit_info.value.code == 2
    captured = capsys.readouterr()
    assert "argument --plot: the results table beside it" in captured.err, captured.err
    assert "is a folder" in captured.err and captured.out == ""


@pytest.mark.parametrize(
    ("arguments", "typed", "model"),
    [
        (["demo", "stand", "--robot", "solo12", "--feet", "FL_foot,FR_FOOT,HL_FOOT"], "solo12",
         "solo"),
        (["demo", "stand", "--robot", "go2", "--feet", "FL_FOOT,FR_foot,RL_foot"], "go2",
         "go2_description"),
        (["demo", "legged", "--robot", "solo12", "--feet", "FL_foot,FR_FOOT,HL_FOOT,HR_FOOT",
          "--duration", "0.1", "--quiet"], "solo12", "solo"),
    ],
    ids=["stand solo12", "stand go2", "legged solo12"],
)  # fmt: skip
def test_errors_name_the_robot_as_typed(arguments, typed, model, capsys):
    with pytest.raises(SystemExit) as exit_info:
        main(arguments)
    assert exit_info.value.code == 2
    message = capsys.readouterr().err.strip().splitlines()[-1]
    assert "argument --feet:" in message and f"model {typed!r}" in message, message
    assert repr(model) not in message, message


def test_a_case_only_typo_is_suggested_first(capsys):
    with pytest.raises(SystemExit):
        main(["demo", "stand", "--robot", "solo12", "--feet", "FL_foot,FR_FOOT,HL_FOOT"])
    message = capsys.readouterr().err
    assert "The foot frame 'FL_foot'" in message and "Closest frames: 'FL_FOOT', " in message


def test_the_library_names_the_robot_as_loaded():
    robot = va.load_robot("go2")
    assert robot.name == robot.model.name == "go2"  # the URDF calls it go2_description
    with pytest.raises(va.FrameNotFoundError, match=r"'FL_FOOT' is not in the model 'go2'\."):
        va.ParallelVirtualActuator(robot, "base", ["FL_FOOT", "FR_foot"])


def test_help_has_no_markup():
    parser, subparsers = build_parser()
    for name, each in {"": parser, **subparsers}.items():
        text = each.format_help()
        assert "`" not in text and ":class:" not in text, (name, text)


def test_the_help_texts_in_the_docs_are_what_the_command_prints(monkeypatch):
    monkeypatch.setenv("COLUMNS", "80")
    parser, subparsers = build_parser()
    text = (ROOT / "docs" / "cli.md").read_text(encoding="utf-8")
    blocks = re.findall(r"```text\n(usage: python -m virtual_actuators.*?)\n```", text, re.S)
    shown = {}
    for block in blocks:
        name = block.split("python -m virtual_actuators", 1)[1].split()[0]
        shown[name if name in subparsers else ""] = block
    assert sorted(shown) == sorted(["", *subparsers])  # every command's help is shown
    for name, block in shown.items():
        assert block == subparsers.get(name, parser).format_help().rstrip("\n"), name


def test_viz_at_a_terminal_serves_until_enter():
    pytest.importorskip("meshcat")
    pty = pytest.importorskip("pty")
    terminal, side = pty.openpty()  # standard input is a terminal: a person is there
    env = {**os.environ, "PYTHONPATH": str(ROOT), "PYTHONWARNINGS": "ignore"}
    process = subprocess.Popen(
        [sys.executable, "-m", "virtual_actuators", "example", "single-leg", "--viz"],
        env=env, stdin=side, stdout=subprocess.PIPE, stderr=subprocess.PIPE,
    )  # fmt: skip
    os.close(side)
    printed = b""
    try:
        deadline = time.monotonic() + 120
        while b"Enter" not in printed:  # the prompt ends without a newline: read what comes
            assert time.monotonic() < deadline, printed
            if select.select([process.stdout], [], [], 1.0)[0]:
                chunk = os.read(process.stdout.fileno(), 4096)
                assert chunk, (printed, process.stderr.read())
                printed += chunk
        time.sleep(1.0)
        assert process.poll() is None  # waiting for Enter
        os.write(terminal, b"\n")
        rest, errors = process.communicate(timeout=30)
    finally:
        if process.poll() is None:
            process.kill()
            process.communicate()
        os.close(terminal)
    assert process.returncode == 0, errors
    text = (printed + rest).decode()
    assert len(re.findall(r"http://\S+", text)) == 1, text
    assert text.rstrip().endswith("viewer: stopped"), text
