"""Every closed loop is smooth at the tick rate.

Each walk runs `SECONDS` simulated seconds at 1 kHz; `effort_smoothness` measures every tick
after the first second (the walks' JSON figures): its efforts must not oscillate from one tick
to the next by more than `OSCILLATION_MAX` of any joint's effort limit (the 75th percentile over
the ticks: a persistent alternation, not a touchdown's step), and the base's angular rate must
not zigzag (`BASE_ALTERNATION_MAX` of the ticks at most). A 100 Hz trace cannot see either: it
samples every alternation at the same phase.

Every registered walk is here, the legged walk on solo12 (its default), go2, anymal, anymal_c,
hyq, two robots no other test walks (b1, go1), a legged manipulator whose arm the walker's
posture holds (anymal-kinova) and the hexapod's tripod, and the balance on its default robot
(Talos) and g1. Each case's run is shared by its two tests.
"""

import pytest

from virtual_actuators.gaits.registry import WALKS, run_walk

pytestmark = [pytest.mark.slow, pytest.mark.filterwarnings("ignore:Robot 'hyq'")]

SECONDS = 3.0  # [s] simulated, each
OSCILLATION_MAX = 0.005  # [-] of the effort limit, every joint
BASE_ALTERNATION_MAX = 0.01  # [-] of the ticks, every axis


def trot(robot: str, speed: float, gait: str = "trot") -> tuple[str, dict]:
    return "legged", {"robot": robot, "gait": gait, "speed": speed}


CASES = {
    "turkey-walk": ("turkey-walk", {}),
    "flamingo-slopes": ("flamingo-slopes", {}),
    "hexapod-walk": ("hexapod-walk", {}),
    "legged": ("legged", {}),  # solo12 trotting at 0.4 m/s
    "legged go2 trot 0.5": trot("go2", 0.5),
    "legged go2 trot 1.0": trot("go2", 1.0),
    "legged anymal trot 0.5": trot("anymal", 0.5),
    "legged anymal_c trot 0.5": trot("anymal_c", 0.5),
    "legged hyq trot 0.5": trot("hyq", 0.5),
    "legged b1 trot 0.5": trot("b1", 0.5),
    "legged go1 trot 0.5": trot("go1", 0.5),
    "legged hexapod tripod 0.3": trot("hexapod", 0.3, "tripod"),
    "legged anymal_kinova trot 0.5": trot("anymal_kinova", 0.5),
    "balance": ("balance", {}),  # Talos, the demo's default
    "balance g1": ("balance", {"robot": "g1"}),
}


class Runs(dict):
    """The walks run so far, by case (a short repr in a failure's report)."""

    def __repr__(self) -> str:
        return f"Runs({', '.join(self)})"


@pytest.fixture(scope="module")
def runs():
    """Each case run once, for both of its tests."""
    return Runs()


def measured(runs, case):
    if case not in runs:
        name, options = CASES[case]
        runs[case] = run_walk(name, duration=SECONDS, progress=False, **options)
    result = runs[case]
    smoothness = result.smoothness
    assert smoothness.ticks >= 1900, f"{case}: {smoothness.ticks} ticks measured (a fall?)"
    return result, smoothness


def test_every_registered_walk_is_here():
    assert {name for name, _ in CASES.values()} == set(WALKS)


@pytest.mark.parametrize("case", list(CASES))
def test_efforts_do_not_oscillate_at_the_tick_rate(runs, case):
    result, smoothness = measured(runs, case)
    worst = max(zip(smoothness.joint_oscillation, smoothness.joints, strict=True))
    assert worst[0] < OSCILLATION_MAX, f"{case}: {result.metrics.summary()}"
    assert smoothness.oscillation == worst[0] and smoothness.oscillation_joint == worst[1]


@pytest.mark.parametrize("case", list(CASES))
def test_the_base_rate_does_not_alternate(runs, case):
    result, smoothness = measured(runs, case)
    assert smoothness.rate_alternation < BASE_ALTERNATION_MAX, (
        f"{case}: p75 of the rate's second difference {smoothness.rate_oscillation_radps:.4f} "
        f"rad/s; {result.metrics.summary()}"
    )
