"""Sweeps: the grid, the range syntax, a 2-worker process-pool run, the table and the map."""

from __future__ import annotations

import argparse
import csv
import json

import numpy as np
import pytest

import virtual_actuators as va
from virtual_actuators.cli.types import value_range
from virtual_actuators.demos.sweep import (
    grid,
    plot_success_map,
    run_case,
    run_sweep,
    success_map,
    write_results,
)


def test_value_range():
    assert value_range("0.3:0.6:0.05") == pytest.approx([0.3, 0.35, 0.4, 0.45, 0.5, 0.55, 0.6])
    assert value_range("0.4,0.5") == [0.4, 0.5]
    assert value_range("0.5") == [0.5]
    for bad in ("a:b:c", "0.3:0.6:0", "0:1e6:1e-3", "", "nan"):
        with pytest.raises(argparse.ArgumentTypeError):
            value_range(bad)


def test_grid_and_errors():
    cases = grid("turkey-walk", [0.4, 0.5], ["flat", "rolling"], 3)
    assert len(cases) == 12 and {c.seed for c in cases} == {0, 1, 2}
    with pytest.raises(va.InvalidInputError, match="walk"):
        grid("moonwalk", [0.4], ["flat"], 1)
    with pytest.raises(va.InvalidInputError, match="seeds"):
        grid("turkey-walk", [0.4], ["flat"], 0)
    with pytest.raises(va.InvalidInputError, match="engine"):
        run_sweep(cases, engine="spark")


def test_seeds_change_the_start_and_runs_repeat():
    case = grid("turkey-walk", [0.5], ["flat"], 2, duration=1.0)
    first, again, other = run_case(case[0]), run_case(case[0]), run_case(case[1])
    assert (first.distance, first.steps, first.fell) == (again.distance, again.steps, again.fell)
    assert first.distance != other.distance  # another push
    assert not first.fell and first.fall_time != first.fall_time  # NaN: it did not fall


@pytest.mark.slow
def test_two_workers_table_and_map(tmp_path):
    cases = grid("turkey-walk", [0.4, 0.6], ["flat"], 2, duration=1.5)
    seen = []
    results = run_sweep(cases, workers=2, on_result=seen.append)
    assert len(seen) == len(results) == 4
    assert [(r.speed, r.seed) for r in results] == [(c.speed, c.seed) for c in cases]
    assert all(not r.error and r.distance > 0.2 for r in results)
    table = write_results(results, tmp_path / "sweep.csv")
    rows = list(csv.DictReader(table.open()))
    assert [float(row["speed"]) for row in rows] == [0.4, 0.4, 0.6, 0.6]
    data = json.loads(write_results(results, tmp_path / "sweep.json").read_text())
    assert len(data["results"]) == 4
    speeds, terrains, rate = success_map(results)
    assert speeds == [0.4, 0.6] and terrains == ["flat"]
    assert np.array_equal(rate, [[1.0, 1.0]])
    assert plot_success_map(results, tmp_path / "map.png").stat().st_size > 1000


def test_a_walk_that_crashes_is_recorded_not_raised(monkeypatch):
    from virtual_actuators.demos import sweep
    from virtual_actuators.gaits import registry

    def broken(*args, **kwargs):
        raise RuntimeError("a bug in a gait")

    monkeypatch.setattr(registry, "run_walk", broken)
    result = sweep.run_case(grid("turkey-walk", [0.5], ["flat"], 1)[0])
    assert result.fell and "RuntimeError: a bug in a gait" in result.error
    with pytest.raises(va.InvalidInputError, match="workers"):
        run_sweep(grid("turkey-walk", [0.5], ["flat"], 1), workers=2.5)


def test_the_hexapod_sweeps_like_the_bipeds(tmp_path, capsys):
    from virtual_actuators.__main__ import main

    out = tmp_path / "hexapod.json"
    arguments = ["sweep", "hexapod-walk", "--speed", "0.3", "--seeds", "1", "--duration", "0.5"]
    assert main([*arguments, "--workers", "1", "--quiet", "--out", str(out)]) == 0
    (row,) = json.loads(out.read_text())["results"]
    assert row["walk"] == "hexapod-walk" and row["speed"] == 0.3 and row["terrain"] == "flat"
    assert not row["fell"] and not row["error"] and row["steps"] >= 1
    assert 0.0 < row["distance"] < 0.3  # at most 0.3 m/s for 0.5 s
    assert "1 walks of hexapod-walk" in capsys.readouterr().out


def test_the_cli_names_every_registered_walk():
    from virtual_actuators.cli.options import WALK_DEMOS
    from virtual_actuators.demos import WALKS

    assert WALK_DEMOS == tuple(WALKS)


def test_the_cli_bounds_speeds_as_the_walks_do():
    from virtual_actuators.cli.types import MAX_SPEED
    from virtual_actuators.gaits.base import MAX_SPEED as WALKS_MAX_SPEED

    assert MAX_SPEED == WALKS_MAX_SPEED
