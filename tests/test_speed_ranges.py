"""Every walk's supported speed range: refused outside it (a usage error), walked at its ends.

The ranges are the registry's (``Walk.speed_range``), measured in closed-loop MuJoCo runs of each
walk's default duration; the runs here are shorter (a few simulated seconds), the same physics.
"""

from __future__ import annotations

import pytest

from virtual_actuators import InvalidInputError
from virtual_actuators.__main__ import main
from virtual_actuators.gaits.legged.patterns import PATTERNS
from virtual_actuators.gaits.legged.walk import LEGGED_SPEEDS, LeggedWalkConfig
from virtual_actuators.gaits.registry import WALKS, run_walk


def test_every_walk_with_a_speed_states_its_range():
    for name, walk in WALKS.items():
        supported = walk.speed_range()
        if name == "balance":
            assert supported is None  # it stands: no speed
            continue
        low, high = supported
        assert 0.0 < low < high <= 1.5, (name, supported)
    assert WALKS["legged"].speed_range(robot="go2") == (0.1, 1.5)
    assert WALKS["legged"].speed_range(robot="anymal_b") == WALKS["legged"].speed_range(
        robot="anymal"
    )  # an alias is its robot
    assert WALKS["legged"].speed_range(robot="my.urdf", gait="pace") == LEGGED_SPEEDS["pace"][None]
    hexapod = WALKS["hexapod-walk"]
    assert hexapod.speed_range(pendulum=True)[1] < hexapod.speed_range()[1]


def _option_sets(name):
    """Every set of options that selects a range of walk ``name`` (robots, gaits, payloads)."""
    if name == "legged":
        return [{"robot": robot, "gait": gait} for gait in PATTERNS
                for robot in [*(r for r in LEGGED_SPEEDS[gait] if r), "solo12", "my.urdf"]]
    if name == "hexapod-walk":
        return [{}, {"pendulum": True}, {"track": True}]
    return [{}]


@pytest.mark.parametrize("name", list(WALKS))
def test_every_default_speed_is_a_supported_one(name):
    """A run given no speed walks inside its range (issue 35: the legged walk ran 0.4 m/s)."""
    walk = WALKS[name]
    for options in _option_sets(name):
        default = walk.default_speed(**options)
        supported = walk.speed_range(**options)
        if supported is None:
            assert default == walk.nominal_speed or name == "balance", options
            continue
        low, high = supported
        assert low <= default <= high, (options, default, supported)
        walk.check_speed(default, **options)  # and the walk's own check agrees
    assert WALKS["legged"].default_speed(gait="walk") == 0.2  # 0.4 moved to its range's end
    assert WALKS["legged"].default_speed(robot="hexapod", gait="walk") == 0.3
    assert WALKS["legged"].default_speed() == 0.4  # inside: the gait's own
    assert WALKS["hexapod-walk"].default_speed(track=True) == 0.2
    assert LeggedWalkConfig(gait="walk").speed == 0.2 and LeggedWalkConfig().speed == 0.4


@pytest.mark.parametrize(
    ("name", "options", "expected"),
    [("legged", {"gait": "walk"}, 0.2), ("legged", {"robot": "hexapod", "gait": "walk"}, 0.3),
     ("hexapod-walk", {"pendulum": True}, 0.2), ("turkey-walk", {}, 0.5),
     ("flamingo-slopes", {}, 0.4)],
)
def test_a_run_given_no_speed_walks_at_the_default(name, options, expected):
    result = run_walk(name, duration=0.05, progress=False, **options)
    config = getattr(result, "config", None)
    speed = config.speed if config is not None else result.gait.bunny.speed
    assert speed == pytest.approx(expected)


def test_the_command_lines_walk_runs_at_a_supported_speed(capsys):
    assert main(["demo", "legged", "--gait", "walk", "--duration", "0.05", "--quiet"]) == 0
    assert "(set 0.20)" in capsys.readouterr().out


@pytest.mark.parametrize(
    ("name", "speed", "options", "expected"),
    [
        ("flamingo-slopes", 1.5, {}, "from 0.3 to 0.5 m/s, got 1.5"),
        ("flamingo-slopes", 0.2, {}, "from 0.3 to 0.5 m/s, got 0.2"),
        ("turkey-walk", 0.7, {}, "from 0.3 to 0.6 m/s"),
        ("legged", 1.0, {"robot": "solo12"}, "legged (robot 'solo12') walks at desired speeds "
                                              "from 0.1 to 0.8 m/s"),
        ("legged", 0.5, {"gait": "pace"}, "(gait 'pace')"),
        ("hexapod-walk", 0.6, {"pendulum": True}, "hexapod-walk (pendulum) walks"),
    ],
)
def test_run_walk_refuses_a_speed_outside_the_range(name, speed, options, expected):
    with pytest.raises(InvalidInputError, match="force_speed=True") as error:
        run_walk(name, speed=speed, progress=False, **options)
    assert expected in str(error.value)


def test_force_speed_runs_outside_the_range():
    result = run_walk("flamingo-slopes", speed=0.6, duration=0.05, progress=False,
                      force_speed=True)
    assert result.simulator.time >= 0.05 - 1e-9


@pytest.mark.parametrize(
    ("arguments", "expected"),
    [
        (["demo", "flamingo-slopes", "--speed", "1.5"], "from 0.3 to 0.5 m/s, got 1.5 m/s"),
        (["demo", "legged", "--robot", "go2", "--gait", "walk", "--speed", "0.5"],
         "(robot 'go2', gait 'walk') walks at desired speeds from 0.05 to 0.2 m/s"),
        (["demo", "turkey-walk", "--force-speed"], "--force-speed: it lets a --speed"),
    ],
)
def test_the_command_line_refuses_it_with_a_usage_error(arguments, expected, capsys):
    with pytest.raises(SystemExit) as exit_info:
        main(arguments)
    assert exit_info.value.code == 2
    err = capsys.readouterr().err
    assert "usage:" in err and expected in err and "Traceback" not in err


def test_the_command_line_runs_it_forced(capsys):
    code = main(["demo", "flamingo-slopes", "--speed", "0.6", "--force-speed", "--duration",
                 "0.05", "--quiet"])
    assert code == 0
    assert "set 0.60" in capsys.readouterr().out


def _ends():
    """(walk, speed, options, duration) at both ends of every range, short runs."""
    cases = []
    for name, options, duration in [
        ("turkey-walk", {}, 6.0),
        ("flamingo-slopes", {}, 8.0),
        ("hexapod-walk", {}, 3.0),
        ("hexapod-walk", {"pendulum": True}, 3.0),
        ("legged", {}, 3.0),
        ("legged", {"robot": "go2"}, 3.0),
        ("legged", {"gait": "pace"}, 3.0),
    ]:
        for speed in WALKS[name].speed_range(**options):
            cases.append(pytest.param(name, speed, options, duration,
                                      id=f"{name}-{speed}-{'-'.join(map(str, options.values()))}"))
    return cases


@pytest.mark.slow
@pytest.mark.parametrize(("name", "speed", "options", "duration"), _ends())
def test_the_range_ends_walk_without_falling(name, speed, options, duration):
    metrics = run_walk(name, speed=speed, duration=duration, progress=False, **options).metrics
    assert not metrics.fell, metrics.summary()
    mean = getattr(metrics, "mean_speed_mps", None) or metrics.speed_mps
    assert mean > 0.5 * speed, metrics.summary()  # it walks, at about the speed asked


@pytest.mark.parametrize("name", ["legged", "hexapod-walk", "turkey-walk"])
def test_the_speed_bound_is_absolute_and_says_why(name):
    """force_speed lifts a walk's range, not the 1.5 m/s bound of every walk (issue 35)."""
    with pytest.raises(InvalidInputError, match=r"1\.5 m/s bounds every walk") as error:
        run_walk(name, speed=2.0, force_speed=True, duration=0.05, progress=False)
    assert "force_speed does not lift it" in str(error.value)
    assert "go2's trot" in str(error.value)
